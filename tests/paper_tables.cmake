# tools/paper-tables.sh --quick: the three tables' plumbing on tiny sizes (no timing).
if(TARGET raystream-bench AND TARGET rs_egl)
  add_test(NAME paper_tables COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/paper_tables.sh
           ${PROJECT_SOURCE_DIR}/tools/paper-tables.sh ${CMAKE_CURRENT_BINARY_DIR}/paper_tables
           ${CMAKE_BINARY_DIR})
  set_tests_properties(paper_tables PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77
    ENVIRONMENT "RS_DATA_DIR=${RS_DATA_DIR};ASAN_OPTIONS=detect_leaks=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp")
endif()
