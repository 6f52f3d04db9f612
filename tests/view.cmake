# test_view checks the frustum with the renderer's own ray generator (rs_trace), which the
# rs_view module itself does not need.
if(TARGET test_view AND TARGET rs_trace)
  target_link_libraries(test_view PRIVATE rs_trace)
endif()
