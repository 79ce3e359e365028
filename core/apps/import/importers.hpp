// core/apps/import/importers.hpp: `tern import`'s converters from other projects' logs into a
// sensor log (docs/sensor-log.md). Each reads `in` (the unpacked directory of the original
// files, as shipped), streams the topics into `out` and finishes it (sensor_log.yaml); a file
// that cannot be read, or a row that cannot be parsed, is an ImportError naming the file, line
// and field. Rows dropped for a reason the user should know (time going backwards, ...) and the
// input's known weaknesses are counted in the report's warnings, one line each.
#pragma once

#include <filesystem>

#include "import/sensor_log_writer.hpp"
#include "import/surface_commands.hpp"

namespace tern::core {

/// Paul Riseborough's InertialNav text files (github.com/priseborough/InertialNav,
/// code/main_closed_loop_float.cpp): IMU.txt, GPS.txt, MAG.txt, NTUN.txt, ATT.txt,
/// GPOSonboard.txt, timing.txt, as in its InputFilesPX4_search.zip (a PX4 fixed wing, Zurich
/// 2014). `in`: the directory holding them (or one level above it). The files hold no surface
/// commands: no actuators table (one line says so).
ImportReport import_inertialnav(const std::filesystem::path& in, SensorLogWriter& out);

/// The ALFA dataset's mavros topic CSVs (CMU AirLab, castacks/alfa-dataset-tools: one
/// <bag>-mavros-<topic>.csv per topic, ROS ENU/FLU frames). `in`: the directory holding them
/// (or one level above it). The surfaces' commands from <bag>-mavros-rc-out.csv (servo PWM) where
/// the directory has it and `commands` states the full deflections.
ImportReport import_alfa(const std::filesystem::path& in, SensorLogWriter& out, const CommandMapping& commands = {});

/// A PX4 ULog file (.ulg): sensor_combined, vehicle_magnetometer, vehicle_air_data, ... (the mapping:
/// import/ulog_import.hpp). `in`: the .ulg file, or a directory holding one .ulg. The surfaces'
/// commands from actuator_controls where the log has them and `commands` states the full deflections.
ImportReport import_ulog(const std::filesystem::path& in, SensorLogWriter& out, const CommandMapping& commands = {});

/// An ArduPilot DataFlash log (.bin): IMU, GPS/GPA, BARO, ARSP, MAG, ATT/POS, ... (the mapping:
/// import/dataflash_import.hpp). `in`: the .bin file, or a directory holding one .bin. The surfaces'
/// commands from RCOU through the log's SERVOn_FUNCTION parameters, and SIDD's excitation, where
/// `commands` states the full deflections.
ImportReport import_dataflash(const std::filesystem::path& in, SensorLogWriter& out, const CommandMapping& commands = {});

}  // namespace tern::core
