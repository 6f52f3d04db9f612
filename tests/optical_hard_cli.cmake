# raystream-optsynth --hard sequences tracked by raystream-track: worst error/stated <= 5,
# every unsolved frame with a reason (issue 19).
if(TARGET raystream-optsynth AND TARGET raystream-track)
  add_test(NAME optical_hard_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/optical_hard_cli.sh
           $<TARGET_FILE:raystream-optsynth> $<TARGET_FILE:raystream-track>
           ${CMAKE_CURRENT_BINARY_DIR}/optical_hard_cli)
  set_tests_properties(optical_hard_cli PROPERTIES TIMEOUT 300 ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1")
endif()
