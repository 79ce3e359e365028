// Estimator health: the State status and the innovation test ratios (see estimator.hpp).
#include <algorithm>
#include <cmath>

#include "tern/estimator_ekf/estimator.hpp"

namespace tern::ekf {

msg::StateStatus Estimator::status(std::uint8_t* degraded_sensors) const {
  // Bit i is Sensor i: imu 1, gnss 2, baro 4, diff_pressure 8, mag 16 (msg::sensor_bit).
  std::uint8_t bits = 0;
  for (int i = 0; i < kSensorCount; ++i)
    if (counters_[i].timed_out) bits |= static_cast<std::uint8_t>(1u << i);
  if (gnss_pos_.stats.consecutive_rejected >= static_cast<std::uint64_t>(cfg_.inflate_after)) bits |= msg::sensor_bit::gnss;
  if (degraded_sensors != nullptr) *degraded_sensors = bits;
  // Invalid too until the GNSS start-up checks have held (the origin is provisional till then),
  // unless the start was in the air (origin_valid()).
  if (!initialized_ || !origin_valid() || (bits & msg::sensor_bit::imu) != 0) return msg::StateStatus::invalid;
  // The covariance says whether the attitude and position are still known: roll and pitch are
  // the NED x and y components of the body-frame attitude error.
  const Cov& P = filter_.P();
  const Mat3 R = filter_.x().R();
  const Mat3 P_tilt = R * P.block<3, 3>(idx::th, idx::th) * R.transpose();
  const double tilt_var = std::max(P_tilt(0, 0), P_tilt(1, 1));
  const double pos_var = std::max(P(idx::p, idx::p), P(idx::p + 1, idx::p + 1));
  if (!(tilt_var <= cfg_.max_tilt_sigma * cfg_.max_tilt_sigma) || !(pos_var <= cfg_.max_position_sigma * cfg_.max_position_sigma))
    return msg::StateStatus::invalid;
  return bits != 0 ? msg::StateStatus::degraded : msg::StateStatus::ok;
}

msg::Innovations Estimator::take_innovations(Nanos stamp) {
  msg::Innovations m;
  m.stamp = stamp;
  m.gnss_pos = gnss_pos_.stats.take_max_ratio();
  m.gnss_vel = gnss_velocity_stats().take_max_ratio();
  m.baro = baro_.stats.take_max_ratio();
  m.diff_pressure = pitot_.stats.take_max_ratio();
  const double heading = mag_heading_.stats.take_max_ratio(), direction = mag_.stats.take_max_ratio();
  m.mag = std::max(heading, direction);  // one of the two models takes each sample (Estimator::add_mag)
  const double side_force = side_force_.stats.take_max_ratio(), sideslip = sideslip_.stats.take_max_ratio();
  m.sideslip = side_force_.k != 0.0 ? side_force : sideslip;
  m.normal_force = normal_force_.stats.take_max_ratio();
  return m;
}

}  // namespace tern::ekf
