// core/apps/sysid/log_units.cpp: a sensor log's values against their columns' units (log_units.hpp).
#include "sysid/log_units.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "config/error.hpp"
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

/// m/s^2: the range of the specific force's median magnitude in m/s^2. It is g at rest and g
/// times the load factor in flight (tern's aerobatics mission: 1.0-1.1 g); an accelerometer in g
/// reads 1, one in mg or cm/s^2 hundreds.
constexpr double kMinMedianAccel = 0.5 * kStandardGravity, kMaxMedianAccel = 3.0 * kStandardGravity;

/// Throws ConfigError when the median of the specific force's magnitude lies outside
/// kMinMedianAccel .. kMaxMedianAccel: identified, a log in g gave 12 of 29 coefficients (C_ell_p
/// 24 % large) and exited 0.
void require_m_per_s2_accelerometer(const CsvTable& imu, const std::map<std::string, Column>& body) {
  const Column &x = body.at("accel_x"), &y = body.at("accel_y"), &z = body.at("accel_z");
  if (x.empty()) return;
  Column norm(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) norm[k] = std::sqrt(x[k] * x[k] + y[k] * y[k] + z[k] * z[k]);
  const double mid = median(std::move(norm));
  if (mid >= kMinMedianAccel && mid <= kMaxMedianAccel) return;
  throw ConfigError(fmt::format(
      "{}: the specific force's median magnitude is {:.4g} m/s^2: an accelerometer reads about {:.1f} at "
      "rest and in level flight; {} (docs/sensor-log.md, imu: m/s^2)",
      imu.file.string(), mid, kStandardGravity, mid < kMinMedianAccel ? "g logged as m/s^2?" : "mg or cm/s^2 logged as m/s^2?"));
}

/// rad/s: the RMS angular rate above which the gyros are not in rad/s. tern's aerobatics mission
/// (rolls and loops) flies at 0.96 rad/s RMS, its sysid manoeuvres at 0.24; the same logged in
/// deg/s read 55 and 14.
constexpr double kMaxGyroRms = 4.0;

/// Throws ConfigError when the gyros' RMS rate over the log exceeds kMaxGyroRms: replayed, a log in
/// deg/s had the estimator reset its velocity and yaw hundreds of times, and sysid then found "no
/// airborne stretch of 10 s".
void require_rad_per_s_gyro(const CsvTable& imu, const std::map<std::string, Column>& body) {
  const Column &p = body.at("gyro_x"), &q = body.at("gyro_y"), &r = body.at("gyro_z");
  if (p.empty()) return;
  double sum = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k) sum += p[k] * p[k] + q[k] * q[k] + r[k] * r[k];
  const double rms = std::sqrt(sum / static_cast<double>(p.size()));
  if (!(rms > kMaxGyroRms)) return;
  throw ConfigError(
      fmt::format("{}: the gyros' RMS rate is {:.1f} rad/s ({:.0f} deg/s): no fixed wing turns that fast through a "
                  "whole flight (tern's aerobatics: 0.96 rad/s); deg/s logged as rad/s? (docs/sensor-log.md, imu)",
                  imu.file.string(), rms, rms / kRadPerDeg));
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
  require_m_per_s2_accelerometer(imu, columns);
  require_rad_per_s_gyro(imu, columns);
}

void require_imu_units(const CsvTable& imu, const std::map<std::string, Column>& body) {
  require_imu_magnitudes(imu, body);
  require_frd_accelerometer(imu, body.at("accel_z"));
}

}  // namespace tern::core::sysid
