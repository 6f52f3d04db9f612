# The viewer's frame-rate target under forced frame times (issue 17): scale steps down and
# back up, with hysteresis. apps/common is not a library module, so not a test_*.c.
if(TARGET rs_appcommon)
  add_executable(app_pace_test ${CMAKE_CURRENT_SOURCE_DIR}/app_pace_test.c)
  target_link_libraries(app_pace_test PRIVATE rs_appcommon)
  add_test(NAME app_pace COMMAND app_pace_test)
endif()

# Still-pose refinement's stillness thresholds, sample sequence and C mean (issue 17).
if(TARGET rs_appcommon)
  add_executable(app_refine_test ${CMAKE_CURRENT_SOURCE_DIR}/app_refine_test.c)
  target_link_libraries(app_refine_test PRIVATE rs_appcommon m)
  add_test(NAME app_refine COMMAND app_refine_test)
endif()
