# The GLES renderer's test seams (backends/gles/seams: GPU out-of-memory on demand, kernel
# sources replaced) are linked into the tests that use them, and only there: the shipped
# librs_gles.a has none (docs/gles.md, "Test seams").
foreach(t test_gl_errors test_gl_memory test_gl_envmap_capture test_gl_display_fused
    test_gl_compute)
  if(TARGET ${t} AND TARGET rs_gles_seams)
    target_link_libraries(${t} PRIVATE rs_gles_seams)
  endif()
endforeach()
