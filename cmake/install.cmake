# Install rules for tern's data (included from the top-level CMakeLists.txt):
#   <prefix>/share/tern/configs   aircraft, gains and missions; the installed `tern fly` without a
#                                 config flies share/tern/configs/missions/default.yaml (found
#                                 relative to the binary: <exe>/../share/tern).
# Everything else installs from its own folder: the SDK (headers, libraries, CMake package,
# templates, tern-new-plugin) from sdk/, `tern` and tern-plot from core/, stock plugins via
# tern_add_plugin(), tools such as tern-aero from their plugin folders.
install(DIRECTORY ${CMAKE_CURRENT_LIST_DIR}/../configs/ DESTINATION ${CMAKE_INSTALL_DATADIR}/tern/configs)
