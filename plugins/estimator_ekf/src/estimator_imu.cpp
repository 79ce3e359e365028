// Estimator: the IMU sample: propagation, the lever arm to the centre of gravity, a lost attitude, sensor delays (see estimator.hpp).
#include "tern/estimator_ekf/estimator.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "tern/math.hpp"

namespace tern::ekf {

bool Estimator::add_imu(const msg::Imu& m) {
  const bool ok = m.accel.allFinite() && m.gyro.allFinite() && m.accel.cwiseAbs().maxCoeff() <= cfg_.accel_max &&
                  m.gyro.cwiseAbs().maxCoeff() <= cfg_.gyro_max && (imu_stamp_ < 0 || m.stamp > imu_stamp_);
  if (!accept(Sensor::imu, m.stamp, ok)) return false;
  double dt = imu_stamp_ < 0 ? 0.0 : to_seconds(m.stamp - imu_stamp_);
  imu_stamp_ = m.stamp;
  const Vec3 gyro = R_bi_ * m.gyro;
  const Vec3 accel = imu_to_cg(R_bi_ * m.accel, gyro, dt);
  // The last kPreInitImuSpan of samples: the initialisation's, and the GNSS start-up checks' rest
  // test (still(), over the last second) until they have held, a provisional start included.
  if (!initialized_ || !gnss_checks_.passed()) {
    pre_init_imu_.push_back({m.stamp, accel, gyro});
    while (m.stamp - pre_init_imu_.front().stamp > kPreInitImuSpan) pre_init_imu_.pop_front();
  } else if (!pre_init_imu_.empty()) {
    pre_init_imu_.clear();
  }
  if (!initialized_) {
    // Low-pass averages for the initial attitude and gyro bias.
    const double a = imu_samples_ == 0 ? 1.0 : std::clamp(dt / cfg_.init_average_time, 0.0, 1.0);
    accel_avg_ += a * (accel - accel_avg_);
    gyro_avg_ += a * (gyro - gyro_avg_);
    ++imu_samples_;
    rate_ = gyro;
    return true;
  }
  if (dt > cfg_.imu_reinit_gap) {
    lose_attitude(m.stamp, dt);
    return true;
  }
  if (dt > cfg_.imu_max_dt) {
    push(m.stamp, EventKind::imu_gap, Sensor::imu, dt);
    dt = cfg_.imu_max_dt;
  }
  bool covariance_stepped = false;
  if (dt > 0.0) {
    covariance_stepped = filter_.propagate(accel, gyro, dt, process_, cfg_.gravity);
    // The wind is never less known than without any air data: where none reaches it (on the
    // ground, below the pitot's minimum airspeed) the random walk would grow it past 8 m/s in a
    // minute of taxiing.
    if (covariance_stepped) filter_.limit_variance(idx::w, 2, cfg_.init_wind_sigma * cfg_.init_wind_sigma);
    if (!output_offset_.isZero()) {
      output_offset_ *= cfg_.gnss_recovery_time > 0.0 ? std::exp(-dt / cfg_.gnss_recovery_time) : 0.0;
      if (output_offset_.norm() < 1e-4) output_offset_.setZero();
    }
  }
  rate_ = filter_.x().rate(gyro);
  gnss_vel_.gyro = gyro;
  // the yaw from IMU and GNSS velocity alone, beside the filter (yaw_gsf.hpp)
  if (dt > 0.0 && cfg_.gsf_max_sigma > 0.0) gsf_.predict(accel, gyro - filter_.x().b_g, dt, airborne(m.stamp) ? last_Va_ : 0.0);
  if (dt > 0.0) {  // |NED acceleration|, low-passed over 0.2 s (ArduPilot EKF3's accNavMag)
    const Vec3 a_ned = filter_.x().q * (accel - filter_.x().b_a) + Vec3(0.0, 0.0, cfg_.gravity);
    accel_nav_ += std::min(dt / 0.2, 1.0) * (a_ned.norm() - accel_nav_);
  }
  accel_sum_ += accel;
  ++accel_n_;
  // The covariance changes when it steps and in updates: checked with the next step (within one
  // covariance period), the state with every sample.
  if (covariance_stepped ? !filter_.healthy() : !filter_.x().all_finite()) {
    ++filter_resets_;
    push(m.stamp, EventKind::filter_reset, Sensor::imu);
    initialized_ = false;
    keep_calibration_ = false;  // the state is not finite: nothing to keep
    imu_samples_ = 0;
    mag_samples_ = 0;
    history_.clear();
    return true;
  }
  history_.push(m.stamp, filter_.x(), filter_.correction_sum());
  return true;
}

Vec3 Estimator::imu_to_cg(const Vec3& accel_body, const Vec3& gyro_body, double dt) {
  // An accelerometer at r from the CG feels f_cg + omega_dot x r + omega x (omega x r). The
  // angular acceleration is the gyro's difference, low-passed over 20 ms (its noise would
  // otherwise reach the specific force as noise / dt * |r|).
  if (dt > 0.0 && dt <= cfg_.imu_max_dt) {
    const double a = dt / (0.02 + dt);
    omega_dot_ += a * ((gyro_body - gyro_body_) / dt - omega_dot_);
  }
  gyro_body_ = gyro_body;
  const Vec3& r = cfg_.imu_position;
  if (r.isZero()) return accel_body;
  const Vec3 w = filter_.x().rate(gyro_body);
  return accel_body - omega_dot_.cross(r) - w.cross(w.cross(r));
}

void Estimator::lose_attitude(Nanos stamp, double gap) {
  // Without the gyro for this long the attitude is unknown (a turn rolls through tens of
  // degrees): start again from the in-flight initialisation; the origin and the barometer
  // calibration stay.
  push(stamp, EventKind::imu_lost, Sensor::imu, gap);
  initialized_ = false;
  keep_calibration_ = true;  // the sensors' biases and sensitivities did not change meanwhile
  imu_samples_ = 0;
  mag_samples_ = 0;
  pre_init_imu_.clear();
  prev_fix_tv_ = -1;
  history_.clear();
}

Nanos Estimator::valid_at(Sensor s, Nanos stamp) const {
  return stamp - static_cast<Nanos>(std::llround(cfg_.delay[static_cast<int>(s)] * 1e9));
}

}  // namespace tern::ekf
