# The library installs and exports: a separate project finds it with find_package and with
# pkg-config, links it and renders with it.
set(rs_prefix ${CMAKE_BINARY_DIR}/install-test)
set(rs_flags "")
set(rs_ldflags "")
if(RS_SANITIZE)
  set(rs_flags "-fsanitize=address,undefined")
  set(rs_ldflags "-fsanitize=address,undefined")
endif()
add_test(NAME install_and_consume COMMAND ${CMAKE_COMMAND}
  -DBUILD=${CMAKE_BINARY_DIR} -DPREFIX=${rs_prefix}
  -DSRC=${CMAKE_CURRENT_SOURCE_DIR}/consumer -DFLAGS=${rs_flags} -DLDFLAGS=${rs_ldflags}
  -P ${CMAKE_CURRENT_SOURCE_DIR}/consumer/run.cmake)
set_tests_properties(install_and_consume PROPERTIES TIMEOUT 300 RUN_SERIAL TRUE
  ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1")
