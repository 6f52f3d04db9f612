# raystream-glbench end to end: the three kernel chains by name, per-kernel times named in
# the output, bad options refused in one line. Skipped (exit 77) without an EGL context.
if(TARGET raystream-glbench)
  add_test(NAME glbench_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/glbench_cli.sh
           $<TARGET_FILE:raystream-glbench> ${CMAKE_CURRENT_BINARY_DIR}/glbench_cli)
  set_tests_properties(glbench_cli PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77
    ENVIRONMENT "RS_DATA_DIR=${RS_DATA_DIR};ASAN_OPTIONS=detect_leaks=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp")
endif()
