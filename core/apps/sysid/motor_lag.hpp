// core/apps/sysid/motor_lag.hpp: how long the thrust takes to follow the throttle's command,
// estimated from the flight (issue 76, item 4: an actuator's lag from the data).
//
// Why. The thrust is removed from the measured x force with the prior's propeller model at the
// logged throttle (aero_samples.hpp); the motor and propeller take some 50-150 ms to spin up, far
// longer than a servo. The Aerosonde's thrust at trim changes by 90 N per unit of throttle against
// a drag of 1 N, so a throttle that moves with the gusts (the airspeed loop) leaves the commands'
// thrust on average too large by much of the drag: on the sysid mission's seed 1 (light
// turbulence, the `realistic` actuators' 0.1-s motor) the drag at trim +68 % with the servos'
// 0.02 s, +57 % with the true 0.1 s.
//
// The estimate: the first-order lag tau on a grid (0 to max_tau_s, step_s) whose thrust leaves
// the least of the x force unexplained at the manoeuvres' frequencies: C_X of the airborne samples
// (aero_samples.hpp, the throttle lagged by tau), each stretch less its centred moving average
// over highpass_s, regressed by least squares on the same high-passed alpha, alpha^2, q^ and
// delta_e (the x force's aerodynamic terms); the residual's mean square at each tau. The thrust's
// error at a wrong tau is the throttle's movement in the last tau seconds, which no aerodynamic
// term follows. Klein and Morelli, *Aircraft System Identification*, 2006, sec. 10.2 (data
// compatibility: an instrument's time constant fitted with the model's residual).
//
// Adopted when the minimum lies below max_tau_s (not at the grid's top) and its residual is at
// least min_gain below the residual at `start_tau` (the servos' lag, the series as loaded); else
// start_tau is kept with one line why. The bound: the grid's span over which the residual stays
// within min_gain of the minimum (half of it each side), not a standard error.
// Units: s. Errors: std::invalid_argument for a grid without points (max_tau_s or step_s not > 0).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "sysid/identify.hpp"

namespace tern::core::sysid {

struct MotorLagOptions {
  double max_tau_s = 0.3;   ///< s, top of the grid (a motor slower than this is not a motor's lag)
  double step_s = 0.01;     ///< s, the grid's step
  double highpass_s = 2.0;  ///< s, the centred moving average each stretch loses (the trim's slow drift)
  double min_gain = 0.005;  ///< fraction of the residual at start_tau that the minimum must lie below
};

struct MotorLag {
  NuisanceEstimate tau;                          ///< s; identified when adopted, else start_tau with a note
  std::vector<std::pair<double, double>> curve;  ///< (tau s, residual mean square) over the grid
  std::string line;                              ///< one line for SysidResult::notes
};

/// The series with the throttle lagged by tau (s): FlightSeries::delta_t replaced.
using ThrottleAt = std::function<std::vector<double>(double tau)>;

/// The motor's lag from `series` and the throttle at each tau (header); start_tau: the lag the series
/// would be loaded with otherwise.
MotorLag estimate_motor_lag(const FlightSeries& series, const ThrottleAt& throttle, const Aircraft& prior, const AirborneFilter& airborne,
                            double start_tau, const MotorLagOptions& o = {});

}  // namespace tern::core::sysid
