# raystream-track end to end: sim, record/replay round trip, stop conditions, and one-line
# errors with a non-zero exit for bad input.
if(TARGET raystream-track)
  add_test(NAME track_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/track_cli.sh
           $<TARGET_FILE:raystream-track> ${CMAKE_CURRENT_BINARY_DIR}/track_cli)
  set_tests_properties(track_cli PROPERTIES TIMEOUT 600
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1")
endif()
