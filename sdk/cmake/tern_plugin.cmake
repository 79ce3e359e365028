# tern_add_plugin(NAME <name> SOURCES <files...> [LIBRARIES <targets...>]
#                 [OUTPUT_DIRECTORY <dir>] [NO_INSTALL])
#
# Builds libtern_<name>.so, a tern plugin: a MODULE library with hidden visibility, position
# independent code and no GNU unique symbols (so that dlclose really unloads it, which hot-swap
# relies on), linked against the tern SDK. The plugin's sources must register exactly one
# class with TERN_PLUGIN(...) (tern/plugin.hpp), which emits the handshake the host checks.
#
# Output directory: OUTPUT_DIRECTORY, else TERN_PLUGIN_BUILD_DIR (tern's own tree: build/plugins),
# else <your build dir>/plugins. Install rule (`cmake --install`): TERN_INSTALL_PLUGIN_DIR, else
# <libdir>/tern/plugins, which the installed `tern` searches (<exe>/../lib/tern/plugins);
# NO_INSTALL skips it (test fixtures).
function(tern_add_plugin)
  cmake_parse_arguments(TP "NO_INSTALL" "NAME;OUTPUT_DIRECTORY" "SOURCES;LIBRARIES" ${ARGN})
  if(NOT TP_NAME)
    message(FATAL_ERROR "tern_add_plugin: NAME is required")
  endif()
  if(NOT TP_SOURCES)
    message(FATAL_ERROR "tern_add_plugin(${TP_NAME}): SOURCES is required")
  endif()
  set(_target tern_${TP_NAME})
  add_library(${_target} MODULE ${TP_SOURCES})
  if(TARGET tern::sdk)
    target_link_libraries(${_target} PRIVATE tern::sdk ${TP_LIBRARIES})
  else()
    target_link_libraries(${_target} PRIVATE tern_sdk ${TP_LIBRARIES})
  endif()
  set_target_properties(${_target} PROPERTIES
    PREFIX "lib"
    OUTPUT_NAME ${_target}
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    POSITION_INDEPENDENT_CODE ON)
  target_compile_options(${_target} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-fno-gnu-unique>)
  target_link_options(${_target} PRIVATE -Wl,--no-undefined -Wl,-z,defs)
  if(TP_OUTPUT_DIRECTORY)
    set_target_properties(${_target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${TP_OUTPUT_DIRECTORY})
  elseif(DEFINED TERN_PLUGIN_BUILD_DIR)
    set_target_properties(${_target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${TERN_PLUGIN_BUILD_DIR})
  else()
    set_target_properties(${_target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/plugins)
  endif()
  if(NOT TP_NO_INSTALL)
    if(DEFINED TERN_INSTALL_PLUGIN_DIR)
      install(TARGETS ${_target} LIBRARY DESTINATION ${TERN_INSTALL_PLUGIN_DIR})
    elseif(DEFINED CMAKE_INSTALL_LIBDIR)
      install(TARGETS ${_target} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/tern/plugins)
    else()
      install(TARGETS ${_target} LIBRARY DESTINATION lib/tern/plugins)
    endif()
  endif()
endfunction()
