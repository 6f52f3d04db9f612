# test_defaults runs raystream-render beside the library (tests/test_defaults.c).
if(TARGET raystream-render AND TEST test_defaults)
  set_property(TEST test_defaults APPEND PROPERTY ENVIRONMENT
               "RS_RENDER_BIN=$<TARGET_FILE:raystream-render>")
endif()
