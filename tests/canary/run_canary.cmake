# A fifth method from its own files plus one list entry (issue "A method is one
# type"): copies the repository into WORK, adds the canary's room
# (tests/canary/room) as macros/methods/canary/, appends "canary" to the one
# list (methods/CMakeLists.txt, TRUEAXIS_ALL_METHODS) and checks that
# this is the only line of the repository that changed; then builds the copy's
# map generator and tests/canary/canary_check.cpp and runs both.
#
#   cmake -DSOURCE=<repository> -DWORK=<scratch dir> -DPYTHON=python3 -P run_canary.cmake
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/src)
file(GLOB entries RELATIVE ${SOURCE} ${SOURCE}/* ${SOURCE}/.[a-z]*)
foreach(entry IN LISTS entries)
  if(NOT entry MATCHES "^(build.*|\\.git)$")
    file(COPY ${SOURCE}/${entry} DESTINATION ${WORK}/src)
  endif()
endforeach()

# The method's own files.
file(COPY ${SOURCE}/tests/canary/room/ DESTINATION ${WORK}/src/methods/canary)

# The one list entry.
set(list_file methods/CMakeLists.txt)
file(STRINGS ${SOURCE}/${list_file} before)
file(READ ${SOURCE}/${list_file} text)
string(REGEX REPLACE "set\\(TRUEAXIS_ALL_METHODS ([a-z ]+)\\)" "set(TRUEAXIS_ALL_METHODS \\1 canary)" text "${text}")
file(WRITE ${WORK}/src/${list_file} "${text}")
file(STRINGS ${WORK}/src/${list_file} after)
list(LENGTH before n_before)
list(LENGTH after n_after)
set(changed 0)
if(n_before EQUAL n_after)
  math(EXPR last "${n_before} - 1")
  foreach(i RANGE ${last})
    list(GET before ${i} a)
    list(GET after ${i} b)
    if(NOT a STREQUAL b)
      math(EXPR changed "${changed} + 1")
    endif()
  endforeach()
endif()
if(NOT n_before EQUAL n_after OR NOT changed EQUAL 1)
  message(FATAL_ERROR "canary: adding the method changed ${changed} line(s) of ${list_file}, not one")
endif()
message(STATUS "canary: one line of one existing file (${list_file}) changed; the room is new")

# Unoptimised and without debug information (a build type with no flags of its
# own): the checks are of behaviour, and this is the least time to build the copy.
execute_process(COMMAND ${CMAKE_COMMAND} -S ${WORK}/src -B ${WORK}/build -G Ninja -DCMAKE_BUILD_TYPE=None
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "canary: the copy with the canary does not configure")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK}/build --target trueaxis-map canary_check portable_tests trueaxis-calibrate trueaxis-sim
                        trueaxis-var
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "canary: the copy with the canary does not build:\n${out}")
endif()
execute_process(COMMAND ${WORK}/build/bin/canary_check RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "canary: the module does not hold the canary")
endif()
execute_process(COMMAND ${WORK}/build/bin/trueaxis-map --json OUTPUT_FILE ${WORK}/map.json RESULT_VARIABLE rc)
execute_process(COMMAND ${PYTHON} ${SOURCE}/tests/canary/check_canary_map.py ${WORK}/map.json
                        ${SOURCE}/macros/register_map.json RESULT_VARIABLE rc2)
if(NOT rc EQUAL 0 OR NOT rc2 EQUAL 0)
  message(FATAL_ERROR "canary: the JSON map does not hold the canary")
endif()
execute_process(COMMAND ${WORK}/build/bin/portable_tests RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "canary: the portable tests fail with the canary:\n${out}")
endif()
execute_process(COMMAND ${PYTHON} ${SOURCE}/tests/canary/check_canary_flow.py ${WORK}/build/bin ${WORK}/flow
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "canary: trueaxis-calibrate does not hold the canary:\n${out}")
endif()
message(STATUS "canary: module, map, portable tests, calibrate flow, store, report and plan hold the canary")
