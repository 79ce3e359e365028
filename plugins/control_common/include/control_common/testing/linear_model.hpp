// Test plant for the autopilot loops: the uavbook's linearised transfer-function models
// (Beard & McLain, section 5.4), integrated with 1 ms Euler sub-steps:
//   roll      p_dot = -a_phi1 p + a_phi2 delta_a,  phi_dot = p         (phi/delta_a = a_phi2/(s(s+a_phi1)))
//   course    chi_dot = g/Va tan(phi)                                  (coordinated turn, no wind)
//   pitch     q_dot = -a_theta1 q - a_theta2 (theta - alpha*) + a_theta3 (delta_e - delta_e*),  theta_dot = q
//   altitude  h_dot = Va sin(theta - alpha*)                           (flight-path angle gamma = theta - alpha*)
//   airspeed  Va_dot = -a_V1 (Va - Va*) + a_V2 (delta_t - delta_t*) - a_V3 sin(theta - alpha*)
//   yaw rate  r = g/Va tan(phi) cos(theta)                             (coordinated)
// The coefficients are what `tern aero gains` / `tern aero linearize` print for the aircraft
// files configs/aircraft/*.yaml (see configs/gains/README.md), to 4 decimals; the Aerosonde's
// a_V2 8.1372 is the removed design_gains.py's (tern aero's trim gives 8.1375).
#pragma once

#include <cmath>

#include "control_common/loops.hpp"
#include "tern/math.hpp"

namespace tern::control::testmodel {

struct Coefficients {
  double a_phi1, a_phi2, a_theta1, a_theta2, a_theta3, a_V1, a_V2, a_V3;
  double Va_trim, alpha_trim, delta_e_trim, delta_t_trim;
};

/// RMRC Anaconda at Va = 17 m/s (tern aero gains, configs/aircraft/anaconda.yaml).
inline Coefficients anaconda() {
  return {25.6544, 137.9495, 15.6294, 162.1535, -58.5883, 0.5214, 15.3522, 9.81, 17.0, -0.0114, 0.1679, 0.5676};
}
/// Aerosonde at Va = 25 m/s (tern aero gains, configs/aircraft/aerosonde.yaml).
inline Coefficients aerosonde() {
  return {22.6289, 130.8837, 5.2947, 99.9474, -36.1124, 0.2207, 8.1372, 9.81, 25.0, 0.0501, -0.1250, 0.6768};
}

class LinearAircraft {
 public:
  explicit LinearAircraft(const Coefficients& k) : k_(k) {
    theta = k.alpha_trim;
    Va = k.Va_trim;
  }
  double phi = 0.0, p = 0.0, chi = 0.0, theta = 0.0, q = 0.0, h = 100.0, Va = 0.0;
  /// Offsets of the plant's trim from the controller's trim, to exercise the integrators.
  double delta_e_offset = 0.0, delta_t_offset = 0.0;

  void step(const Surfaces& u, double dt) {
    constexpr double g = 9.81;
    const int n = static_cast<int>(std::lround(dt / 1e-3));
    const double h_s = dt / n;
    for (int i = 0; i < n; ++i) {
      const double gamma = theta - k_.alpha_trim;
      const double p_dot = -k_.a_phi1 * p + k_.a_phi2 * u.delta_a;
      const double q_dot =
          -k_.a_theta1 * q - k_.a_theta2 * (theta - k_.alpha_trim) + k_.a_theta3 * (u.delta_e - (k_.delta_e_trim + delta_e_offset));
      const double Va_dot =
          -k_.a_V1 * (Va - k_.Va_trim) + k_.a_V2 * (u.delta_t - (k_.delta_t_trim + delta_t_offset)) - k_.a_V3 * std::sin(gamma);
      chi += h_s * g / Va * std::tan(phi);
      h += h_s * Va * std::sin(gamma);
      phi += h_s * p;
      theta += h_s * q;
      p += h_s * p_dot;
      q += h_s * q_dot;
      Va += h_s * Va_dot;
    }
    chi = tern::wrap_pi(chi);
  }

  VehicleState state() const {
    VehicleState x;
    x.phi = phi;
    x.theta = theta;
    x.chi = chi;
    x.p = p;
    x.q = q;
    x.r = 9.81 / Va * std::tan(phi) * std::cos(theta);
    x.h = h;
    x.h_dot = Va * std::sin(theta - k_.alpha_trim);
    x.Va = Va;
    return x;
  }
  const Coefficients& coefficients() const { return k_; }

 private:
  Coefficients k_;
};

}  // namespace tern::control::testmodel
