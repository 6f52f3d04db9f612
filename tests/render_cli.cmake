# raystream-render end to end: good runs write complete outputs; bad input fails in one line.
if(TARGET raystream-render)
  add_test(NAME render_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/render_cli.sh
           $<TARGET_FILE:raystream-render> ${CMAKE_CURRENT_BINARY_DIR}/render_cli)
  set_tests_properties(render_cli PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77
    ENVIRONMENT "RS_DATA_DIR=${RS_DATA_DIR};ASAN_OPTIONS=detect_leaks=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp")
endif()
