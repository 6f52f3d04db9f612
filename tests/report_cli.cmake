# raystream-report end to end on tiny sizes (cpu, and egl on llvmpipe when built): every
# number present, the reference setting's error against itself zero, a readable PNG plot.
if(TARGET raystream-report)
  add_test(NAME report_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/report_cli.sh
           $<TARGET_FILE:raystream-report> ${CMAKE_CURRENT_BINARY_DIR}/report_cli)
  set_tests_properties(report_cli PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77
    ENVIRONMENT "RS_DATA_DIR=${RS_DATA_DIR};ASAN_OPTIONS=detect_leaks=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp")
endif()
