# Short libFuzzer smoke runs of the tracker and stream protocol parsers (tests/fuzz.sh), registered only when
# clang-14 with libFuzzer is available. Longer runs: tests/fuzz.sh SECONDS.
find_program(RS_FUZZ_CLANG NAMES clang-14)
if(RS_FUZZ_CLANG AND NOT DEFINED RS_FUZZ_WORKS)
  set(_probe ${CMAKE_CURRENT_BINARY_DIR}/fuzz_probe.c)
  file(WRITE ${_probe} "#include <stdint.h>\n#include <stddef.h>\nint LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { (void)d; (void)n; return 0; }\n")
  execute_process(COMMAND ${RS_FUZZ_CLANG} -fsanitize=fuzzer,address ${_probe}
                          -o ${CMAKE_CURRENT_BINARY_DIR}/fuzz_probe
                  RESULT_VARIABLE _rc OUTPUT_QUIET ERROR_QUIET)
  if(_rc EQUAL 0)
    set(RS_FUZZ_WORKS ON CACHE INTERNAL "clang-14 links libFuzzer")
  else()
    set(RS_FUZZ_WORKS OFF CACHE INTERNAL "clang-14 links libFuzzer")
  endif()
endif()
if(RS_FUZZ_CLANG AND RS_FUZZ_WORKS)
  add_test(NAME fuzz_proto_smoke
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/fuzz.sh 20 ${CMAKE_CURRENT_BINARY_DIR}/fuzz)
  set_tests_properties(fuzz_proto_smoke PROPERTIES TIMEOUT 180
                       ENVIRONMENT "RS_FUZZ_CC=${RS_FUZZ_CLANG}")
  add_test(NAME fuzz_stream_smoke
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/fuzz.sh 20 ${CMAKE_CURRENT_BINARY_DIR}/fuzz)
  set_tests_properties(fuzz_stream_smoke PROPERTIES TIMEOUT 180
                       ENVIRONMENT "RS_FUZZ_CC=${RS_FUZZ_CLANG};RS_FUZZ_TARGET=stream")
else()
  message(STATUS "raystream: clang-14 with libFuzzer not found; fuzz smoke test skipped")
endif()
