# cmake -DSIZE=arm-none-eabi-size -DIMAGES="a.elf;b.elf" -P size_report.cmake
# Prints, per image, flash = text + data and RAM = data + bss (Berkeley format).
# RAM counts the 64 KiB stack reservation and the 4 KiB NV RAM as bss.
foreach(image IN LISTS IMAGES)
  execute_process(COMMAND ${SIZE} -B ${image} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "size failed on ${image}")
  endif()
  string(REGEX MATCH "\n *([0-9]+)[ \t]+([0-9]+)[ \t]+([0-9]+)" _ "${out}")
  math(EXPR flash "${CMAKE_MATCH_1} + ${CMAKE_MATCH_2}")
  math(EXPR ram "${CMAKE_MATCH_2} + ${CMAKE_MATCH_3}")
  get_filename_component(name ${image} NAME)
  message("${name}: flash ${flash} B (text ${CMAKE_MATCH_1} + data ${CMAKE_MATCH_2}), "
          "RAM ${ram} B (data ${CMAKE_MATCH_2} + bss ${CMAKE_MATCH_3})")
endforeach()
