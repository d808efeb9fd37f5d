# canopy_sort_failures(<LastTest.log> <tool-crashed var> <other var>)
#
# Reads a ctest log and sorts its failed tests in two lists: those whose output
# shows LeakSanitizer's own tracer dying ("LeakSanitizer has encountered a fatal
# error", a failure of the tool, not a finding; docs/testing.md) and every other
# failure. run_sanitized.cmake runs the first kind again; tests/sanitizers/
# tool_crashes_test.cmake checks this on a log with the characters below.
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
  set(${tool_crashed_var} "${_tool_crashed}" PARENT_SCOPE)
  set(${other_var} "${_other}" PARENT_SCOPE)
endfunction()
