# The firmware's behaviours checked on both FCU programs (tern-fcu-emulator and tern-fcu-sil).
function(tern_fcu_sil_behaviour_target)
  add_executable(tern_fcu_sil_behaviour_tests ${TERN_FCU_SERIAL_DIR}/tests/test_main.cpp ${TERN_FCU_SERIAL_DIR}/tests/sil_behaviours.cpp
    ${TERN_FCU_SERIAL_DIR}/tests/sil_duties.cpp ${TERN_FCU_SERIAL_DIR}/tests/fcu_process.cpp)
  target_link_libraries(tern_fcu_sil_behaviour_tests PRIVATE tern_fcu_serial_core doctest::doctest)
  target_compile_definitions(tern_fcu_sil_behaviour_tests PRIVATE
    TERN_FCU_EMULATOR="$<TARGET_FILE:tern-fcu-emulator>" TERN_FCU_SIL="$<TARGET_FILE:tern-fcu-sil>"
    TERN_AIRCRAFT_DIR="${CMAKE_SOURCE_DIR}/configs/aircraft" TERN_FCU_CONFIGS="${CMAKE_SOURCE_DIR}/configs/fcu")
  add_dependencies(tern_fcu_sil_behaviour_tests tern-fcu-emulator tern-fcu-sil)
endfunction()
