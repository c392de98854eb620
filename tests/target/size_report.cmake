# cmake -DSIZE=arm-none-eabi-size -DNM=arm-none-eabi-nm -DSETS="name:image:module_ram_bound:flash_bound|..."
#       -P size_report.cmake
# Prints, per method set's firmware image (tests/target/firmware_main.cpp):
#   flash  = text + data;
#   RAM    = data + bss, which counts the 64 KiB stack reservation and the 32 KiB
#            NV RAM as bss;
#   module = the size of the module object main owns (its static `module`), the
#            RAM an integrator gives the module besides his stack and storage.
# Fails (FATAL_ERROR) when the module's RAM or the flash exceeds its bound
# (0: none).
# over(value_var bound what): notes in `verdict` whether ${value_var} is within
# `bound` bytes (0: no target), and the set in `failed` when it is not.
macro(over value_var bound what)
  if(${bound} GREATER 0)
    math(EXPR bound_kib "${bound} / 1024")
    if(${${value_var}} GREATER ${bound})
      string(APPEND verdict "  OVER the ${what} target of ${bound_kib} KiB")
      list(APPEND failed ${name})
    else()
      string(APPEND verdict "  (${what} target <= ${bound_kib} KiB)")
    endif()
  endif()
endmacro()

set(failed "")
string(REPLACE "|" ";" SETS "${SETS}")
foreach(entry IN LISTS SETS)
  string(REPLACE ":" ";" fields "${entry}")
  list(GET fields 0 name)
  list(GET fields 1 image)
  list(GET fields 2 ram_bound)
  list(GET fields 3 flash_bound)
  execute_process(COMMAND ${SIZE} -B ${image} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "size failed on ${image}")
  endif()
  string(REGEX MATCH "\n *([0-9]+)[ \t]+([0-9]+)[ \t]+([0-9]+)" _ "${out}")
  math(EXPR flash "${CMAKE_MATCH_1} + ${CMAKE_MATCH_2}")
  math(EXPR ram "${CMAKE_MATCH_2} + ${CMAKE_MATCH_3}")
  execute_process(COMMAND ${NM} -S ${image} OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
  string(REGEX MATCH "[0-9a-f]+ ([0-9a-f]+) [bBdD] _ZZ4mainE6module\n" _ "${symbols}")
  if(NOT rc EQUAL 0 OR NOT CMAKE_MATCH_1)
    message(FATAL_ERROR "${image}: no static `module` in main (tests/target/firmware_main.cpp)")
  endif()
  math(EXPR module "0x${CMAKE_MATCH_1}")
  math(EXPR module_kib "${module} * 10 / 1024")
  string(REGEX REPLACE "([0-9])$" ".\\1" module_kib "${module_kib}")
  set(verdict "")
  over(module ${ram_bound} "module RAM")
  over(flash ${flash_bound} "flash")
  message("${name}: module RAM ${module} B (${module_kib} KiB); image flash ${flash} B, RAM ${ram} B${verdict}")
endforeach()
if(failed)
  message(FATAL_ERROR "over a size target: ${failed}")
endif()
