// core/apps/sysid/log_units.cpp: a sensor log's values against their columns' units (log_units.hpp).
#include "sysid/log_units.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "config/error.hpp"
#include "replay/sensor_units.hpp"
#include "sysid/flight_data.hpp"
#include "tern/math.hpp"

namespace tern::core::sysid {

namespace {

using Column = std::vector<double>;

/// rad: no control surface deflects further (a log in degrees passes it at 1.6 deg)
constexpr double kMaxSurfaceDeflection = kPi / 2.0;
/// the throttle's documented 0 (idle) .. 1 (full), with room for an autopilot's overshoot or a
/// reversible motor's -1 (a percentage or a pulse width in microseconds passes it at once)
constexpr double kMinThrottle = -1.0, kMaxThrottle = 1.5;

/// m/s^2: the median of the accelerometer's z above which the IMU is not FRD. In FRD the specific
/// force's z is about -g on the ground and -g times the load factor in flight (the lift pushes up);
/// an IMU with its z up (FLU, ROS's base_link) reads about +g, and no flight spends half its time
/// inverted.
constexpr double kMaxMedianAccelZ = 0.5 * kStandardGravity;

/// Throws ConfigError when the median of `accel_z` (the body's, after imu_mount) exceeds
/// kMaxMedianAccelZ: identified, an FLU log gave C_m_delta_e +0.90 and C_ell_beta +0.11 and exited 0.
void require_frd_accelerometer(const CsvTable& imu, const Column& accel_z) {
  const double mid = median(accel_z);
  if (!(mid > kMaxMedianAccelZ)) return;
  throw ConfigError(
      fmt::format("{}: accel_z's median is {:+.2f} m/s^2: an FRD accelerometer reads about {:.1f} on z at rest and in "
                  "level flight; these axes point z up (FLU, as ROS's base_link) or the IMU is upside down: turn its "
                  "columns to FRD or give its mounting (sensor_log.yaml estimator: imu_mount; docs/sensor-log.md)",
                  imu.file.string(), mid, -kStandardGravity));
}

}  // namespace

void require_command_unit(const CsvTable& table, const char* column) {
  const Column& c = table.at(column);
  const bool throttle = std::string_view(column) == "delta_t";
  const double lo = throttle ? kMinThrottle : -kMaxSurfaceDeflection, hi = throttle ? kMaxThrottle : kMaxSurfaceDeflection;
  const auto out = std::find_if(c.begin(), c.end(), [lo, hi](double v) { return v < lo || v > hi; });
  if (out == c.end()) return;
  const double t = table.at("t")[static_cast<std::size_t>(out - c.begin())];
  throw ConfigError(throttle
                        ? fmt::format("{}: delta_t is {:g} at t = {:g} s: the throttle is 0 (idle) .. 1 (full), not a percentage or "
                                      "a pulse width (docs/sensor-log.md, actuators)",
                                      table.file.string(), *out, t)
                        : fmt::format("{}: {} is {:g} rad at t = {:g} s: a surface deflects less than {:.4g} rad ({:g} deg); degrees "
                                      "logged as radians? (docs/sensor-log.md, actuators)",
                                      table.file.string(), column, *out, t, kMaxSurfaceDeflection, kMaxSurfaceDeflection / kRadPerDeg));
}

void require_imu_magnitudes(const CsvTable& imu, const std::map<std::string, Column>& columns) {
  const Column &ax = columns.at("accel_x"), &ay = columns.at("accel_y"), &az = columns.at("accel_z");
  const Column &p = columns.at("gyro_x"), &q = columns.at("gyro_y"), &r = columns.at("gyro_z");
  Column f(ax.size()), w(p.size());
  for (std::size_t k = 0; k < ax.size(); ++k) f[k] = std::sqrt(ax[k] * ax[k] + ay[k] * ay[k] + az[k] * az[k]);
  for (std::size_t k = 0; k < p.size(); ++k) w[k] = std::sqrt(p[k] * p[k] + q[k] * q[k] + r[k] * r[k]);
  core::require_imu_magnitudes(imu.file, std::move(f), w);  // replay/sensor_units.hpp: the replay's own check
}

void require_imu_units(const CsvTable& imu, const std::map<std::string, Column>& body) {
  require_imu_magnitudes(imu, body);
  require_frd_accelerometer(imu, body.at("accel_z"));
}

}  // namespace tern::core::sysid
