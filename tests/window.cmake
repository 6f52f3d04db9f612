# The viewer's real window under Xvfb: a screenshot (xwd) of the window must equal the
# frame the viewer last received. Skipped (exit 77) when Xvfb or xwd is missing;
# tools/deps.sh installs both, so CI runs it.
if(TARGET rs_window AND TARGET raystream-viewer AND TARGET raystream-server)
  add_executable(xwd_compare xwd_compare.c)
  target_link_libraries(xwd_compare PRIVATE rs_image m)
  add_test(NAME viewer_window_xvfb COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/window_xvfb.sh
           $<TARGET_FILE:raystream-viewer> ${CMAKE_CURRENT_BINARY_DIR}/window_xvfb
           $<TARGET_FILE:raystream-server> $<TARGET_FILE:xwd_compare>)
  set_tests_properties(viewer_window_xvfb PROPERTIES TIMEOUT 120 SKIP_RETURN_CODE 77
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
endif()

# Every way the viewer shows a frame (local egl straight into the window, egl read back,
# osmesa, cpu, remote) against the CPU reference of the same camera (issue 17).
if(TARGET rs_window AND TARGET raystream-viewer AND TARGET raystream-server AND
   TARGET raystream-render)
  add_test(NAME viewer_window_local_xvfb
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/window_local_xvfb.sh
           $<TARGET_FILE:raystream-viewer> ${CMAKE_CURRENT_BINARY_DIR}/window_local_xvfb
           $<TARGET_FILE:raystream-server> $<TARGET_FILE:xwd_compare>
           $<TARGET_FILE:raystream-render>)
  set_tests_properties(viewer_window_local_xvfb PROPERTIES TIMEOUT 300 SKIP_RETURN_CODE 77
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
endif()

# The viewer on its own backend without a window (--local --headless): egl, osmesa and cpu
# frames against the CPU reference (no Xvfb needed).
if(TARGET raystream-viewer AND TARGET raystream-render AND TARGET xwd_compare)
  add_test(NAME viewer_headless_local
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/viewer_headless_local.sh
           $<TARGET_FILE:raystream-viewer> ${CMAKE_CURRENT_BINARY_DIR}/viewer_headless_local
           $<TARGET_FILE:raystream-render> $<TARGET_FILE:xwd_compare>)
  set_tests_properties(viewer_headless_local PROPERTIES TIMEOUT 300 SKIP_RETURN_CODE 77
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
endif()

# Still-pose refinement (issue 17): converging to the 16-sample CPU reference, restarting on
# motion; headless on cpu, egl and osmesa, and in the window (egl, the GPU mean) under Xvfb.
if(TARGET raystream-viewer AND TARGET raystream-render AND TARGET xwd_compare AND
   TARGET raystream-server)
  add_test(NAME viewer_refine
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/viewer_refine.sh
           $<TARGET_FILE:raystream-viewer> ${CMAKE_CURRENT_BINARY_DIR}/viewer_refine
           $<TARGET_FILE:raystream-render> $<TARGET_FILE:xwd_compare>
           $<TARGET_FILE:raystream-server>)
  set_tests_properties(viewer_refine PROPERTIES TIMEOUT 400 SKIP_RETURN_CODE 77
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
endif()
if(TARGET rs_window AND TARGET raystream-viewer AND TARGET raystream-render AND
   TARGET xwd_compare)
  add_test(NAME viewer_refine_xvfb
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/viewer_refine_xvfb.sh
           $<TARGET_FILE:raystream-viewer> ${CMAKE_CURRENT_BINARY_DIR}/viewer_refine_xvfb
           $<TARGET_FILE:xwd_compare> $<TARGET_FILE:raystream-render>)
  set_tests_properties(viewer_refine_xvfb PROPERTIES TIMEOUT 300 SKIP_RETURN_CODE 77
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
endif()

# The server's per-viewer frame-rate target (issue 17): a forced 1 ms budget sends smaller
# frames that the viewer scales up; no target, full size.
if(TARGET raystream-server AND TARGET raystream-viewer AND TARGET raystream-render AND
   TARGET xwd_compare)
  add_test(NAME server_target_fps
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/server_target_fps.sh
           $<TARGET_FILE:raystream-server> ${CMAKE_CURRENT_BINARY_DIR}/server_target_fps
           $<TARGET_FILE:raystream-viewer> $<TARGET_FILE:raystream-render>
           $<TARGET_FILE:xwd_compare>)
  set_tests_properties(server_target_fps PROPERTIES TIMEOUT 300
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
endif()
