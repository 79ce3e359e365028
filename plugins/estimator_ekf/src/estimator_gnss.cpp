// Estimator: GNSS fixes: fusion, reported accuracies, resets to the fix (see estimator.hpp).
#include "tern/estimator_ekf/estimator.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "tern/math.hpp"
#include "estimator_fusion.hpp"

namespace tern::ekf {

namespace {
/// s: a receiver reports its fix within its navigation latency of the epoch it holds for (tens to a
/// few hundred ms; tern's configs and docs use 0.12 s (a u-blox M8N) and 0.21 s); a time_of_validity
/// further back is on another clock (a GPS time of week, a boot time), and taken, it held every fix
/// as too old for the filter's history.
constexpr double kMaxGnssEpochAge = 1.0;
}  // namespace

Nanos Estimator::gnss_epoch(const msg::Gnss& m) {
  if (m.time_of_validity <= 0) return m.stamp;  // not given
  const double age = to_seconds(m.stamp - m.time_of_validity);
  if (age >= 0.0 && age <= kMaxGnssEpochAge) return m.time_of_validity;
  if (!epoch_ignored_) push(m.stamp, EventKind::gnss_epoch_ignored, Sensor::gnss, age);
  epoch_ignored_ = true;
  return m.stamp;
}

bool Estimator::add_gnss(const msg::Gnss& fix) {
  // Without the receiver's down velocity (use_gnss_vel_d false) the fix's vel_d is not data:
  // everything below takes the estimate's (0 before initialisation), and the update fuses
  // north and east only.
  msg::Gnss m = fix;
  if (!cfg_.use_gnss_vel_d) m.vel.z() = initialized_ ? filter_.x().v.z() : 0.0;
  const bool poor = gnss_checks_.passed() && !cfg_.gnss_checks.usable_in_flight(m.h_acc, m.v_acc, m.s_acc);
  if (static_cast<int>(m.fix_type) < cfg_.min_fix_type || poor) {
    ++counters_[static_cast<int>(Sensor::gnss)].received;  // no fix, or one its receiver calls poor: not usable, not invalid
    if (!gnss_checks_.passed()) check_gnss_start(m, false);
    return false;
  }
  const bool ok = std::isfinite(m.lat) && std::isfinite(m.lon) && std::isfinite(m.alt) && m.vel.allFinite() &&
                  std::fabs(m.lat) <= msg::kGnssMaxAbsLat && std::fabs(m.lon) <= msg::kGnssMaxAbsLon && m.alt > msg::kGnssMinAlt &&
                  m.alt < msg::kGnssMaxAlt && m.vel.norm() < msg::kGnssMaxSpeed;
  const bool was_timed_out = counters_[static_cast<int>(Sensor::gnss)].timed_out;
  if (!accept(Sensor::gnss, m.stamp, ok)) return false;
  // The receiver has to settle first: fixes that fail a start-up check count (received,
  // time-outs) but are not used.
  if (!gnss_checks_.passed() && !check_gnss_start(m, true)) return false;
  // The receiver's epoch when the driver gives it (sim_aero does; over ROSflight's link it is
  // the stamp), minus the configured delay.
  const Nanos epoch = gnss_epoch(m);
  const Nanos t_v = valid_at(Sensor::gnss, epoch);
  const Vec3 p_before = filter_.x().p;
  if (!origin_) {
    origin_.emplace(m.lat, m.lon, m.alt);
    started_in_air_ = !gnss_checks_.passed() && gnss_check_motion(m) == GnssChecks::Motion::in_air;
    origin_lat_ = m.lat;
    origin_lon_ = m.lon;
    origin_alt_ = m.alt;
    origin_stamp_ = m.stamp;
    push(m.stamp, EventKind::origin_set, Sensor::gnss, to_seconds(m.stamp - gnss_checks_.first_stamp()));  // provisional until passed
    // The GNSS altitude is above mean sea level, the model's height above the ellipsoid: the
    // geoid's undulation (tens of metres) changes the field by a few nT of ~50000.
    if (cfg_.mag_field_from_model) set_earth_field(tern::world_magnetic_field(m.lat, m.lon, m.alt, cfg_.mag_model_date));
  }
  const Vec3 p = ned_from_geodetic(m.lat, m.lon, m.alt);
  if (cfg_.use_gnss_accuracy) use_reported_accuracy(m);
  if (!initialized_) {
    try_initialize(m, p, t_v);
    prev_fix_vel_ = m.vel;
    prev_fix_tv_ = t_v;
    return true;
  }
  set_gnss_noise();
  if (cfg_.gnss_constellation_jumps) add_constellation_jump(m);
  const UpdateResult r = fuse_robust(Sensor::gnss, gnss_pos_, p, t_v, idx::p, 3);
  if (r == UpdateResult::invalid && history_.full()) {
    push(m.stamp, EventKind::too_old, Sensor::gnss, to_seconds(imu_stamp_ - t_v));
  }
  if (r == UpdateResult::rejected) {
    if (gnss_reject_since_ < 0) gnss_reject_since_ = m.stamp;
    const double innovation = (p - gnss_pos_.h(filter_.x())).norm();
    // a fix its receiver marks degraded is fused (within its reported accuracy) but resets the
    // position only when the estimate itself is lost (further from it than gnss_fault_distance)
    const bool trusted = !gnss_checks_.degraded(m) || innovation > cfg_.gnss_fault_distance;
    if (to_seconds(m.stamp - gnss_reject_since_) > cfg_.gnss_reset_time && trusted && gnss_reset_allowed(m.stamp, innovation)) {
      reset_to_gnss(m.stamp, p, m.vel, t_v);
      push(m.stamp, EventKind::gnss_reset, Sensor::gnss, innovation);
      return true;
    }
  } else if (r == UpdateResult::accepted) {
    gnss_reject_since_ = -1;
  }
  // Velocity is not inflated: a rejected velocity usually means a manoeuvre the IMU model did
  // not follow, and inflating velocity (with its correlation to attitude) lets one fix swing
  // the attitude.
  UpdateResult rv = cfg_.use_gnss_vel_d ? fuse(gnss_vel_, m.vel, t_v) : fuse_gnss_velocity_ne(m.vel, t_v);
  // Three axes rejected: the north and east alone, as PX4 EKF2 gates the horizontal velocity and
  // the vertical apart. A receiver's down velocity lags most in a pull (its dynamic model; the
  // barometer follows the climb): on the PX4 Zurich 2014 flight's 4-g pull at 70 s it was 5 m/s
  // behind, the three axes were rejected for 1.2 s and the horizontal, unaided, drifted 5 m/s
  // until recover_velocity reset it.
  if (rv == UpdateResult::rejected && cfg_.use_gnss_vel_d && fuse_gnss_velocity_ne(m.vel, t_v) == UpdateResult::accepted)
    rv = UpdateResult::accepted;
  if (align_yaw_in_flight(rv, m, p, t_v)) return true;
  if (recover_velocity(rv, m, p, t_v)) return true;
  if (check_yaw_with_gsf(m, p, t_v)) return true;
  // First GNSS after a time-out: hide the position jump from the output, then let it decay.
  if (was_timed_out && cfg_.gnss_recovery_time > 0.0) output_offset_ -= filter_.x().p - p_before;
  return true;
}

bool Estimator::check_gnss_start(const msg::Gnss& m, bool usable) {
  const bool passed = gnss_checks_.update(m, usable, gnss_check_motion(m));
  if (passed) {
    push(m.stamp, EventKind::gnss_checks_passed, Sensor::gnss, to_seconds(m.stamp - gnss_checks_.first_stamp()));
    return true;
  }
  // What fails while waiting: when it changes, at most every report_interval.
  const std::uint32_t failing = gnss_checks_.failing();
  const bool due = checks_reported_ < 0 || to_seconds(m.stamp - checks_reported_) >= cfg_.gnss_checks.report_interval;
  if (failing != reported_failing_ && due) {
    push(m.stamp, EventKind::gnss_checks_failing, Sensor::gnss, static_cast<double>(failing));
    reported_failing_ = failing;
    checks_reported_ = m.stamp;
  }
  // Every check passing, not yet for hold_time: the estimator starts (or goes on) on these fixes,
  // its state invalid until they have held; a failure drops what they started.
  if (failing == 0) return true;
  if (origin_) drop_unsettled_start(m.stamp);
  return false;
}

void Estimator::drop_unsettled_start(Nanos stamp) {
  // The origin, the filter and the barometer's calibration, as before the first fix; the IMU's
  // averages start again (imu_samples_), the counters and the checks go on.
  push(stamp, EventKind::origin_dropped, Sensor::gnss);
  origin_.reset();
  started_in_air_ = false;
  initialized_ = false;
  keep_calibration_ = false;
  imu_samples_ = 0;
  mag_samples_ = 0;
  pre_init_imu_.clear();
  prev_fix_tv_ = -1;
  history_.clear();
  baro_calibrated_ = false;
  baro_cal_count_ = 0;
  baro_cal_sum_ = baro_cal_q_sum_ = baro_offset_ = 0.0;
  output_offset_.setZero();
  gnss_reject_since_ = gnss_vel_reject_since_ = mag_reject_since_ = -1;
}

GnssChecks::Motion Estimator::gnss_check_motion(const msg::Gnss& m) const {
  // Flying: the pitot's airspeed (its last sample, at most 0.5 s old) or the ground speed says so;
  // on the ground, still by the gyro over the last second (still(), as for the initial gyro bias).
  const bool pitot_flying =
      last_diff_stamp_ >= 0 && to_seconds(m.stamp - last_diff_stamp_) < 0.5 && pitot_.airspeed(last_diff_pressure_) >= cfg_.min_airspeed;
  if (pitot_flying || m.vel.head<2>().norm() >= cfg_.gnss_checks.in_air_ground_speed) return GnssChecks::Motion::in_air;
  return still() ? GnssChecks::Motion::at_rest : GnssChecks::Motion::moving;
}

UpdateResult Estimator::fuse_gnss_velocity_ne(const Vec3& vel, Nanos t_v) {
  gnss_vel_ne_.full = gnss_vel_;  // its antenna, gyro and noise, as set for this fix
  return fuse(gnss_vel_ne_, GnssVelocityNE::Vec(vel.head<2>()), t_v);
}

void Estimator::use_reported_accuracy(const msg::Gnss& m) {
  // The GNSS error state is a Gauss-Markov process of rate k whose steady sigma is
  // walk / sqrt(2 k): the reported accuracy (at least the floor) sets the walk. The receiver's
  // speed accuracy is the velocity noise where larger than the configured one (its velocity
  // errors are correlated, EstimatorConfig::gnss_vel_sigma_h).
  const double sqrt_two_k = std::sqrt(2.0 * cfg_.process.gnss_error_k);
  reported_h_acc_ = m.h_acc > 0.0 && std::isfinite(m.h_acc);
  reported_s_acc_ = m.s_acc > 0.0 && std::isfinite(m.s_acc);
  if (m.h_acc > 0.0 && std::isfinite(m.h_acc)) process_.gnss_error_walk_h = std::max(cfg_.gnss_accuracy_floor, m.h_acc) * sqrt_two_k;
  if (m.v_acc > 0.0 && std::isfinite(m.v_acc)) process_.gnss_error_walk_v = std::max(cfg_.gnss_accuracy_floor, m.v_acc) * sqrt_two_k;
  if (m.s_acc > 0.0 && std::isfinite(m.s_acc)) {
    gnss_vel_sigma_h_ = std::max(cfg_.gnss_vel_sigma_h, m.s_acc);
    gnss_vel_sigma_v_ = std::max(cfg_.gnss_vel_sigma_v, m.s_acc);
  }
}

void Estimator::add_constellation_jump(const msg::Gnss& m) {
  // A fix from another set of satellites (their count or the reported dilution changed) is
  // another solution. For nested sets (satellites lost or regained) the larger set's error e_L
  // and the smaller's e_S = e_L + d differ by d, independent of e_L, whose covariance is the
  // difference of the two solutions' (least squares from a subset of the ranges; Kaplan &
  // Hegarty sec. 11.2): per axis, the difference of the reported accuracies squared, s_S^2 - s_L^2.
  // To a worse set: e <- e + d, the GNSS error state's variance grows by it. To a better set:
  // e_L = (s_L^2 / s_S^2) e_S + w, Var(w) = s_L^2 (1 - s_L^2 / s_S^2): the state shrinks towards
  // zero, and so does its covariance. Either way the jump moves e_gnss, not the position, and is
  // not rejected as an outlier.
  const Vec3 steady = gnss_error_variance();
  const double floor2 = cfg_.gnss_accuracy_floor * cfg_.gnss_accuracy_floor;
  const double h2 = reported_h_acc_ ? std::max(m.h_acc * m.h_acc, floor2) : steady.x();
  const Vec3 acc2(h2, h2, m.v_acc > 0.0 && std::isfinite(m.v_acc) ? std::max(m.v_acc * m.v_acc, floor2) : steady.z());
  const bool changed = prev_num_sats_ >= 0 && (m.num_sats != prev_num_sats_ || m.hdop != prev_hdop_);
  const Vec3 before = prev_acc2_;
  prev_num_sats_ = m.num_sats;
  prev_hdop_ = m.hdop;
  prev_acc2_ = acc2;
  if (!changed) return;
  Vec3 a = Vec3::Ones(), q = Vec3::Zero();
  for (int i = 0; i < 3; ++i) {
    if (acc2(i) >= before(i)) {
      q(i) = acc2(i) - before(i);
    } else {
      a(i) = acc2(i) / before(i);
      q(i) = acc2(i) * (1.0 - a(i));
    }
  }
  ErrVec dx = ErrVec::Zero();
  dx.segment<3>(idx::eg) = (a - Vec3::Ones()).cwiseProduct(filter_.x().e_gnss);
  filter_.inject(dx);
  filter_.scale_covariance(idx::eg, a);
  filter_.add_variance(idx::eg, q);
  ++constellation_jumps_;
}

void Estimator::set_gnss_noise() {
  // Only for what the receiver does not report: its own accuracies already grow with its
  // dynamics (u-blox hAcc, vAcc, sAcc).
  const double dv = cfg_.gnss_vel_accel_scale * accel_nav_, dp = cfg_.gnss_pos_accel_scale * accel_nav_;
  gnss_vel_.sigma_h = reported_s_acc_ ? gnss_vel_sigma_h_ : std::hypot(gnss_vel_sigma_h_, dv);
  gnss_vel_.sigma_v = reported_s_acc_ ? gnss_vel_sigma_v_ : std::hypot(gnss_vel_sigma_v_, dv);
  // Without a reported accuracy the fix's white noise is at least the floor: PX4 EKF2 takes
  // EKF2_GPS_P_NOISE (0.5 m) as the noise of a fix without hAcc, ArduPilot EKF3 EK3_POSNE_M_NSE.
  const double floor = cfg_.gnss_accuracy_floor;
  gnss_pos_.sigma_h = reported_h_acc_ ? cfg_.gnss_pos_sigma_h : std::hypot(std::max(cfg_.gnss_pos_sigma_h, floor), dp);
  gnss_pos_.sigma_v = reported_h_acc_ ? cfg_.gnss_pos_sigma_v : std::hypot(std::max(cfg_.gnss_pos_sigma_v, floor), dp);
}

Vec3 Estimator::gnss_error_variance() const {
  // The GNSS error's steady variance walk^2 / (2 k), at least init_gnss_error_sigma^2.
  const double two_k = 2.0 * process_.gnss_error_k;
  const double floor = cfg_.init_gnss_error_sigma * cfg_.init_gnss_error_sigma;
  const auto steady = [&](double walk) { return two_k > 0.0 ? std::max(floor, walk * walk / two_k) : floor; };
  const double h = steady(process_.gnss_error_walk_h);
  return {h, h, steady(process_.gnss_error_walk_v)};
}

bool Estimator::gnss_reset_allowed(Nanos stamp, double innovation) const {
  // At most one reset per reset_min_interval: a second one soon after means the filter and the
  // receiver disagree for a reason a reset does not cure (latency, a lever arm, a multipath
  // episode), and covariance inflation has to carry it. A position lost by more than
  // gnss_fault_distance is reset at once.
  return last_gnss_reset_ < 0 || to_seconds(stamp - last_gnss_reset_) >= cfg_.reset_min_interval || innovation > cfg_.gnss_fault_distance;
}

void Estimator::reset_to_gnss(Nanos stamp, const Vec3& p, const Vec3& vel, Nanos t_v) {
  // The fix, valid at t_v, carried to now; applied as a correction so that the history's
  // delayed updates see it (Filter::inject adds it to the correction sum).
  const NominalState& x = filter_.x();
  ErrVec dx = ErrVec::Zero();
  dx.segment<3>(idx::p) = p - x.q * cfg_.gnss_antenna + vel * to_seconds(imu_stamp_ - t_v) - x.p;
  dx.segment<3>(idx::v) = vel - x.v;
  dx.segment<3>(idx::eg) = -x.e_gnss;
  filter_.inject(dx);
  Cov& P = filter_.mutable_P();
  P.middleRows<6>(idx::p).setZero();
  P.middleCols<6>(idx::p).setZero();
  P.middleRows<3>(idx::eg).setZero();
  P.middleCols<3>(idx::eg).setZero();
  // As at initialisation: p = z - e_gnss, e_gnss at its steady sigma.
  const double sh = cfg_.gnss_pos_sigma_h, sv = cfg_.gnss_pos_sigma_v;
  const Vec3 e2 = gnss_error_variance();
  P.diagonal().segment<3>(idx::p) = Vec3(sh * sh, sh * sh, sv * sv) + e2;
  P.diagonal().segment<3>(idx::v) << 1.0, 1.0, 1.0;
  P.diagonal().segment<3>(idx::eg) = e2;
  P.block<3, 3>(idx::p, idx::eg) = Mat3((-e2).asDiagonal());
  P.block<3, 3>(idx::eg, idx::p) = Mat3((-e2).asDiagonal());
  gnss_pos_.stats.consecutive_rejected = 0;
  gnss_reject_since_ = -1;
  last_gnss_reset_ = stamp;
  ++gnss_resets_;
}

}  // namespace tern::ekf
