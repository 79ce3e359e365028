#include "complementary_filter.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>  // cross product
#include "tern/math.hpp"

namespace tern_@NAME@ {
using tern::kPi;
using tern::kRadPerDeg;
using tern::wrap_pi;

void ComplementaryFilter::imu(double t, const Eigen::Vector3d& accel, const Eigen::Vector3d& gyro) {
  if (!accel.allFinite() || !gyro.allFinite() || !std::isfinite(t)) return;
  x_.p = gyro.x();
  x_.q = gyro.y();
  x_.r = gyro.z();
  // gravity direction in the body, centripetal term removed (a = omega x v - g_b, v = (Va, 0, 0))
  const Eigen::Vector3d g_b = gyro.cross(Eigen::Vector3d(x_.Va, 0.0, 0.0)) - accel;
  const double phi_a = std::atan2(g_b.y(), g_b.z());
  const double theta_a = std::atan2(-g_b.x(), std::hypot(g_b.y(), g_b.z()));
  if (!x_.attitude_valid) {
    x_.phi = phi_a;
    x_.theta = theta_a;
    x_.attitude_valid = true;
    last_imu_ = t;
    return;
  }
  const double dt = t - last_imu_;
  last_imu_ = t;
  if (!(dt > 0.0) || dt > 1.0) return;  // out of order or after a long gap: skip one sample
  const double sf = std::sin(x_.phi), cf = std::cos(x_.phi);
  const double ct = std::max(std::cos(x_.theta), 1e-3), tt = std::tan(x_.theta);
  x_.phi += dt * (x_.p + (x_.q * sf + x_.r * cf) * tt);
  x_.theta += dt * (x_.q * cf - x_.r * sf);
  x_.psi += dt * (x_.q * sf + x_.r * cf) / ct;
  const double k = std::min(dt / prm_.tau_att, 1.0);
  x_.phi = wrap_pi(x_.phi + k * wrap_pi(phi_a - x_.phi));
  x_.theta = std::clamp(x_.theta + k * (theta_a - x_.theta), -kPi / 2, kPi / 2);
  x_.psi = wrap_pi(x_.psi);
  // dead reckoning between GNSS fixes
  x_.p_n += dt * x_.v_n;
  x_.p_e += dt * x_.v_e;
  x_.p_d += dt * x_.v_d;
}

void ComplementaryFilter::gnss(const Eigen::Vector3d& p_ned, const Eigen::Vector3d& v_ned) {
  if (!p_ned.allFinite() || !v_ned.allFinite()) return;
  const double w = x_.position_valid ? prm_.gnss_blend : 1.0;
  x_.p_n += w * (p_ned.x() - x_.p_n);
  x_.p_e += w * (p_ned.y() - x_.p_e);
  x_.p_d += w * (p_ned.z() - x_.p_d);
  x_.v_n = v_ned.x();
  x_.v_e = v_ned.y();
  x_.v_d = v_ned.z();
  const double Vg = std::hypot(v_ned.x(), v_ned.y());
  if (Vg >= prm_.min_gnss_speed) {
    const double chi = std::atan2(v_ned.y(), v_ned.x());
    // first fix with speed: take the course; afterwards, correct with time constant tau_psi (10 Hz fixes)
    const double k = x_.position_valid ? std::min(0.1 / prm_.tau_psi, 1.0) : 1.0;
    x_.psi = wrap_pi(x_.psi + k * wrap_pi(chi - x_.psi));
  }
  x_.position_valid = true;
}

void ComplementaryFilter::airspeed(double dp, double rho) {
  if (!std::isfinite(dp)) return;
  const double r = rho > 0.0 && std::isfinite(rho) ? rho : prm_.rho_default;
  x_.Va = std::sqrt(2.0 * std::max(dp, 0.0) / r);
}

Eigen::Vector3d geodetic_to_ned(double lat, double lon, double alt, double lat0, double lon0, double alt0) {
  // WGS-84 radii of curvature at the origin (meridian M and prime vertical N)
  constexpr double a = 6378137.0, e2 = 6.69437999014e-3;
  const double s = std::sin(lat0 * kRadPerDeg);
  const double den = std::sqrt(1.0 - e2 * s * s);
  const double M = a * (1.0 - e2) / (den * den * den), N = a / den;
  return {(lat - lat0) * kRadPerDeg * (M + alt0), (lon - lon0) * kRadPerDeg * (N + alt0) * std::cos(lat0 * kRadPerDeg),
          -(alt - alt0)};
}

}  // namespace tern_@NAME@
