# @brief Runs one libFuzzer target for a bounded time on a fresh corpus seeded from SEEDS (";"-list of files).
file(REMOVE_RECURSE ${CORPUS})
file(MAKE_DIRECTORY ${CORPUS})
foreach(s ${SEEDS})
  if(EXISTS ${s})
    get_filename_component(n ${s} NAME)
    file(COPY_FILE ${s} ${CORPUS}/seed_${n})
  endif()
endforeach()
execute_process(
  COMMAND ${FUZZER} -max_total_time=${SECONDS} -rss_limit_mb=1024 -malloc_limit_mb=512 -timeout=10
          -max_len=65536 -print_final_stats=1 ${CORPUS}
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fuzzer ${FUZZER} failed (exit ${rc})")
endif()
