# raystream-bench --times (was raystream-glbench) end to end: the three kernel chains by
# name, per-kernel times named in the output and in --json. Skipped (exit 77) without an
# EGL context.
if(TARGET raystream-bench)
  add_test(NAME bench_times_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/bench_times_cli.sh
           $<TARGET_FILE:raystream-bench> ${CMAKE_CURRENT_BINARY_DIR}/bench_times_cli)
  set_tests_properties(bench_times_cli PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77
    ENVIRONMENT "RS_DATA_DIR=${RS_DATA_DIR};ASAN_OPTIONS=detect_leaks=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp")
endif()
