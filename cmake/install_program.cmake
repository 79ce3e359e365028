# tern_install_program(TARGET): installs an executable into <prefix>/bin with the run-time search
# path that finds tern's own libraries from there ($ORIGIN/../<libdir>: libtern_sdk.so and the
# rest), so that every installed program starts from any prefix without LD_LIBRARY_PATH. The
# install test (tests/sdk_install) runs each installed program from the prefix.
function(tern_install_program target)
  set_target_properties(${target} PROPERTIES INSTALL_RPATH "$ORIGIN/../${CMAKE_INSTALL_LIBDIR}")
  install(TARGETS ${target} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endfunction()
