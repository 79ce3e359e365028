// tern/aero/modes.hpp: the dynamic modes of the uavbook ch. 5 linear models (`tern aero linearize`, issue 22):
// short period and phugoid (longitudinal), roll, spiral and dutch roll (lateral), and the
// textbook approximations of each, a second computation to check them against.
//
// Modes: the eigenvalues (Eigen::EigenSolver) of the dynamic blocks [u w q theta] of A_lon and
// [v p r phi] of A_lat (h and psi are pure integrators: their zero eigenvalues are no mode).
// Identification by eigenvector content, as in Beard & McLain ch. 5 and Etkin & Reid ch. 6:
//  * longitudinal: the two eigenvalues (a complex pair, or two real roots when overdamped)
//    whose eigenvectors carry the most angle of attack alpha = w/Va relative to the airspeed
//    change u/Va are the short period, the other two the phugoid;
//  * lateral: the two with the most sideslip beta = v/Va relative to the roll angle phi are the
//    dutch roll; of the other two real roots the faster is the roll mode, the slower the spiral
//    (if they form a complex pair it is reported as the coupled "roll-spiral" oscillation).
// A note says when the eigenvector choice disagrees with the frequency ordering (short period
// faster than phugoid, roll faster than spiral).
#pragma once

#include <complex>
#include <string>
#include <vector>

#include "tern/aero/linear_model.hpp"
#include "tern/aircraft.hpp"

namespace tern::aero {

/// One mode: a complex pair (oscillatory) or one real eigenvalue.
struct Mode {
  std::string name;             ///< "short period", "phugoid", "roll", "spiral", "dutch roll", ...
  std::complex<double> lambda;  ///< eigenvalue, 1/s (of a pair, the one with imag > 0)
  bool oscillatory = false;     ///< a complex pair
  bool stable = false;          ///< Re(lambda) < 0
  double wn = 0;                ///< natural frequency |lambda|, rad/s (all modes)
  double zeta = 0;              ///< damping ratio -Re(lambda)/|lambda| (oscillatory; 1 or -1 for a real root)
  double period = 0;            ///< damped period 2 pi / Im(lambda), s (oscillatory; 0 otherwise)
  double tau = 0;               ///< time constant -1/Re(lambda), s (stable; of the envelope if oscillatory; else 0)
  double t_double = 0;          ///< time to double ln 2 / Re(lambda), s (unstable; else 0)
};

struct Modes {
  std::vector<Mode> lon;           ///< short period, phugoid (two entries each if overdamped)
  std::vector<Mode> lat;           ///< roll, spiral, dutch roll (or roll-spiral, dutch roll)
  std::vector<std::string> notes;  ///< how ambiguous cases were decided
};

/// Modes of the linear model's dynamic blocks (see the header comment).
Modes dynamic_modes(const LinearModel& lm);

/// Approximate modes from the aircraft's coefficients at the trim, without A or its eigenvalues
/// (the second computation). Dimensional derivatives as in Beard & McLain table 5.2 with the
/// inertia products Gamma_3,4,8 of sec. 3.3 (q_bar = rho Va^2 / 2, C_p = G3 C_ell + G4 C_n,
/// C_r = G4 C_ell + G8 C_n):
///  * short period (alpha, q; Nelson, Flight Stability and Automatic Control, ch. 4): wn^2 = Z_alpha M_q / Va - M_alpha,
///    zeta = -(Z_alpha / Va + M_q) / (2 wn), Z_alpha = -q_bar S (C_L_alpha + C_D*) / m,
///    M_alpha = -a_theta2, M_q = -a_theta1;
///  * phugoid (Lanchester with speed damping; Nelson ch. 4): wn = sqrt(-Z_u g / Va),
///    Z_u = -2 q_bar S C_L* / (m Va), zeta = -X_u / (2 wn), X_u = -a_V1;
///  * roll (Etkin & Reid eq. 6.8,8): lambda = L_p = -a_phi1;
///  * spiral (quasi-steady roll and yaw with r = g phi / Va; Etkin & Reid sec. 6.8):
///    lambda = -(g / Va) (L_beta N_r - L_r N_beta) / (L_beta N_p - L_p N_beta);
///  * dutch roll (beta, r; Nelson ch. 5): wn^2 = N_beta + Y_beta N_r / Va,
///    zeta = -(Y_beta / Va + N_r) / (2 wn), Y_beta = q_bar S C_Y_beta / m.
struct ModeApproximations {
  double short_period_wn = 0, short_period_zeta = 0;  ///< rad/s, -
  double phugoid_wn = 0, phugoid_zeta = 0;            ///< rad/s, -
  double roll_lambda = 0;                             ///< 1/s
  double spiral_lambda = 0;                           ///< 1/s
  double dutch_roll_wn = 0, dutch_roll_zeta = 0;      ///< rad/s, -
};
ModeApproximations approximate_modes(const tern::Aircraft& ac, const LinearModel& lm);

/// The modes as a readable table, then the approximations, every line starting with "# ".
std::string modes_table(const Modes& modes, const ModeApproximations& approx);

/// The first mode named `name` in modes.lon or modes.lat; nullptr if none.
const Mode* find_mode(const Modes& modes, const std::string& name);

}  // namespace tern::aero
