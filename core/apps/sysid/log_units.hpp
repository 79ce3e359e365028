// core/apps/sysid/log_units.hpp: a sensor log's values against their columns' units
// (docs/sensor-log.md), before sysid and validate read them as such. A log written in another unit
// parses, replays and identifies: in degrees, g, deg/s, percent or FLU axes, tern sysid exited 0
// with coefficients wrong by 24 % to sign (a foreign log so rewritten, this file's checks' notes).
// Each check is on a statistic no flight in the right unit reaches, and throws ConfigError, one line
// naming the file, the value and the likely unit:
//   - a surface command beyond pi/2 rad (degrees logged as radians), a throttle outside -1 .. 1.5
//     (the documented 0 .. 1; a percentage or a pulse width): the first such row, with its time;
//   - the specific force's median magnitude outside 0.5 g .. 3 g (g, mg or cm/s^2 as m/s^2, or
//     gravity taken out) and the gyros' RMS rate over the log above 4 rad/s (deg/s logged as
//     rad/s): replay/sensor_units.hpp's, which `tern replay` makes too;
//   - accel_z's median above +g/2 (the IMU's z up: FLU, as ROS's base_link, or upside down).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "replay/replay_csv.hpp"

namespace tern::core::sysid {

/// The actuators' `column` (delta_a, delta_e, delta_r: rad; delta_t: 0 .. 1) within its unit's
/// range; the table has a `t` column. Values that are not numbers are not judged.
void require_command_unit(const CsvTable& actuators, const char* column);

/// The IMU's columns (accel_x .. gyro_z, m/s^2 and rad/s, every column the same length, every
/// value finite) against their units: the magnitudes' checks, which any rotation of the axes leaves
/// alone, so that they hold before the IMU's mounting is known (before the log is replayed).
void require_imu_magnitudes(const CsvTable& imu, const std::map<std::string, std::vector<double>>& columns);

/// The IMU's columns in the body's axes (imu_mount applied) against their units and FRD:
/// require_imu_magnitudes and accel_z's median; `imu` names the file.
void require_imu_units(const CsvTable& imu, const std::map<std::string, std::vector<double>>& body);

}  // namespace tern::core::sysid
