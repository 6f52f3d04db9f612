# Issue 18 as a newcomer meets raystream-render and raystream-scene (tests/newcomer_cli.sh).
if(TARGET raystream-render AND TARGET raystream-scene)
  add_test(NAME newcomer_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/newcomer_cli.sh
           $<TARGET_FILE:raystream-render> ${CMAKE_CURRENT_BINARY_DIR}/newcomer_cli
           $<TARGET_FILE:raystream-scene>)
  set_tests_properties(newcomer_cli PROPERTIES TIMEOUT 600
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp")
endif()
