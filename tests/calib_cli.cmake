# raystream-calib end to end: synthetic checkerboards calibrated back; one-line errors.
if(TARGET raystream-calib)
  add_test(NAME calib_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/calib_cli.sh
           $<TARGET_FILE:raystream-calib> ${CMAKE_CURRENT_BINARY_DIR}/calib_cli)
  set_tests_properties(calib_cli PROPERTIES TIMEOUT 120 ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1")
endif()
