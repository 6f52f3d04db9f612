# raystream-streambench on a tiny sequence: the link it emulates stated, progress, a row per
# encoding, defaults in --help, bad values named with their range.
if(TARGET raystream-streambench)
  add_test(NAME streambench_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/streambench_cli.sh
           $<TARGET_FILE:raystream-streambench> ${CMAKE_CURRENT_BINARY_DIR}/streambench_cli)
  set_tests_properties(streambench_cli PROPERTIES TIMEOUT 300
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp")
endif()
