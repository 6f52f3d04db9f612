# raystream-scene end to end: builds, exports and re-reads scenes; bad input fails in one line.
if(TARGET raystream-scene)
  add_test(NAME scene_tool COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/scene_tool.sh
           $<TARGET_FILE:raystream-scene> ${CMAKE_CURRENT_BINARY_DIR}/scene_tool)
  set_tests_properties(scene_tool PROPERTIES TIMEOUT 300
    ENVIRONMENT "RS_DATA_DIR=${RS_DATA_DIR};ASAN_OPTIONS=detect_leaks=1")
endif()
