# raystream-optsynth frames tracked by raystream-track through video:; one-line errors.
if(TARGET raystream-optsynth AND TARGET raystream-track)
  add_test(NAME optical_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/optical_cli.sh
           $<TARGET_FILE:raystream-optsynth> $<TARGET_FILE:raystream-track>
           ${CMAKE_CURRENT_BINARY_DIR}/optical_cli)
  set_tests_properties(optical_cli PROPERTIES TIMEOUT 120 ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1")
endif()
