# The MAVLink 1.0 C API of a dialect (what `mavgen --lang=C --wire-protocol=1.0` writes, as one
# header <dialect>/mavlink.h), generated at build time by mavlink/generate_c.py: for code written
# against the MAVLink C library, such as the ROSflight firmware's mavlink_adapter.cpp
# (#include "rosflight/mavlink.h"). Included by plugins/fcu_serial/CMakeLists.txt (needs python3).
set(TERN_FCU_MAVLINK_C_DIR ${CMAKE_CURRENT_LIST_DIR}/../mavlink CACHE INTERNAL "fcu_serial's MAVLink generators")
set(TERN_FCU_MAVLINK_C_PYTHON ${Python3_EXECUTABLE} CACHE INTERNAL "python3 for generate_c.py")

# tern_fcu_mavlink_c(<target> <dialect.xml>): <target> is an INTERFACE library whose include
# directory (${CMAKE_CURRENT_BINARY_DIR}/<target>) holds <dialect>/mavlink.h, e.g. rosflight/mavlink.h
# for rosflight.xml; targets linking it build after the header is generated.
function(tern_fcu_mavlink_c target dialect)
  get_filename_component(xml ${dialect} ABSOLUTE)
  get_filename_component(name ${xml} NAME_WE)
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/${target})
  set(header ${dir}/${name}/mavlink.h)
  set(gen ${TERN_FCU_MAVLINK_C_DIR})
  add_custom_command(
    OUTPUT ${header}
    COMMAND ${TERN_FCU_MAVLINK_C_PYTHON} ${gen}/generate_c.py ${xml} ${dir}
    DEPENDS ${gen}/generate_c.py ${TERN_MAVLINK_DIR}/generate.py ${gen}/c_api_core.h.in ${xml}
    COMMENT "fcu_serial: MAVLink 1.0 C API (${name}/mavlink.h) from ${xml}"
    VERBATIM)
  add_custom_target(${target}_generate DEPENDS ${header})
  add_library(${target} INTERFACE)
  target_include_directories(${target} INTERFACE ${dir})
  target_link_libraries(${target} INTERFACE tern_mavlink)  # the checksum (tern/mavlink/frame.hpp)
  add_dependencies(${target} ${target}_generate)
endfunction()

# Tests: the generated API against tern's own codec (tern_fcu_serial_core), and the generator.
tern_fcu_mavlink_c(tern_fcu_mavlink_c_rosflight ${CMAKE_CURRENT_SOURCE_DIR}/mavlink/rosflight.xml)
add_executable(tern_fcu_mavlink_c_tests ${CMAKE_CURRENT_SOURCE_DIR}/tests/test_main.cpp ${CMAKE_CURRENT_SOURCE_DIR}/tests/test_mavlink_c.cpp)
target_link_libraries(tern_fcu_mavlink_c_tests PRIVATE tern_fcu_mavlink_c_rosflight tern_fcu_serial_core doctest::doctest)
add_test(NAME fcu_mavlink_c COMMAND tern_fcu_mavlink_c_tests)
add_test(NAME fcu_mavlink_c_generator COMMAND ${TERN_FCU_MAVLINK_C_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/tests/test_generate_c.py)
