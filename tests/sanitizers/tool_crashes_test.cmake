# cmake -P tool_crashes_test.cmake: canopy_sort_failures (ToolCrashes.cmake) on ctest
# logs whose outputs hold what broke the earlier line-by-line reading (CI, 2026-11-28:
# a tracer crash was not run again): a lone '[', a ';', a '\'.
cmake_minimum_required(VERSION 3.16)
include("${CMAKE_CURRENT_LIST_DIR}/ToolCrashes.cmake")
set(_log "${CMAKE_CURRENT_BINARY_DIR}/tool_crashes_test/LastTest.log")
set(_failed "${CMAKE_CURRENT_BINARY_DIR}/tool_crashes_test/LastTestsFailed.log")
file(REMOVE "${_failed}")
set(_failures 0)
function(expect what actual expected)
  if(NOT "${actual}" STREQUAL "${expected}")
    message(SEND_ERROR "${what}: '${actual}', expected '${expected}'")
  else()
    message(STATUS "ok: ${what}: '${actual}'")
  endif()
endfunction()

# One test's block as ctest writes it in LastTest.log.
function(log_block out number name output status)
  set(${out} "${${out}}${number}/9 Test: ${name}
Command: \"/usr/bin/mpiexec\" \"-np\" \"4\"
Directory: /build
\"${name}\" start time: Nov 28 20:00 UTC
Output:
----------------------------------------------------------
${output}
<end of output>
Test time =   1.00 sec
----------------------------------------------------------
Test ${status}.
\"${name}\" end time: Nov 28 20:00 UTC
\"${name}\" time elapsed: 00:00:01
----------------------------------------------------------

" PARENT_SCOPE)
endfunction()

set(_lsan_crash "step 1 executed ran 2 failures 0
closed
Tracer caught signal 11: addr=0x37730 pc=0x7fc3256e80f0 sp=0x7fc2f83ffd10
==8681==LeakSanitizer has encountered a fatal error.
==8681==HINT: LeakSanitizer does not work under ptrace (strace, gdb, etc)")
set(_awkward "#3 0x7f in vtkDataArray::operator[ (cut)
path C:\\dir\\ ; a semicolon; and \\")

set(_text "Start testing: Nov 28 20:00 UTC\n----------------------------------------------------------\n")
log_block(_text 1 unit.passes "fine" Passed)
log_block(_text 2 insitu.tracer_crash "${_awkward}\n${_lsan_crash}" Failed)
log_block(_text 3 insitu.real_failure "${_awkward}\n==1==ERROR: AddressSanitizer: heap-use-after-free" Failed)
log_block(_text 4 insitu.second_crash "${_lsan_crash}\n${_awkward}" Failed)
file(WRITE "${_log}" "${_text}")
canopy_sort_failures("${_log}" _crashed _other)
expect("tool crashes among three failures" "${_crashed}" "insitu.tracer_crash;insitu.second_crash")
expect("other failures among three failures" "${_other}" "insitu.real_failure")

set(_text "")
log_block(_text 1 insitu.only_crash "${_awkward}\n${_lsan_crash}" Failed)
log_block(_text 2 unit.passes "[" Passed)
file(WRITE "${_log}" "${_text}")
canopy_sort_failures("${_log}" _crashed _other)
expect("tool crashes alone" "${_crashed}" "insitu.only_crash")
expect("no other failure" "${_other}" "")

# A fixture's setup crashed: the test requiring it was not run, logged as passed,
# listed in LastTestsFailed.log. Both run again.
set(_text "")
log_block(_text 1 insitu.setup_crash "${_lsan_crash}" Failed)
log_block(_text 2 insitu.needs_the_setup "" Passed)
log_block(_text 3 unit.passes "fine" Passed)
file(WRITE "${_log}" "${_text}")
file(WRITE "${_failed}" "1:insitu.setup_crash\n2:insitu.needs_the_setup\n")
canopy_sort_failures("${_log}" _crashed _other)
expect("a crashed setup and the test not run" "${_crashed}"
  "insitu.setup_crash;insitu.needs_the_setup")
expect("no other failure with a setup crash" "${_other}" "")
# A setup that really failed: the test not run is not run again either.
set(_text "")
log_block(_text 1 insitu.setup_fails "==1==ERROR: AddressSanitizer: heap-use-after-free" Failed)
log_block(_text 2 insitu.needs_the_setup "" Passed)
file(WRITE "${_log}" "${_text}")
file(WRITE "${_failed}" "1:insitu.setup_fails\n2:insitu.needs_the_setup\n")
canopy_sort_failures("${_log}" _crashed _other)
expect("a failed setup" "${_other}" "insitu.setup_fails")
