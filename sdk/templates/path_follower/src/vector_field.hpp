// vector_field.hpp: vector-field path following (plain C++, no tern types), Beard & McLain,
// *Small Unmanned Aircraft*, ch. 10.
//   straight line (sec. 10.2): chi_q = atan2(q_e, q_n) (unwrapped near chi),
//     e_py = -sin(chi_q) (p_n - r_n) + cos(chi_q) (p_e - r_e)                         (eq. 10.2)
//     chi_c = chi_q - chi_inf (2/pi) atan(k_path e_py)                                 (eq. 10.8)
//     h_c = -r_d - sqrt(s_n^2 + s_e^2) q_d / sqrt(q_n^2 + q_e^2)                        (eq. 10.5)
//   orbit (sec. 10.3): d = |p - c| (horizontal), varphi = atan2(p_e - c_e, p_n - c_n)
//     chi_c = varphi + lambda (pi/2 + atan(k_orbit (d - rho) / rho))                   (eq. 10.14)
//     h_c = -c_d, roll feed-forward phi_ff = lambda atan(Va^2 / (g rho)) near the circle.
// Frames: NED positions in m, angles in rad, lambda = 1 clockwise, -1 counter-clockwise.
#pragma once

#include <Eigen/Core>

namespace tern_@NAME@ {

struct FollowerGains {
  double chi_inf = 1.0472;  ///< course approach angle far from the line, rad, (0, pi/2]
  double k_path = 0.025;    ///< line convergence gain, 1/m, > 0
  double k_orbit = 2.0;     ///< orbit convergence gain, > 0
};

/// Guidance output: course chi_c (rad, near the current course), altitude h_c (m above the
/// origin), roll feed-forward phi_ff (rad; orbits only).
struct Guidance {
  double chi_c = 0.0, h_c = 0.0, phi_ff = 0.0;
};

/// Straight line through r (NED, m) with direction q (NED, need not be unit, must not be zero),
/// seen from position p (NED, m) with course chi (rad). Returns NaNs if q is zero or not finite.
Guidance follow_line(const Eigen::Vector3d& r, const Eigen::Vector3d& q, const Eigen::Vector3d& p,
                     double chi, const FollowerGains& g);

/// Cross-track error e_py of eq. 10.2 (m, positive: the aircraft is right of the line).
double cross_track_error(const Eigen::Vector3d& r, const Eigen::Vector3d& q, const Eigen::Vector3d& p);

/// Orbit of centre c (NED, m), radius rho (m, > 0), direction lambda (+1 cw, -1 ccw) seen from
/// p with course chi, at airspeed Va (m/s, for the feed-forward).
Guidance follow_orbit(const Eigen::Vector3d& c, double rho, int lambda, const Eigen::Vector3d& p,
                      double chi, double Va, const FollowerGains& g);

}  // namespace tern_@NAME@
