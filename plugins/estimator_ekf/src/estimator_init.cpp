// Estimator: initialisation and alignment: still on the ground, the first attitude and the prior covariance (see estimator.hpp).
#include "tern/estimator_ekf/estimator.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "tern/math.hpp"

namespace tern::ekf {

namespace {
/// Prior covariance of a sensor's sensitivity error S (9 states, row by row).
Eigen::Matrix<double, 9, 9> sensitivity_covariance(double scale_sigma, double cross_axis_sigma) {
  // Scale errors on the diagonal of S, cross-axis sensitivity off it, independent. The board's
  // mounting rotation is left out: it turns the gyro and the accelerometer together, and a
  // rotation of the whole IMU frame (S_g's antisymmetric part, the attitude and the accelerometer
  // bias together) is what no measurement sees; a prior along it let the aggressive mission's
  // filter wander 6 deg in roll (imu_mount_sigma widens the published attitude instead).
  Eigen::Matrix<double, 9, 1> d;
  for (int k = 0; k < 9; ++k) d(k) = k % 4 == 0 ? scale_sigma * scale_sigma : cross_axis_sigma * cross_axis_sigma;
  return d.asDiagonal();
}
}  // namespace

bool Estimator::still() const {
  if (pre_init_imu_.empty()) return false;
  // the last second of samples
  const Nanos newest = pre_init_imu_.back().stamp;
  const auto last_second = [newest](const ImuRecord& r) { return newest - r.stamp <= kNanosPerSecond; };
  Vec3 mean = Vec3::Zero();
  std::size_t n = 0;
  for (const ImuRecord& r : pre_init_imu_)
    if (last_second(r)) mean += r.gyro, ++n;
  mean /= static_cast<double>(n);
  double sq = 0.0;
  for (const ImuRecord& r : pre_init_imu_)
    if (last_second(r)) sq += (r.gyro - mean).squaredNorm();
  const double rms = std::sqrt(sq / static_cast<double>(n));
  return mean.norm() < cfg_.rest_rate_max && rms < cfg_.rest_rate_max;
}

std::optional<Vec3> Estimator::mean_specific_force(Nanos t0, Nanos t1) const {
  Vec3 sum = Vec3::Zero();
  int n = 0;
  for (const ImuRecord& r : pre_init_imu_) {
    if (r.stamp > t0 && r.stamp <= t1) {
      sum += r.accel;
      ++n;
    }
  }
  if (n == 0) return std::nullopt;
  return sum / n;
}

void Estimator::try_initialize(const msg::Gnss& m, const Vec3& p_ned, Nanos t_v) {
  if (imu_samples_ < cfg_.init_min_imu_samples) return;
  const bool have_mag = mag_samples_ > 0;
  if (!have_mag && expect_mag_ && to_seconds(m.stamp - origin_stamp_) < cfg_.mag_init_wait) return;

  // Moving: the specific force is not gravity alone. With the fix before this one (at most
  // kMaxInitFixGap old) the kinematic acceleration is the GNSS velocity difference, and the attitude
  // comes from the specific force in both frames plus the field; without it, wait for the next fix.
  const bool moving = m.vel.norm() >= 0.5;
  const double dt_fix = prev_fix_tv_ < 0 ? 0.0 : to_seconds(t_v - prev_fix_tv_);
  const std::optional<Vec3> f_body = dt_fix > 0.0 && dt_fix <= kMaxInitFixGap ? mean_specific_force(prev_fix_tv_, t_v) : std::nullopt;
  if (moving && !f_body) return;

  NominalState x;
  double yaw_sigma = cfg_.init_yaw_sigma;
  if (have_mag && moving) {
    const Vec3 f_ned = (m.vel - prev_fix_vel_) / dt_fix - Vec3(0.0, 0.0, cfg_.gravity);
    const Vec3 m_ned = field_direction_ned(field_.declination, field_.inclination);
    try {
      x.q = attitude_triad(*f_body, f_ned, mag_avg_, m_ned);
    } catch (const std::invalid_argument&) {  // specific force along the field: no better than level
      x.q = attitude_from_accel_mag(accel_avg_, mag_avg_, field_.declination);
    }
  } else if (have_mag) {
    x.q = attitude_from_accel_mag(accel_avg_, mag_avg_, field_.declination);
  } else if (m.vel.head<2>().norm() > 3.0) {
    x.q = attitude_from_accel(accel_avg_, std::atan2(m.vel.y(), m.vel.x()));
    yaw_sigma = 0.5;
  } else {
    x.q = attitude_from_accel(accel_avg_, 0.0);
    yaw_sigma = 1.0;
  }
  // Not accelerating (the averaged specific force is gravity: roll and pitch from it), and at rest
  // only if also held still (the averaged rate is the gyro bias); a hand-held aircraft turning
  // slowly before its launch is the former, not the latter.
  const bool unaccelerated = m.vel.norm() < 0.5 && std::fabs(accel_avg_.norm() - cfg_.gravity) < 0.5;
  const bool at_rest = unaccelerated && still();
  x.p = p_ned - x.q * cfg_.gnss_antenna + m.vel * to_seconds(std::max<Nanos>(imu_stamp_ - t_v, 0));
  x.v = m.vel;
  x.b_g = at_rest ? gyro_avg_ : Vec3::Zero();

  Cov P0 = Cov::Zero();
  const double sh = cfg_.gnss_pos_sigma_h, sv = cfg_.gnss_pos_sigma_v;
  P0.diagonal().segment<3>(idx::p) << sh * sh, sh * sh, sv * sv;
  const double vh = std::max(cfg_.gnss_vel_sigma_h, 0.05), vv = std::max(cfg_.gnss_vel_sigma_v, 0.05);
  P0.diagonal().segment<3>(idx::v) << vh * vh, vh * vh, vv * vv;
  // Tilt and yaw uncertainty are about NED axes: P_theta(body) = R^T diag(t^2, t^2, y^2) R.
  const Mat3 R = x.R();
  // In flight the averaged specific force is not gravity (turns, pull-ups) and the levelled
  // field carries that tilt error into yaw: start with wide attitude uncertainty and let GNSS
  // velocity and the air data pull the attitude in.
  // 0.4 rad: above max_tilt_sigma's default (0.35), so that such a start is invalid until the GNSS
  // velocity has brought the tilt in, rather than valid, invalid and valid again as the first
  // propagation grows it past the threshold (the Zurich 2014 hand launch, initialised walking).
  const double tilt_sigma = unaccelerated ? cfg_.init_tilt_sigma : std::max(cfg_.init_tilt_sigma, 0.4);
  if (!unaccelerated) yaw_sigma = std::max(yaw_sigma, 0.6);
  const double t2 = tilt_sigma * tilt_sigma;
  const Mat3 Pg = Vec3(t2, t2, yaw_sigma * yaw_sigma).asDiagonal();
  P0.block<3, 3>(idx::th, idx::th) = R.transpose() * Pg * R;
  const double gb = at_rest ? cfg_.init_gyro_bias_sigma : std::max(cfg_.init_gyro_bias_sigma, 0.05);
  P0.diagonal().segment<3>(idx::bg).setConstant(gb * gb);
  P0.diagonal().segment<3>(idx::ba).setConstant(cfg_.init_accel_bias_sigma * cfg_.init_accel_bias_sigma);
  if (cfg_.accel_level_calibrated) {  // the board's tilt in the offset: b_x = -g mu_pitch, b_y = g mu_roll
    const Vec3 gm = cfg_.gravity * cfg_.imu_mount_sigma;
    P0(idx::ba, idx::ba) += gm.y() * gm.y();
    P0(idx::ba + 1, idx::ba + 1) += gm.x() * gm.x();
  }
  P0.block<9, 9>(idx::sg, idx::sg) = sensitivity_covariance(cfg_.init_gyro_scale_sigma, cfg_.init_gyro_cross_axis_sigma);
  P0.diagonal().segment<3>(idx::bm).setConstant(cfg_.init_mag_bias_sigma * cfg_.init_mag_bias_sigma);
  double wind_sigma = cfg_.init_wind_sigma;
  const double Va = pitot_.airspeed(last_diff_pressure_);
  if (last_diff_stamp_ >= 0 && to_seconds(m.stamp - last_diff_stamp_) < 0.5 && Va >= cfg_.min_airspeed) {
    x.wind = (m.vel - Va * (x.q * Vec3::UnitX())).head<2>();
    // the wind from the air-data triangle inherits the yaw uncertainty: Va * sigma_psi across
    wind_sigma = std::hypot(cfg_.init_wind_sigma_airdata, unaccelerated ? 0.0 : Va * yaw_sigma);
  }
  P0.diagonal().segment<2>(idx::w).setConstant(wind_sigma * wind_sigma);
  P0(idx::bb, idx::bb) = cfg_.init_baro_bias_sigma * cfg_.init_baro_bias_sigma;
  P0(idx::sp, idx::sp) = cfg_.init_static_error_sigma * cfg_.init_static_error_sigma;
  P0(idx::wd, idx::wd) = cfg_.process.vertical_wind_sigma * cfg_.process.vertical_wind_sigma;
  // p = z - e_gnss: the absolute position is as uncertain as the GNSS error, and p + e_gnss
  // (what the receiver measures) only as the white part.
  const Vec3 e2 = gnss_error_variance();
  P0.diagonal().segment<3>(idx::eg) = e2;
  P0.diagonal().segment<3>(idx::p) += e2;
  P0.block<3, 3>(idx::p, idx::eg) = Mat3((-e2).asDiagonal());
  P0.block<3, 3>(idx::eg, idx::p) = Mat3((-e2).asDiagonal());
  if (keep_calibration_) keep_calibration(x, P0);
  keep_calibration_ = false;
  filter_.initialize(x, P0);
  history_.clear();
  initialized_ = true;
  inflight_yaw_aligned_ = false;  // a yaw from the magnetometer (or none): the first fixes in flight confirm it
  init_stamp_ = m.stamp;
  mag_reject_since_ = mag_slot_ = -1;
  gnss_reject_since_ = -1;
  rate_ = x.rate(imu_samples_ > 0 ? gyro_avg_ : Vec3::Zero());
  push(m.stamp, EventKind::initialized, Sensor::gnss, have_mag ? 1.0 : 0.0);
}

void Estimator::keep_calibration(NominalState& x, Cov& P0) const {
  // The sensor states and their covariance among themselves, from the filter before the
  // re-initialisation; their correlations with the (new) navigation states start at zero.
  const NominalState& old = filter_.x();
  x.b_g = old.b_g;
  x.b_a = old.b_a;
  x.S_g = old.S_g;
  x.b_m = old.b_m;
  x.k_sp = old.k_sp;
  static constexpr std::array<std::pair<int, int>, 5> kBlocks{{{idx::bg, 3}, {idx::ba, 3}, {idx::sg, 9}, {idx::bm, 3}, {idx::sp, 1}}};
  for (const auto& [i0, ni] : kBlocks) {
    P0.middleRows(i0, ni).setZero();
    P0.middleCols(i0, ni).setZero();
  }
  for (const auto& [i0, ni] : kBlocks)
    for (const auto& [j0, nj] : kBlocks) P0.block(i0, j0, ni, nj) = filter_.P().block(i0, j0, ni, nj);
}

}  // namespace tern::ekf
