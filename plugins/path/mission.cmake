# tern_path_mission: the path planner's mission reading (tern/path/mission.hpp) and checks
# (tern/path/mission_check.hpp), plain C++ (Eigen, yaml-cpp, GeographicLib). One library for the
# plugin and the host: `tern check` and `tern fly` read a mission with the planner's own parser.
# Included by core/CMakeLists.txt (so that the host has it even when TERN_PLUGINS leaves the
# path plugins out) and used by plugins/path/CMakeLists.txt.
if(TARGET tern_path_mission)
  return()
endif()
find_library(TERN_GEOGRAPHICLIB_LIBRARY NAMES GeographicLib REQUIRED)
find_path(TERN_GEOGRAPHICLIB_INCLUDE_DIR GeographicLib/LocalCartesian.hpp REQUIRED)
add_library(tern_path_mission STATIC ${CMAKE_CURRENT_LIST_DIR}/src/mission.cpp ${CMAKE_CURRENT_LIST_DIR}/src/mission_check.cpp)
target_include_directories(tern_path_mission PUBLIC ${CMAKE_CURRENT_LIST_DIR}/include)
target_include_directories(tern_path_mission SYSTEM PRIVATE ${TERN_GEOGRAPHICLIB_INCLUDE_DIR})
target_link_libraries(tern_path_mission PUBLIC Eigen3::Eigen PRIVATE yaml-cpp ${TERN_GEOGRAPHICLIB_LIBRARY})
target_compile_options(tern_path_mission PRIVATE $<$<CXX_COMPILER_ID:GNU>:-fno-gnu-unique>)
set_target_properties(tern_path_mission PROPERTIES POSITION_INDEPENDENT_CODE ON
  CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
