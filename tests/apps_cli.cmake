# The apps' command lines: --help, named bad values, output targets checked at start and
# a stats file that cannot be written at shutdown failing the server (tests/apps_cli.sh).
if(TARGET raystream-server AND TARGET raystream-viewer)
  add_test(NAME apps_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/apps_cli.sh
           $<TARGET_FILE:raystream-server> ${CMAKE_CURRENT_BINARY_DIR}/apps_cli
           $<TARGET_FILE:raystream-viewer>)
  set_tests_properties(apps_cli PROPERTIES TIMEOUT 300)
endif()
