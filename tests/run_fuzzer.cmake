# @brief Runs one libFuzzer target on a fresh corpus seeded from SEEDS (";"-list of files).
# In `make test` (CI) the run is deterministic: a fixed seed and a fixed number of inputs (RUNS), so CI explores the
# same inputs a developer's run did and cannot fail on a crash nobody has seen; SECONDS only caps a slow machine
# (a capped run is a prefix of the same sequence). To hunt for new bugs, set FV_FUZZ_SECONDS=N: a random seed and
# N seconds, no run limit (e.g. `FV_FUZZ_SECONDS=300 ctest -L fuzz`).
file(REMOVE_RECURSE ${CORPUS})
file(MAKE_DIRECTORY ${CORPUS})
foreach(s ${SEEDS})
  if(EXISTS ${s})
    get_filename_component(n ${s} NAME)
    file(COPY_FILE ${s} ${CORPUS}/seed_${n})
  endif()
endforeach()
if(DEFINED ENV{FV_FUZZ_SECONDS})
  set(limits -seed=0 -max_total_time=$ENV{FV_FUZZ_SECONDS})
else()
  set(limits -seed=1 -runs=${RUNS} -max_total_time=${SECONDS})
endif()
get_filename_component(workdir ${CORPUS} DIRECTORY)
execute_process(
  COMMAND ${FUZZER} ${limits} -rss_limit_mb=1024 -malloc_limit_mb=512 -timeout=10
          -max_len=65536 -print_final_stats=1 -artifact_prefix=${workdir}/ ${CORPUS}
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fuzzer ${FUZZER} failed (exit ${rc}); the input that failed is in ${workdir}/crash-* "
                      "(or leak-*/timeout-*/oom-*); replay it with: ${FUZZER} FILE")
endif()
