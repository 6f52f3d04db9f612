# test_gl_storage again on the GLES versions below 3.2 that the GL backends support, through
# Mesa's version override (other drivers ignore the variable, and the runs repeat the
# default one): GLES 3.1 takes buffer textures through OES/EXT_texture_buffer, GLES 3.0 has
# none and must fall back to 2D textures.
if(TARGET test_gl_storage)
  foreach(version 3.1 3.0)
    string(REPLACE "." "" suffix ${version})
    add_test(NAME test_gl_storage_es${suffix} COMMAND test_gl_storage
             WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
    set_tests_properties(test_gl_storage_es${suffix} PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77
      ENVIRONMENT "MESA_GLES_VERSION_OVERRIDE=${version};${rs_cmocka_env}")
  endforeach()
endif()
