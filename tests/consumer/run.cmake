# cmake -P script: install the build tree to PREFIX, build the consumer, run both binaries.
file(REMOVE_RECURSE ${PREFIX} ${PREFIX}-consumer)
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD} --prefix ${PREFIX}
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "install failed: ${rc}")
endif()
# Test seams and driver headers stay out of the installed API: no fake-device tables, no
# libusb or hidapi types, and every header under include/raystream/.
file(GLOB rs_installed LIST_DIRECTORIES false ${PREFIX}/include/*.h ${PREFIX}/include/raystream/*.h)
foreach(h IN LISTS rs_installed)
  if(NOT h MATCHES "/include/raystream/rs_[a-z0-9_]+\\.h$")
    message(FATAL_ERROR "header installed outside include/raystream: ${h}")
  endif()
  file(READ ${h} text)
  foreach(seam rs_usb_api rs_hid_api "libusb.h" "hidapi.h" LIBUSB_)
    string(FIND "${text}" "${seam}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "${h} exposes ${seam} (a test seam or driver type)")
    endif()
  endforeach()
endforeach()
foreach(h rs_tracker rs_serial rs_status)
  if(NOT EXISTS ${PREFIX}/include/raystream/${h}.h)
    message(FATAL_ERROR "raystream/${h}.h is not installed")
  endif()
endforeach()
set(ENV{PKG_CONFIG_PATH} "${PREFIX}/lib/pkgconfig:${PREFIX}/lib/x86_64-linux-gnu/pkgconfig")
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SRC} -B ${PREFIX}-consumer
                -DCMAKE_PREFIX_PATH=${PREFIX} "-DCMAKE_C_FLAGS=${FLAGS}"
                "-DCMAKE_EXE_LINKER_FLAGS=${LDFLAGS}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(rc)
  message(FATAL_ERROR "consumer configure failed:\n${out}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${PREFIX}-consumer
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(rc)
  message(FATAL_ERROR "consumer build failed:\n${out}")
endif()
foreach(exe consumer_cmake consumer_pkgconfig)
  execute_process(COMMAND ${PREFIX}-consumer/${exe} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE out)
  if(rc)
    message(FATAL_ERROR "${exe} failed (${rc}):\n${out}")
  endif()
  message(STATUS "${exe}: ${out}")
endforeach()
