// tern/aero/trim.hpp: trim of the uavbook model (Beard & McLain, ch. 5).
//
// Finds the state and inputs at which the aircraft flies at airspeed Va, flight-path angle gamma
// and turn radius R with constant alpha, beta, p, q, r (no wind). The book minimises the
// difference between the wanted and the computed state derivative; tern solves the same
// conditions as a square system by Newton's method (finite-difference Jacobian, backtracking):
// unknowns alpha, phi, theta, delta_e, delta_a, delta_r, delta_t; conditions u', v', w', p', q',
// r' = 0 and h' = Va sin(gamma); the turn is coordinated (beta = 0) with heading rate
// psi' = Va cos(gamma) / R (book sec. 5.3) and body rates from psi' with phi' = theta' = 0
// (book eq. 3.2). An aircraft without a rudder (a flying wing: C_Y_delta_r, C_ell_delta_r and
// C_n_delta_r all 0) cannot coordinate: it trims with delta_r = 0 and beta among the unknowns in
// its place (the sideslip that balances the side force and the yawing moment the ailerons and the
// propeller leave).
#pragma once

#include <limits>
#include <string>

#include "tern/aircraft.hpp"
#include "tern/aero/model.hpp"

namespace tern::sim {

struct TrimRequest {
  double Va = 17.0;                                    ///< airspeed, m/s, > 0
  double gamma = 0.0;                                  ///< flight-path angle, rad (climb positive)
  double R = std::numeric_limits<double>::infinity();  ///< turn radius, m (> 0 right turn, < 0 left; inf: straight)
  double altitude = 100.0;                             ///< height of the trim state above the ground, m (clear of the gear)
  double psi = 0.0;                                    ///< heading of the trim state, rad
};

struct TrimResult {
  StateVector x = StateVector::Zero();             ///< trim state (position (0, 0, -altitude))
  Deltas delta;                                    ///< trim inputs
  double alpha = 0, beta = 0, phi = 0, theta = 0;  ///< rad (beta 0 but for an aircraft without a rudder)
  double residual = 0;                             ///< norm of the trim conditions at the solution
  int iterations = 0;
};

/// Computes the trim. Throws std::runtime_error (one line naming the request) when the request
/// is invalid (Va <= 0, |gamma| >= pi/2, |R| too small), when Newton's method does not converge,
/// or when the trim needs an input outside its limits (throttle outside [0, 1], a surface beyond
/// its maximum deflection).
TrimResult compute_trim(const Aircraft& ac, const TrimRequest& req);

}  // namespace tern::sim
