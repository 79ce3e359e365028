// Estimator: the magnetometer, yaw resets and their recovery from the GNSS course and the yaw GSF (see estimator.hpp).
#include "tern/estimator_ekf/estimator.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "tern/math.hpp"
#include "estimator_fusion.hpp"

namespace tern::ekf {

namespace {
/// Share of mag_fusion_interval a sample may come before its slot and still take it (a stream at
/// the interval's rate keeps every sample through its stamps' jitter).
constexpr double kMagSlotEarly = 0.25;
}  // namespace

bool Estimator::add_mag(const msg::Mag& m) {
  const double n = m.field.norm();
  const bool ok = m.field.allFinite() && n > 1e-7 && n < 1e-3;
  if (!accept(Sensor::mag, m.stamp, ok)) return false;
  if (!initialized_) {
    const double a = mag_samples_ == 0 ? 1.0 : 0.1;
    mag_avg_ += a * (m.field - mag_avg_);
    ++mag_samples_;
    return true;
  }
  const Vec3 z = m.field / field_.intensity;  // in units of the Earth's field, like b_m
  if (mag_inhibited_) {
    test_stopped_mag(m.stamp, z);
    return true;
  }
  // At most one sample per mag_fusion_interval slot: each fused sample books the next slot one
  // interval after its own slot, not after the sample, so a stream at any faster rate averages the
  // interval's rate (60 Hz and 100 Hz alike: 50 a second); a slot more than an interval behind
  // (a gap) starts again from the sample.
  const Nanos interval = from_seconds(cfg_.mag_fusion_interval);
  if (mag_slot_ >= 0 && m.stamp >= mag_slot_ - interval && m.stamp < mag_slot_ - from_seconds(kMagSlotEarly * cfg_.mag_fusion_interval))
    return true;
  mag_slot_ =
      (mag_slot_ < 0 || m.stamp < mag_slot_ - interval || m.stamp - mag_slot_ > interval) ? m.stamp + interval : mag_slot_ + interval;
  const Vec3 e = euler_from_quaternion(filter_.x().q);
  const Nanos t_v = valid_at(Sensor::mag, m.stamp);
  // The field's direction in the air only (PX4 EKF2's automatic EKF2_MAG_TYPE): on the ground a
  // hangar's steel or a car bends it, and the heading alone keeps that out of roll and pitch.
  // After a resume (test_stopped_mag) only the heading was tested: the field's direction, which
  // also steers roll and pitch, stays out (a field off the model's, e.g. Zurich's 52 uT at 67.6 deg
  // against WMM's 47.8 uT at 63.3, worsened that flight's course 4.7 -> 4.9 deg as 3-axis).
  const bool heading = cfg_.mag_heading_only || !airborne(m.stamp) || mag_resumes_ > 0;
  if (heading) mag_heading_.tilt_variance = MagHeading::tilt_variance_of(z, e.x(), e.y(), filter_.P().block<3, 3>(idx::th, idx::th));
  const UpdateResult r = heading
                             ? fuse(mag_heading_, MagHeading::Vec(MagHeading::heading_from_field(z, e.x(), e.y(), field_.declination)), t_v)
                             : fuse(mag_, Magnetometer::Vec(z), t_v);
  // A heading the filter keeps rejecting means the filter locked onto a wrong (yaw, wind) pair
  // that GNSS velocity and the air data cannot tell apart (e.g. initialised while manoeuvring):
  // after mag_reset_time, trust the magnetometer again.
  if (r == UpdateResult::rejected) {
    if (mag_reject_since_ < 0) {
      mag_reject_since_ = m.stamp;
    } else if (to_seconds(m.stamp - mag_reject_since_) > cfg_.mag_reset_time && to_seconds(m.stamp - init_stamp_) < cfg_.mag_reset_window) {
      reset_yaw(m.stamp, MagHeading::heading_from_field(z - filter_.x().b_m, e.x(), e.y(), field_.declination), cfg_.init_yaw_sigma,
                EventKind::mag_reset);
    }
  } else if (r == UpdateResult::accepted) {
    mag_reject_since_ = -1;
  }
  return true;
}

void Estimator::reset_yaw(Nanos stamp, double psi, double sigma, EventKind why) {
  const bool from_gnss = why != EventKind::mag_reset;
  NominalState& x = filter_.mutable_x();
  const Vec3 e = euler_from_quaternion(x.q);
  const double innovation = wrap_pi(psi - e.z());
  x.q = quaternion_from_euler(e.x(), e.y(), psi);
  Cov& P = filter_.mutable_P();
  // attitude: keep roll and pitch uncertainty, yaw back to the initial figure, no correlations
  const Mat3 R = x.R();
  const Mat3 P_th_ned = R * P.block<3, 3>(idx::th, idx::th) * R.transpose();
  const double t2 = std::max(P_th_ned(0, 0), P_th_ned(1, 1));
  const double y2 = sigma * sigma;
  P.middleRows<3>(idx::th).setZero();
  P.middleCols<3>(idx::th).setZero();
  P.block<3, 3>(idx::th, idx::th) = R.transpose() * Vec3(t2, t2, y2).asDiagonal() * R;
  // wind: from the air-data triangle with the new heading when the pitot is recent
  double wind_sigma = cfg_.init_wind_sigma;
  if (airborne(stamp)) {
    x.wind = (x.v - last_Va_ * (x.q * Vec3::UnitX())).head<2>();
    wind_sigma = std::hypot(cfg_.init_wind_sigma_airdata, from_gnss ? last_Va_ * sigma : 0.0);
  }
  P.middleRows<2>(idx::w).setZero();
  P.middleCols<2>(idx::w).setZero();
  P.diagonal().segment<2>(idx::w).setConstant(wind_sigma * wind_sigma);
  mag_reject_since_ = -1;
  mag_heading_.stats.consecutive_rejected = 0;
  mag_.stats.consecutive_rejected = 0;
  ++(from_gnss ? gnss_yaw_resets_ : mag_resets_);
  push(stamp, why, from_gnss ? Sensor::gnss : Sensor::mag, innovation * 180.0 / tern::kPi);
}

std::pair<double, double> Estimator::gnss_yaw(const msg::Gnss& m) const {
  // The GSF's yaw when it has converged; else the course, which is the heading plus the wind's
  // crab angle (unknown here: within gnss_yaw_sigma).
  if (gsf_converged()) return {gsf_.yaw(), std::max(std::sqrt(gsf_.yaw_variance()), 0.03)};
  return {std::atan2(m.vel.y(), m.vel.x()), cfg_.gnss_yaw_sigma};
}

bool Estimator::gsf_converged() const { return gsf_.active() && gsf_.yaw_variance() < cfg_.gsf_max_sigma * cfg_.gsf_max_sigma; }

bool Estimator::recover_velocity(UpdateResult rv, const msg::Gnss& m, const Vec3& p, Nanos t_v) {
  if (rv == UpdateResult::accepted) gnss_vel_reject_since_ = -1;
  if (rv != UpdateResult::rejected) return false;
  watch_course(m, gnss_vel_reject_since_ < 0);
  if (gnss_vel_reject_since_ < 0) gnss_vel_reject_since_ = m.stamp;
  if (cfg_.gnss_yaw_reset_time <= 0.0 || !airborne(m.stamp) || m.vel.head<2>().norm() < 5.0 || gnss_checks_.degraded(m) ||
      to_seconds(m.stamp - gnss_vel_reject_since_) < cfg_.gnss_yaw_reset_time)
    return false;
  // The yaw is the likely cause only if it is further from the GNSS yaw than that can err: the
  // converged GSF's 3 sigma (at least 10 deg), or the crab angle's bound from the course plus
  // its lag in the manoeuvre (yaw_blamed_on_course: never in loops or vertical flight);
  // otherwise (a manoeuvre the receiver lagged) velocity and position alone.
  const auto [psi, sigma] = gnss_yaw(m);
  const double yaw_error = wrap_pi(psi - euler_from_quaternion(filter_.x().q).z());
  if (gsf_converged() ? std::fabs(yaw_error) > std::max(3.0 * sigma, 0.1745) : yaw_blamed_on_course(yaw_error, sigma)) {
    reset_yaw_to_gnss(m.stamp, p, m, t_v, EventKind::gnss_yaw_reset);
    return true;
  }
  // Within what the course's lag gives (the manoeuvring acceleration times gnss_course_lag) the
  // fix, not the state, is the likely one off: no reset; the timer runs on, so that a difference
  // that outlasts the manoeuvre resets at once.
  const double innovation = (m.vel - filter_.x().v).norm();
  if (innovation <= cfg_.gnss_course_lag * accel_nav_) return false;
  reset_to_gnss(m.stamp, p, m.vel, t_v);
  gnss_vel_reject_since_ = -1;
  push(m.stamp, EventKind::gnss_velocity_reset, Sensor::gnss, innovation);
  return true;
}

bool Estimator::check_yaw_with_gsf(const msg::Gnss& m, const Vec3& p, Nanos t_v) {
  if (!airborne(m.stamp) || cfg_.gsf_max_sigma <= 0.0) {
    gsf_.stop();
    gsf_disagree_since_ = -1;
    return false;
  }
  // The fix is valid at t_v, the GSF runs at the IMU's time: its age is noise in manoeuvres.
  const double age = to_seconds(std::max<Nanos>(imu_stamp_ - t_v, 0));
  gsf_.fuse_velocity(m.vel.head<2>(), std::hypot(std::max(gnss_vel_.sigma_h, 0.3), accel_nav_ * age));
  // A magnetometer the filter follows although the kinematics say otherwise (a compass mounted
  // turned, a motor's field): the filter's yaw and the converged GSF's disagree for
  // gsf_disagree_time. The velocity may stay accepted (the wind state absorbs the difference).
  if (mag_inhibited_ || cfg_.gsf_disagree_time <= 0.0 || !gsf_converged()) {
    gsf_disagree_since_ = -1;
    return false;
  }
  const Mat3 R = filter_.x().R();
  const double yaw_var = (R * filter_.P().block<3, 3>(idx::th, idx::th) * R.transpose())(2, 2);
  const double d = wrap_pi(gsf_.yaw() - euler_from_quaternion(filter_.x().q).z());
  if (std::fabs(d) <= std::max(3.0 * std::sqrt(gsf_.yaw_variance() + yaw_var), cfg_.gnss_yaw_sigma)) {
    gsf_disagree_since_ = -1;
    return false;
  }
  if (gsf_disagree_since_ < 0) gsf_disagree_since_ = m.stamp;
  if (to_seconds(m.stamp - gsf_disagree_since_) < cfg_.gsf_disagree_time) return false;
  reset_yaw_to_gnss(m.stamp, p, m, t_v, EventKind::gsf_yaw_reset);
  gsf_disagree_since_ = -1;
  return true;
}

void Estimator::reset_yaw_to_gnss(Nanos stamp, const Vec3& p, const msg::Gnss& m, Nanos t_v, EventKind why) {
  const auto [psi, sigma] = gnss_yaw(m);
  reset_yaw_to_gnss(stamp, p, m, t_v, why, psi, sigma);
}

void Estimator::reset_yaw_to_gnss(Nanos stamp, const Vec3& p, const msg::Gnss& m, Nanos t_v, EventKind why, double psi, double sigma) {
  // Velocity and position first (the wind then comes from the fix's velocity), then the yaw.
  reset_to_gnss(stamp, p, m.vel, t_v);
  reset_yaw(stamp, psi, sigma, why);
  if (!mag_inhibited_) mag_inhibited_since_ = stamp;
  mag_inhibited_ = true;
  mag_consistent_since_ = -1;
  gnss_vel_reject_since_ = -1;
  inflight_yaw_aligned_ = true;
}

}  // namespace tern::ekf
