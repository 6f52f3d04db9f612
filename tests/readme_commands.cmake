# Every command of README.md's ```sh blocks, run as written (small sizes and short runs
# substituted, as readme_commands.sh lists): exit status 0 and the outputs it names.
if(TARGET raystream-render AND TARGET raystream-bench AND TARGET raystream-report
   AND TARGET raystream-scene AND TARGET raystream-track AND TARGET raystream-optsynth
   AND TARGET raystream-calib AND TARGET raystream-server AND TARGET raystream-viewer
   AND TARGET raystream-streambench AND TARGET rs_egl)
  add_test(NAME readme_commands COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/readme_commands.sh
           ${PROJECT_SOURCE_DIR} ${CMAKE_BINARY_DIR} ${CMAKE_CURRENT_BINARY_DIR}/readme_commands)
  set_tests_properties(readme_commands PROPERTIES TIMEOUT 1500 RUN_SERIAL TRUE
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp")
endif()
