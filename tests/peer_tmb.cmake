# raystream-peer-tmb (the three-mesh-bvh peer harness) on a one-leaf BVH fixture with a
# brute-force GLSL stand-in for the package's chunks, and tools/peer-three-mesh-bvh.sh
# refusing cleanly when npm cannot install the package: no network. Skipped (exit 77)
# without an EGL context.
if(TARGET raystream-peer-tmb)
  add_test(NAME peer_tmb_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/peer_tmb_cli.sh
           $<TARGET_FILE:raystream-peer-tmb> ${CMAKE_CURRENT_BINARY_DIR}/peer_tmb_cli
           ${PROJECT_SOURCE_DIR}/tools/peer-three-mesh-bvh.sh ${CMAKE_BINARY_DIR})
  set_tests_properties(peer_tmb_cli PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77
    ENVIRONMENT "RS_DATA_DIR=${RS_DATA_DIR};ASAN_OPTIONS=detect_leaks=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp")
endif()
