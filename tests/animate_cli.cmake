# raystream-render --frame/--animate: frame N of an animated run is --frame N's image, bit
# for bit on the CPU reference (and on EGL where a context opens); static scenes refuse;
# the viewer's local frames move with --animate and stand still without.
if(TARGET raystream-render AND TARGET raystream-viewer)
  add_test(NAME animate_cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/animate_cli.sh
           $<TARGET_FILE:raystream-render> ${CMAKE_CURRENT_BINARY_DIR}/animate_cli
           $<TARGET_FILE:raystream-viewer>)
  set_tests_properties(animate_cli PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77
    ENVIRONMENT "RS_DATA_DIR=${RS_DATA_DIR};ASAN_OPTIONS=detect_leaks=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp")
endif()
