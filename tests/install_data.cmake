# Installed tools find the installed data from the prefix they run from (tests/install_data.sh).
if(TARGET raystream-render AND TARGET raystream-scene)
  add_test(NAME install_data COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/install_data.sh
           ${CMAKE_BINARY_DIR} ${CMAKE_CURRENT_BINARY_DIR}/install_data)
  set_tests_properties(install_data PROPERTIES TIMEOUT 300
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp")
endif()
