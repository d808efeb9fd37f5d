# canopy_sort_failures(<LastTest.log> <rerun var> <other var>)
#
# Reads a ctest log and sorts its failed tests in two lists. To run again: those
# whose output shows LeakSanitizer's own tracer dying ("LeakSanitizer has
# encountered a fatal error", a failure of the tool, not a finding;
# docs/testing.md), and those not run because a fixture they require failed
# (ctest logs them as passed; LastTestsFailed.log, beside the log, lists them).
# Other: every other failure. run_sanitized.cmake runs the first list again when
# the second is empty; tests/sanitizers/tool_crashes_test.cmake checks this on
# logs with the characters below. Needs policy CMP0057 (if IN_LIST): a script
# including it begins with cmake_minimum_required(VERSION 3.16).
#
# The log is a test's raw output, so it is read as one string and never as a
# CMake list of lines straight away: a lone '[' (a stack trace's "operator[",
# a cut line) would join every following line into one list element up to the
# next ']', and a ';' or a '\' would split or escape lines. Those characters are
# replaced before the log is cut into lines; the lines are only matched.
function(canopy_sort_failures log tool_crashed_var other_var)
  file(READ "${log}" _text)
  string(REPLACE "\\" "/" _text "${_text}")
  string(REPLACE ";" "," _text "${_text}")
  string(REPLACE "[" "(" _text "${_text}")
  string(REPLACE "]" ")" _text "${_text}")
  string(REPLACE "\r" "" _text "${_text}")
  string(REPLACE "\n" ";" _lines "${_text}")
  set(_current "")
  set(_crashed FALSE)
  set(_tool_crashed "")
  set(_other "")
  foreach(_line IN LISTS _lines)
    if(_line MATCHES "^[0-9]+/[0-9]+ Test: (.+)$")
      set(_current "${CMAKE_MATCH_1}")
      set(_crashed FALSE)
    elseif(_line MATCHES "LeakSanitizer has encountered a fatal error")
      set(_crashed TRUE)
    elseif(_line MATCHES "^Test Failed")
      if(_crashed)
        list(APPEND _tool_crashed "${_current}")
      else()
        list(APPEND _other "${_current}")
      endif()
    endif()
  endforeach()
  # Listed as failed without a failure in the log: not run (a fixture failed).
  get_filename_component(_dir "${log}" DIRECTORY)
  if(EXISTS "${_dir}/LastTestsFailed.log")
    file(STRINGS "${_dir}/LastTestsFailed.log" _failed_lines)
    foreach(_line IN LISTS _failed_lines)
      if(_line MATCHES "^[0-9]+:(.+)$")
        set(_name "${CMAKE_MATCH_1}")
        if(NOT _name IN_LIST _tool_crashed AND NOT _name IN_LIST _other)
          list(APPEND _tool_crashed "${_name}")
        endif()
      endif()
    endforeach()
  endif()
  set(${tool_crashed_var} "${_tool_crashed}" PARENT_SCOPE)
  set(${other_var} "${_other}" PARENT_SCOPE)
endfunction()
