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

# Stack analysis (tools/stack_report.py, tests/target: stack_report, stack_bounds):
# gcc writes each firmware library object's stack usage (.su) and call graph
# with every function's frame (.ci, -fcallgraph-info=su) beside the object, so
# the analysis needs no build of its own. Neither option changes the generated
# code: the images are byte for byte the same with and without (checked with
# gcc 12.2 on firmware_target, bench_level_target, bench_gantry_target). GCC
# only; on by default in the cross build.
if(CMAKE_CROSSCOMPILING AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  set(trueaxis_stack_info_default ON)
else()
  set(trueaxis_stack_info_default OFF)
endif()
option(TRUEAXIS_STACK_INFO "Write gcc's stack usage and call graph (.su, .ci) of the firmware libraries"
       ${trueaxis_stack_info_default})
if(TRUEAXIS_STACK_INFO AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  message(FATAL_ERROR "TRUEAXIS_STACK_INFO needs GCC (-fcallgraph-info); turn it off for ${CMAKE_CXX_COMPILER_ID}")
endif()

# trueaxis_firmware(target): a firmware-side library: strict, no exceptions, no
# RTTI; a static library also gets the stack information (TRUEAXIS_STACK_INFO).
function(trueaxis_firmware target)
  trueaxis_strict(${target})
  target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti>)
  get_target_property(type ${target} TYPE)
  if(TRUEAXIS_STACK_INFO AND type STREQUAL "STATIC_LIBRARY")
    target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:C,CXX>:-fstack-usage -fcallgraph-info=su>)
    # ccache (4.7) restores the object and the .su of a cache hit but not the
    # .ci: these objects are compiled without it (stack_report.py would refuse
    # an object without its call graph).
    set_target_properties(${target} PROPERTIES CXX_COMPILER_LAUNCHER "" C_COMPILER_LAUNCHER "")
  endif()
endfunction()
