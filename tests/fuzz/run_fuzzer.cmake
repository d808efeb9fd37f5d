# cmake -DFUZZER=<canopy_*_fuzzer> -DWORK=<scratch dir> -DCORPUS=<seed corpus>
#       -DRUNS=<inputs> -DSEED=<seed> -P run_fuzzer.cmake
# Runs the fuzzer for RUNS inputs from SEED, starting from CORPUS. New inputs go to
# WORK/new (never into the committed corpus); a crashing input to WORK/crash-*.
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/new")
execute_process(
  COMMAND "${FUZZER}" -runs=${RUNS} -seed=${SEED} -max_len=2048 -timeout=60
    -rss_limit_mb=4096 -print_final_stats=1 "-artifact_prefix=${WORK}/" "${WORK}/new" "${CORPUS}"
  RESULT_VARIABLE _result)
if(NOT _result EQUAL 0)
  file(GLOB _artifacts "${WORK}/crash-*" "${WORK}/leak-*" "${WORK}/timeout-*" "${WORK}/oom-*")
  message(FATAL_ERROR "fuzz: the fuzzer found a problem (exit ${_result}); the input: "
    "${_artifacts}. Reproduce with ${FUZZER} <input>; once fixed, add the input to "
    "${CORPUS} as regression_<what>.")
endif()
