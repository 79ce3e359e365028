// core/apps/sysid/aero_samples.hpp: a flight's forces and moments as the uavbook's nondimensional
// coefficients (Beard and McLain, *Small Unmanned Aircraft*, sec. 4.2-4.3), sample by sample: the
// "measured" side of the equation-error regression (Klein and Morelli, *Aircraft System
// Identification*, sec. 5.4: forces from the accelerometers, moments from the rates and their
// derivatives) and its regressors.
//
// Forces, body FRD: F = m a - (T_p, 0, 0), a the specific force, T_p the prior's propeller thrust
// at the inflow V_xz and throttle delta_t (the gear is never in the data: airborne samples only).
// Lift and drag on the x-z plane's flow, as the uavbook model (tern/aero/model.hpp):
//   C_L = (sin(alpha) F_x - cos(alpha) F_z) / (qbar_xz S),  C_D = -(cos(alpha) F_x + sin(alpha) F_z) / (qbar_xz S)
//   qbar_xz = rho V_xz^2 / 2,  V_xz = Va cos(beta);  C_Y = F_y / (qbar S),  qbar = rho Va^2 / 2.
// Moments from J w' + w x (J w) (book eq. 3.17 solved for the moments; J with -Jxz off the
// diagonal), the propeller's torque added back to the rolling moment:
//   l = Jx p' - Jxz r' + (Jz - Jy) q r - Jxz p q + Q_p,  m = Jy q' + (Jx - Jz) p r + Jxz (p^2 - r^2),
//   n = Jz r' - Jxz p' + (Jy - Jx) p q + Jxz q r;
//   C_ell = l / (qbar S b),  C_m = m / (qbar_xz S c),  C_n = n / (qbar S b).
// Nondimensional rates: p^ = b p / (2 Va), q^ = c q / (2 V_xz), r^ = b r / (2 Va).
// qbar is the pitot's differential pressure where the log has one (the dynamic pressure the
// airframe met, gusts included), else rho Va^2 / 2 of the estimator's Va; Va = sqrt(2 qbar / rho).
// C_L and C_D here are rotated by the estimator's alpha; C_X and C_Z let identify.hpp rotate them by
// a better one. alpha and beta here are the estimator's (the wind triangle); identify.hpp says where better
// ones come from.
#pragma once

#include <vector>

#include "sysid/airborne.hpp"
#include "sysid/flight_data.hpp"
#include "tern/aircraft.hpp"

namespace tern::core::sysid {

struct AeroSamples {
  std::vector<double> t;                               ///< s
  std::vector<double> C_L, C_D, C_Y, C_ell, C_m, C_n;  ///< measured coefficients
  std::vector<double> C_X, C_Z;             ///< the body-axis force coefficients F_x / (qbar_xz S), F_z / (qbar_xz S) (thrust removed)
  std::vector<double> alpha, beta;          ///< rad, the estimator's
  std::vector<double> p_hat, q_hat, r_hat;  ///< nondimensional rates
  std::vector<double> delta_a, delta_e, delta_r, delta_t;
  std::vector<double> exc_delta_a, exc_delta_e, exc_delta_r, exc_delta_t;  ///< the excitation's part (FlightSeries), or empty
  std::vector<double> Va;                                                  ///< m/s, from qbar
  std::vector<double> C_ell_prop;   ///< the prior's propeller torque added back to C_ell, Q_p / (qbar S b)
  std::vector<double> p, q, r;      ///< rad/s (the excitation tests read them)
  std::vector<std::size_t> source;  ///< index of each sample in the FlightSeries
  std::size_t size() const { return t.size(); }
};

/// Which samples count as flight (the rest never enter a regression).
struct AirborneFilter {
  AirborneRule ground;          ///< off the ground (airborne.hpp): the log's window, else above where it stood still
  double min_Va_ratio = 0.6;    ///< Va above this fraction of the airborne median
  double max_flow_angle = 0.3;  ///< rad: |alpha|, |beta| beyond it leave the linear model
};

/// The samples where the estimate is valid and the aircraft flies (filter), as coefficients.
/// Mass, inertia, geometry, rho and the propulsion model come from `prior`. `pitot_scale` k
/// (instrumentation.hpp, > 0): the true airspeed is k times the pitot's, so its dynamic pressure
/// k^2 times (no effect where the log has no pitot).
AeroSamples aero_samples(const FlightSeries& s, const Aircraft& prior, const AirborneFilter& filter, double pitot_scale = 1.0);

}  // namespace tern::core::sysid
