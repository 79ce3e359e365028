// tern_sim_aero/profiles.hpp: named sets of sensor defaults (sim_aero's `sensor_profile`).
//   rosflight  ROSflight's standalone simulator (SensorParams' own defaults) with the accelerometer
//              calibrated level at power-up, as the firmware requires before it arms
//   realistic  datasheet-grade: u-blox M8N/M9N GNSS, ICM-20602 IMU with motor vibration, residual
//              hard/soft iron, MS5611 barometer with static-port error, MS4525DO pitot; each
//              figure cited in profiles.cpp
//   ideal      noise-free and error-free (for debugging a controller without an estimator's help)
// Every individual sim_aero parameter still overrides the profile's value.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "tern_sim_aero/sensors.hpp"

namespace tern::sim {

/// The names sensor_profile() accepts, the default first.
const std::vector<std::string>& sensor_profile_names();

/// The sensor parameters of a named profile. Throws std::invalid_argument naming the profile and
/// the valid names for an unknown one.
SensorParams sensor_profile(std::string_view name);

}  // namespace tern::sim
