# tools/gpu-bundle.sh and tools/gpu-device-run.sh --quick: the GPU machine's archive and its
# one-command run, on this machine's EGL (no timing). Builds its own Release tree.
if(TARGET raystream-bench AND TARGET rs_egl)
  add_test(NAME gpu_bundle_smoke COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/gpu_bundle_smoke.sh
           ${PROJECT_SOURCE_DIR}/tools/gpu-bundle.sh ${CMAKE_CURRENT_BINARY_DIR}/gpu_bundle_smoke)
  set_tests_properties(gpu_bundle_smoke PROPERTIES TIMEOUT 900 SKIP_RETURN_CODE 77
    ENVIRONMENT "RS_DATA_DIR=${RS_DATA_DIR}")
endif()
