# rs_add_module(NAME [DEPS targets...] [PRIVATE_DEPS targets...] [PC_REQUIRES names...])
# One static library per folder: every .c file in the calling directory, public headers in
# lib/include/raystream. Registered for install/export and the pkg-config file.
function(rs_add_module name)
  cmake_parse_arguments(M "" "" "DEPS;PRIVATE_DEPS;PC_REQUIRES" ${ARGN})
  file(GLOB srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.c)
  if(NOT srcs)
    message(STATUS "raystream: module ${name} has no sources yet; skipped")
    return()
  endif()
  add_library(${name} STATIC ${srcs})
  target_include_directories(${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/lib/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_include_directories(${name} PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_link_libraries(${name} PUBLIC ${M_DEPS} PRIVATE ${M_PRIVATE_DEPS})
  install(TARGETS ${name} EXPORT raystreamTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  set_property(GLOBAL APPEND PROPERTY RS_MODULES ${name})
  set_property(GLOBAL APPEND PROPERTY RS_PC_REQUIRES ${M_PC_REQUIRES})
endfunction()

# rs_add_backend(NAME [DISPATCHER] [DEPS ...] [PRIVATE_DEPS ...] [PC_REQUIRES ...])
# A backend folder (backends/<name>/): rs_add_module() plus its public headers, kept in
# backends/<name>/include/raystream/ so they read <raystream/rs_x.h> in the tree exactly as
# when installed. Private headers (test seams) stay beside the sources, never installed.
# Device backends are listed in the configure summary; DISPATCHER ones (rs_tracker) are not.
function(rs_add_backend name)
  cmake_parse_arguments(B "DISPATCHER" "" "" ${ARGN})
  rs_add_module(${name} ${B_UNPARSED_ARGUMENTS})
  if(NOT TARGET ${name})
    return()
  endif()
  target_include_directories(${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>)
  file(GLOB hdrs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/include/raystream/*.h)
  install(FILES ${hdrs} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/raystream)
  set_property(GLOBAL APPEND PROPERTY RS_BACKEND_LIBS ${name})
  if(NOT B_DISPATCHER)
    string(REGEX REPLACE "^rs_" "" short ${name})
    set_property(GLOBAL APPEND PROPERTY RS_BACKENDS ${short})
  endif()
endfunction()

# rs_link_order(OUT modules...) : the modules ordered so each comes before every module it
# links (depth-first over their link interfaces): the order a static link line needs.
function(rs_link_order out)
  set(rs_all ${ARGN})
  set(rs_done "")
  set(rs_order "")
  foreach(m IN LISTS rs_all)
    rs__visit(${m})
  endforeach()
  list(REVERSE rs_order)
  set(${out} ${rs_order} PARENT_SCOPE)
endfunction()

macro(rs__visit m)
  if(NOT "${m}" IN_LIST rs_done)
    list(APPEND rs_done ${m})
    get_target_property(rs__deps_${m} ${m} INTERFACE_LINK_LIBRARIES)
    if(rs__deps_${m})
      foreach(d IN LISTS rs__deps_${m})
        # Private deps of a static library appear as $<LINK_ONLY:x>.
        string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" d "${d}")
        if("${d}" IN_LIST rs_all)
          rs__visit(${d})
        endif()
      endforeach()
    endif()
    list(APPEND rs_order ${m})
  endif()
endmacro()

# rs_add_tool(NAME) : an executable from every .c in the calling directory, linked to raystream.
function(rs_add_tool name)
  file(GLOB srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.c)
  add_executable(${name} ${srcs})
  target_link_libraries(${name} PRIVATE raystream ${ARGN})
  install(TARGETS ${name} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endfunction()

# rs_find_pkg(PREFIX pcmodule) : pkg-config dependency as PkgConfig::PREFIX, recorded so the
# installed raystreamConfig.cmake finds it again for consumers of the static libraries.
function(rs_find_pkg prefix module)
  pkg_check_modules(${prefix} ${ARGN} IMPORTED_TARGET GLOBAL ${module})
  if(${prefix}_FOUND)
    set_property(GLOBAL APPEND PROPERTY RS_PKG_IMPORTS "${prefix}=${module}")
  endif()
  set(${prefix}_FOUND ${${prefix}_FOUND} PARENT_SCOPE)
endfunction()

# rs_link_backends_later(TARGET DEFINE_PREFIX names...) : once the whole tree is configured
# (backend folders are configured alphabetically, so a dispatcher may come before the
# backends it opens), link each rs_<name> that exists publicly into TARGET and define
# DEFINE_PREFIX_<NAME>=1 for it.
function(rs_link_backends_now target prefix)
  foreach(b IN LISTS ARGN)
    if(TARGET rs_${b})
      string(TOUPPER ${b} B)
      target_link_libraries(${target} PUBLIC rs_${b})
      target_compile_definitions(${target} PRIVATE ${prefix}_${B}=1)
    endif()
  endforeach()
endfunction()
function(rs_link_backends_later target prefix)
  # Deferred arguments are expanded when the call runs: bake the values in now.
  string(REPLACE ";" " " names "${ARGN}")
  cmake_language(EVAL CODE "cmake_language(DEFER DIRECTORY \"${PROJECT_SOURCE_DIR}\"
                            CALL rs_link_backends_now ${target} ${prefix} ${names})")
endfunction()
