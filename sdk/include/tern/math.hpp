// tern/math.hpp: rotations and angle helpers (Beard & McLain, ch. 2 and appendix B).
//
// Frames: NED inertial (x north, y east, z down), FRD body (x forward, y right, z down).
// Euler angles are the 3-2-1 (yaw psi, pitch theta, roll phi) sequence of the book, in radians.
// Quaternions are Eigen::Quaterniond (scalar w first in the book's e0 e1 e2 e3 order), rotating
// body vectors into NED: v_ned = q * v_body. All functions are header-only and allocation free.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tern {

inline constexpr double kPi = 3.14159265358979323846;
/// Radians per degree (pi / 180): an angle in degrees times kRadPerDeg is the angle in radians.
inline constexpr double kRadPerDeg = kPi / 180.0;
/// Degrees per radian (180 / pi): an angle in radians times kDegPerRad is the angle in degrees.
inline constexpr double kDegPerRad = 180.0 / kPi;
inline constexpr double kGravity = 9.81;  ///< m/s^2, the book's g
/// m/s^2, standard gravity g0 (3rd CGPM, 1901): a datasheet's "g", and the ROSflight firmware's
/// gravity (include/sensors.h, Sensors::gravity_, used by Sensors::calibrate_accel).
inline constexpr double kStandardGravity = 9.80665;

/// Wraps an angle to [-pi, pi). NaN stays NaN.
inline double wrap_pi(double a) {
  if (!std::isfinite(a)) return a;
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a < 0.0) a += 2.0 * kPi;
  return a - kPi;
}

/// Wraps an angle to [0, 2 pi) (the book's <x>, angle mod 2 pi, of Alg. 7). NaN stays NaN.
inline double wrap_2pi(double a) {
  if (!std::isfinite(a)) return a;
  a = std::fmod(a, 2.0 * kPi);
  if (a < 0.0) a += 2.0 * kPi;
  return a >= 2.0 * kPi ? 0.0 : a;  // a tiny negative input rounds up to 2 pi
}

/// Returns `a` shifted by a multiple of 2 pi so that |a - ref| <= pi: the form used for course
/// errors (Beard & McLain, section 10.2: chi_q is chosen so that |chi_q - chi| <= pi).
inline double unwrap_near(double a, double ref) { return ref + wrap_pi(a - ref); }

/// Rotation matrix body -> NED from Euler angles (Beard & McLain, eq. 2.4 transposed).
inline Eigen::Matrix3d rotation_from_euler(double phi, double theta, double psi) {
  const double cf = std::cos(phi), sf = std::sin(phi);
  const double ct = std::cos(theta), st = std::sin(theta);
  const double cp = std::cos(psi), sp = std::sin(psi);
  Eigen::Matrix3d R;
  R << ct * cp, sf * st * cp - cf * sp, cf * st * cp + sf * sp, ct * sp, sf * st * sp + cf * cp, cf * st * sp - sf * cp, -st, sf * ct,
      cf * ct;
  return R;
}

/// Quaternion body -> NED from Euler angles (Beard & McLain, eq. B.3).
inline Eigen::Quaterniond quaternion_from_euler(double phi, double theta, double psi) {
  const double c0 = std::cos(psi / 2), s0 = std::sin(psi / 2);
  const double c1 = std::cos(theta / 2), s1 = std::sin(theta / 2);
  const double c2 = std::cos(phi / 2), s2 = std::sin(phi / 2);
  return Eigen::Quaterniond(c0 * c1 * c2 + s0 * s1 * s2, c0 * c1 * s2 - s0 * s1 * c2, c0 * s1 * c2 + s0 * c1 * s2,
                            s0 * c1 * c2 - c0 * s1 * s2);
}

/// Euler angles (phi, theta, psi) in rad of a body -> NED quaternion (Beard & McLain, eq. B.1).
/// theta is in [-pi/2, pi/2]; at theta = +-pi/2 (gimbal lock) phi is reported as 0.
inline Eigen::Vector3d euler_from_quaternion(const Eigen::Quaterniond& q_in) {
  const Eigen::Quaterniond q = q_in.normalized();
  const double e0 = q.w(), e1 = q.x(), e2 = q.y(), e3 = q.z();
  const double s = std::clamp(2.0 * (e0 * e2 - e1 * e3), -1.0, 1.0);
  const double theta = std::asin(s);
  double phi = std::atan2(2.0 * (e0 * e1 + e2 * e3), e0 * e0 + e3 * e3 - e1 * e1 - e2 * e2);
  double psi = std::atan2(2.0 * (e0 * e3 + e1 * e2), e0 * e0 + e1 * e1 - e2 * e2 - e3 * e3);
  if (std::fabs(s) > 1.0 - 1e-12) phi = 0.0;
  return {phi, theta, psi};
}

/// Skew-symmetric (cross-product) matrix: skew(a) * b == a.cross(b).
inline Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d S;
  S << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return S;
}

/// Saturates x to [lo, hi].
inline double saturate(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }

}  // namespace tern
