# raystream-server against a degenerate camera, 64 idle pre-HELLO connections and a stalled
# viewer (issue 17): each case failed on aa4a7f7. Loopback only.
if(TARGET raystream-server)
  add_executable(server_guard ${CMAKE_CURRENT_SOURCE_DIR}/server_guard.c)
  target_link_libraries(server_guard PRIVATE raystream)
  add_test(NAME server_guard COMMAND server_guard $<TARGET_FILE:raystream-server>
           ${CMAKE_CURRENT_BINARY_DIR} camera greet stall stall-plain)
  set_tests_properties(server_guard PROPERTIES TIMEOUT 120
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1")
endif()
