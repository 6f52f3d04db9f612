# tools/gpu-bench.sh --quick: the GPU report's plumbing on this machine's EGL (no timing).
if(TARGET raystream-bench AND TARGET rs_egl)
  add_test(NAME gpu_bench_smoke COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/gpu_bench_smoke.sh
           ${PROJECT_SOURCE_DIR}/tools/gpu-bench.sh ${CMAKE_CURRENT_BINARY_DIR}/gpu_bench_smoke
           ${CMAKE_BINARY_DIR})
  set_tests_properties(gpu_bench_smoke PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77
    ENVIRONMENT "RS_DATA_DIR=${RS_DATA_DIR};ASAN_OPTIONS=detect_leaks=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp")
endif()
