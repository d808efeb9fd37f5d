# cmake -DBUILD=<sanitizer build> -DCTEST=<ctest> [-DLABEL=<label>] -DSUPPRESSIONS=<lsan.supp>
#       -P run_sanitized.cmake
# Without LABEL: checks that BUILD is a sanitizer build and brings it up to date
# (sanitizers.build). With LABEL: runs that build's tests with the label under the
# sanitizers' options (sanitizers.unit, .insitu, .miniapp). docs/testing.md.
cmake_minimum_required(VERSION 3.16)
if(NOT EXISTS "${BUILD}/CMakeCache.txt" OR NOT EXISTS "${BUILD}/CTestTestfile.cmake")
  message(FATAL_ERROR "sanitizers: there is no sanitizer build in ${BUILD}. scripts/setup.sh --tests "
    "configures and builds it (cmake -S <source> -B ${BUILD} -DCMAKE_BUILD_TYPE=Release "
    "\"-DCANOPY_SANITIZE=address;undefined\" -DCANOPY_BUILD_BENCHMARKS=OFF, then cmake --build)")
endif()
file(STRINGS "${BUILD}/CMakeCache.txt" _sanitize REGEX "^CANOPY_SANITIZE:STRING=.+")
if(NOT _sanitize)
  message(FATAL_ERROR "sanitizers: ${BUILD} is not a sanitizer build (CANOPY_SANITIZE is empty)")
endif()

if(NOT DEFINED LABEL)
  # Up to date with the sources, so that the runs test the code as it is.
  execute_process(COMMAND ${CMAKE_COMMAND} --build "${BUILD}" --target canopy_sanitizer_tests -j 2
    RESULT_VARIABLE _result)
  if(NOT _result EQUAL 0)
    message(FATAL_ERROR "sanitizers: building ${BUILD} failed")
  endif()
  return()
endif()

# Stop at the first error (UBSan too: the build has -fno-sanitize-recover=undefined),
# with stack traces. Leaks are reported, except ParaView's and Python's own, which
# SUPPRESSIONS lists with the reason for each.
# intercept_tls_get_addr=0: GCC 12's LeakSanitizer records the blocks of dynamic
# thread-local storage through __tls_get_addr and, at exit, scans one with a bogus
# address in 4-rank in-situ runs under load ("DTLS 38 at 0x00000003771d-..." with
# verbosity=1, then "Tracer caught signal 11": 3 of 3 runs of
# insitu.mpi.np4_split_trees_moving_2d with two busy cores here, 0 of 3 with this).
# Not scanning dynamic TLS can only report more leaks, not fewer; none appeared.
set(ENV{ASAN_OPTIONS}
  "detect_leaks=1:check_initialization_order=1:halt_on_error=1:intercept_tls_get_addr=0")
set(ENV{LSAN_OPTIONS} "suppressions=${SUPPRESSIONS}:print_suppressions=0")
set(ENV{UBSAN_OPTIONS} "print_stacktrace=1:halt_on_error=1")
# Python's objects in malloc'd memory, which LeakSanitizer scans (its own arenas
# are mmap'd and not scanned): objects Python still references are not leaks,
# and no suppression has to name libpython (lsan.supp).
set(ENV{PYTHONMALLOC} "malloc")
# The output is kept and only what matters printed: a failing test's own output
# right after its name, not hidden among the passing ones (CI shows a window
# of the log around the first failure).
execute_process(
  COMMAND ${CTEST} --test-dir "${BUILD}" -L "^${LABEL}$" -j 2 --output-on-failure --no-tests=error
  RESULT_VARIABLE _result OUTPUT_VARIABLE _output ERROR_VARIABLE _output)
string(REGEX REPLACE "\n *Start +[0-9]+: [^\n]*" "" _output "${_output}")
string(REGEX REPLACE "\n *[0-9]+/[0-9]+ Test +#[0-9]+: [^\n]* Passed [^\n]*" "" _output "${_output}")
message("${_output}")
# LeakSanitizer's own tracer (the thread that stops the others to scan their
# memory) sometimes dies at exit on this platform ("Tracer caught signal 11",
# "LeakSanitizer has encountered a fatal error"; GCC 12, a few jobs in a thousand
# under load): a failure of the tool, not a finding. Those tests, and only those,
# run again, at most twice; any other failure stands (docs/testing.md).
include("${CMAKE_CURRENT_LIST_DIR}/ToolCrashes.cmake")
set(_attempt 0)
while(NOT _result EQUAL 0 AND _attempt LESS 2)
  canopy_sort_failures("${BUILD}/Testing/Temporary/LastTest.log" _rerun _other_failures)
  if(_other_failures OR NOT _rerun)
    break()
  endif()
  math(EXPR _attempt "${_attempt} + 1")
  list(JOIN _rerun "|" _names)
  string(REPLACE "." "\\." _names "${_names}")
  message("sanitizers: running ${_rerun} again (${_attempt} of 2): LeakSanitizer's tracer "
    "crashed in them, or in the fixture they need")
  execute_process(
    COMMAND ${CTEST} --test-dir "${BUILD}" -R "^(${_names})$" --output-on-failure
      --no-tests=error
    RESULT_VARIABLE _result)
endwhile()
if(NOT _result EQUAL 0)
  message(FATAL_ERROR "sanitizers: tests labelled '${LABEL}' failed in ${BUILD} (above: "
    "AddressSanitizer / UBSan / LeakSanitizer reports name the file and line)")
endif()
