# raystream-bench --table 2 end to end on a tiny image: every row present, refusals shown as
# such, the peer's image equal to the reference when the peer is built; bad input in one line.
if(TARGET raystream-bench)
  add_test(NAME bench_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/bench_cli.sh
           $<TARGET_FILE:raystream-bench> ${CMAKE_CURRENT_BINARY_DIR}/bench_cli)
  set_tests_properties(bench_cli PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77
    ENVIRONMENT "RS_DATA_DIR=${RS_DATA_DIR};ASAN_OPTIONS=detect_leaks=1")
endif()
