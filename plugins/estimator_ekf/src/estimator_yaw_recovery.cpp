// Estimator: the yaw resets' two judgments (issue 61, aerobatics): whether the GNSS course may
// blame the yaw for rejected velocity (a manoeuvre the receiver lagged may not), and when a
// magnetometer stopped by a yaw reset is consistent again and resumes (see estimator.hpp).
#include <algorithm>
#include <cmath>

#include "tern/estimator_ekf/estimator.hpp"
#include "tern/math.hpp"

namespace tern::ekf {

namespace {
constexpr double kCourseMinSpeed = 5.0;                 // m/s: below it a fix's course is noise
constexpr double kCourseMaxPitch = 45.0 * kRadPerDeg;   // beyond it the course is not the heading
constexpr double kHeadingMaxPitch = 60.0 * kRadPerDeg;  // beyond it the Euler yaw is ill-conditioned
}  // namespace

void Estimator::watch_course(const msg::Gnss& m, bool restart) {
  const double speed = m.vel.head<2>().norm();
  const double course = std::atan2(m.vel.y(), m.vel.x());
  const double pitch = euler_from_quaternion(filter_.x().q).y();
  if (restart) course_ = CourseWatch{};
  if (speed < kCourseMinSpeed || std::fabs(pitch) > kCourseMaxPitch) course_.not_heading = true;
  if (course_.prev_stamp >= 0 && m.stamp > course_.prev_stamp && speed >= kCourseMinSpeed) {
    const double rate = std::fabs(wrap_pi(course - course_.prev)) / to_seconds(m.stamp - course_.prev_stamp);
    course_.rate_max = std::max(course_.rate_max, rate);
  }
  course_.prev = course;
  course_.prev_stamp = speed >= kCourseMinSpeed ? m.stamp : -1;
}

bool Estimator::align_yaw_in_flight(UpdateResult rv, const msg::Gnss& m, const Vec3& p, Nanos t_v) {
  // In motion, not airborne(): a hand launch reaches the 5 m/s below a fix before the pitot's
  // min_airspeed (config, launch_course_error).
  if (inflight_yaw_aligned_ || cfg_.launch_course_error <= 0.0) return false;
  const Eigen::Vector2d v_gnss = m.vel.head<2>(), v = filter_.x().v.head<2>();
  const Vec3 e = euler_from_quaternion(filter_.x().q);
  if (v_gnss.norm() < kCourseMinSpeed || v.norm() < kCourseMinSpeed || std::fabs(e.y()) > kCourseMaxPitch) return false;
  // The launch threw the aircraft along its nose: the filter's velocity has the direction of its
  // yaw, the receiver's the true one; their difference is the yaw's error (PX4 ecl realignYawGPS,
  // first alignment: "euler321(2) += courseYawError").
  const double d = wrap_pi(std::atan2(v_gnss.y(), v_gnss.x()) - std::atan2(v.y(), v.x()));
  if (std::fabs(d) <= cfg_.launch_course_error) {
    inflight_yaw_aligned_ = rv == UpdateResult::accepted;
    return false;
  }
  if (rv != UpdateResult::rejected) return false;
  reset_yaw_to_gnss(m.stamp, p, m, t_v, EventKind::launch_yaw_alignment, e.z() + d, cfg_.gnss_yaw_sigma);
  return true;
}

bool Estimator::yaw_blamed_on_course(double yaw_error, double sigma) const {
  if (cfg_.gnss_course_lag <= 0.0) return std::fabs(yaw_error) > sigma;  // the course as it is
  if (course_.not_heading) return false;
  return std::fabs(yaw_error) > sigma + cfg_.gnss_course_lag * course_.rate_max;
}

void Estimator::test_stopped_mag(Nanos stamp, const Vec3& z) {
  if (cfg_.mag_resume_time <= 0.0) return;
  const Vec3 e = euler_from_quaternion(filter_.x().q);
  if (std::fabs(e.y()) > kHeadingMaxPitch) return;  // neither passes nor fails
  const Mat3 R = filter_.x().R();
  const double yaw_var = (R * filter_.P().block<3, 3>(idx::th, idx::th) * R.transpose())(2, 2);
  const double innovation = wrap_pi(MagHeading::heading_from_field(z - filter_.x().b_m, e.x(), e.y(), field_.declination) - e.z());
  const bool consistent = yaw_var < cfg_.mag_resume_yaw_sigma * cfg_.mag_resume_yaw_sigma && std::fabs(innovation) <= cfg_.mag_resume_error;
  if (!consistent) {
    mag_consistent_since_ = -1;
    return;
  }
  if (mag_consistent_since_ < 0) mag_consistent_since_ = stamp;
  if (to_seconds(stamp - mag_consistent_since_) < cfg_.mag_resume_time) return;
  mag_inhibited_ = false;
  mag_consistent_since_ = -1;
  mag_reject_since_ = -1;
  mag_heading_.stats.consecutive_rejected = 0;
  mag_.stats.consecutive_rejected = 0;
  ++mag_resumes_;
  push(stamp, EventKind::mag_resumed, Sensor::mag, to_seconds(stamp - mag_inhibited_since_));
}

}  // namespace tern::ekf
