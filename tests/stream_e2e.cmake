# raystream-server + raystream-viewer end to end on loopback: frames match a local render,
# pose ids round-trip, latency and fps are reported; bad clients (garbage, truncated,
# oversized, slow drip, no HELLO, wrong token, NaN pose, wrong size, abrupt close, a
# viewer that never reads) while 8 good viewers keep receiving their own frames in order.
if(TARGET raystream-server AND TARGET raystream-viewer)
  add_test(NAME stream_e2e COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/stream_e2e.sh
           $<TARGET_FILE:raystream-server> ${CMAKE_CURRENT_BINARY_DIR}/stream_e2e
           $<TARGET_FILE:raystream-viewer>)
  set_tests_properties(stream_e2e PROPERTIES TIMEOUT 180 SKIP_RETURN_CODE 77
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1")
endif()
