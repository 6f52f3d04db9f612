# tools/check-skips.sh, the CI gate that fails a run in which a GL test was skipped, can fail.
add_test(NAME check_skips COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_skips.sh
         ${PROJECT_SOURCE_DIR}/tools/check-skips.sh ${CMAKE_CURRENT_BINARY_DIR}/check_skips)
set_tests_properties(check_skips PROPERTIES TIMEOUT 60)
