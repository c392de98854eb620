# Shared build settings: Eigen as a system include, the strict warning set
# (held at zero by -Werror), and the firmware-side flags.

if(CMAKE_CROSSCOMPILING)
  find_path(TRUEAXIS_EIGEN_DIR Eigen/Core PATHS /usr/include/eigen3 NO_CMAKE_FIND_ROOT_PATH REQUIRED)
  add_library(trueaxis_eigen INTERFACE)
  target_include_directories(trueaxis_eigen SYSTEM INTERFACE ${TRUEAXIS_EIGEN_DIR})
else()
  find_package(Eigen3 3.4 REQUIRED NO_MODULE)
  add_library(trueaxis_eigen INTERFACE)
  target_link_libraries(trueaxis_eigen INTERFACE Eigen3::Eigen)
endif()
# Every user of Eigen in this project sees the same configuration (one ODR).
target_compile_definitions(trueaxis_eigen INTERFACE EIGEN_NO_MALLOC EIGEN_NO_IO)
if(CMAKE_CROSSCOMPILING)
  # Eigen's internal asserts would pull newlib's printf (and its heap) into the image.
  target_compile_definitions(trueaxis_eigen INTERFACE EIGEN_NO_DEBUG)
endif()

# Warnings are errors in the project's own builds and CI; an integrator who
# builds firmware_core and macros with another compiler turns it off.
option(TRUEAXIS_WERROR "Treat the project's warnings as errors" ON)

set(TRUEAXIS_WARNINGS
  -Wall -Wextra -Wpedantic
  -Wshadow -Wconversion -Wsign-conversion -Wdouble-promotion
  -Wold-style-cast -Wcast-align -Wnon-virtual-dtor -Woverloaded-virtual
  -Wnull-dereference -Wformat=2 -Wimplicit-fallthrough -Wmissing-declarations)
if(TRUEAXIS_WERROR)
  list(APPEND TRUEAXIS_WARNINGS -Werror)
endif()

# trueaxis_strict(target): the warning set, for every target of the project.
function(trueaxis_strict target)
  target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:CXX>:${TRUEAXIS_WARNINGS}>)
endfunction()

# trueaxis_firmware(target): a firmware-side library: strict, no exceptions, no RTTI.
function(trueaxis_firmware target)
  trueaxis_strict(${target})
  target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti>)
endfunction()
