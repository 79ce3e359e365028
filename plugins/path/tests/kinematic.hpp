// A kinematic fixed-wing for the path tests: coordinated-turn unicycle (Beard & McLain,
// section 9.2: chi_dot = g / Vg tan(phi)) with a first-order roll response to a proportional
// course loop (ROSplane's c_kp = 2.0 rad/rad, roll limit 45 deg, as the Anaconda gains) and a
// first-order altitude response. Optional steady wind (w_n, w_e): the heading psi turns at
// g / Va tan(phi), the course chi is that of the ground velocity. Plain C++; not a flight model.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include "tern/math.hpp"

namespace tern::path::testkit {

struct KinematicAircraft {
  double n = 0.0, e = 0.0, h = 0.0;  ///< position: north, east (m), altitude (m)
  double chi = 0.0;                  ///< course over ground, rad
  double psi = 0.0;                  ///< heading, rad (= chi without wind)
  double w_n = 0.0, w_e = 0.0;       ///< steady wind, m/s (direction the air moves to)
  double phi = 0.0;                  ///< roll, rad
  double Va = 17.0;                  ///< airspeed, m/s (follows Va_c with a time constant)
  double kp_chi = 2.0;               ///< course loop gain, rad roll per rad course error
  double phi_max = 45.0 * 3.14159265358979323846 / 180.0;
  double tau_phi = 0.3;    ///< roll time constant, s
  double tau_h = 3.0;      ///< altitude time constant, s
  double climb_max = 5.0;  ///< m/s

  Eigen::Vector3d p() const { return {n, e, -h}; }
  double Vg() const { return std::hypot(Va * std::cos(psi) + w_n, Va * std::sin(psi) + w_e); }
  /// Starts with heading = course = chi0 (no wind correction).
  void set_course(double chi0) { chi = psi = chi0; }

  /// Advances dt seconds towards the commanded course (chi_c, unwrapped or not), roll
  /// feed-forward phi_ff, altitude h_c and airspeed Va_c.
  void step(double chi_c, double phi_ff, double h_c, double Va_c, double dt) {
    using tern::kPi;
    double err = wrap_pi(chi_c - chi);
    const double phi_c = std::clamp(kp_chi * err + phi_ff, -phi_max, phi_max);
    phi += (phi_c - phi) * (dt / tau_phi);
    psi = wrap_pi(psi + 9.81 / Va * std::tan(phi) * dt);
    const double v_n = Va * std::cos(psi) + w_n, v_e = Va * std::sin(psi) + w_e;
    chi = std::atan2(v_e, v_n);
    n += v_n * dt;
    e += v_e * dt;
    h += std::clamp((h_c - h) / tau_h, -climb_max, climb_max) * dt;
    if (Va_c > 0.0) Va += (Va_c - Va) * (dt / 5.0);
  }
};

}  // namespace tern::path::testkit
