// control_common/pid.hpp: PID with saturation and anti-windup, dirty derivative, washout filter.
//
// Plain C++ (no tern host types), the building blocks of the successive-loop-closure autopilot
// (Beard & McLain, *Small Unmanned Aircraft*, ch. 6, and section 6.5 "digital implementation of
// PID loops"). Time steps dt are in seconds; a dt <= 0 (first call, or a repeated time stamp)
// integrates and differentiates nothing.
#pragma once

#include <limits>

namespace tern::control {

/// Band-limited ("dirty") derivative dy/dt ~ s/(tau s + 1) y, discretised with Tustin's rule
/// (Beard & McLain, eq. 6.31 / section 6.5). The first sample after reset() gives 0.
class DirtyDerivative {
 public:
  explicit DirtyDerivative(double tau = 0.05) : tau_(tau) {}
  /// tau: filter time constant, s (> 0).
  void set_tau(double tau) { tau_ = tau; }
  double tau() const { return tau_; }
  /// Feeds y (any unit) measured dt seconds after the previous sample; returns dy/dt (unit/s).
  double update(double y, double dt);
  double value() const { return ydot_; }
  /// As constructed with the current tau (a new flight, or a loop taken out of use).
  void reset() { *this = DirtyDerivative(tau_); }

 private:
  double tau_;
  double y_prev_ = 0.0;
  double ydot_ = 0.0;
  bool primed_ = false;
};

/// Washout (high-pass) filter H(s) = s / (s + p_wo), Tustin discretisation; used by the yaw
/// damper (Beard & McLain, section 6.1.3) so that a steady yaw rate in a turn is not opposed.
class Washout {
 public:
  explicit Washout(double p_wo = 0.5) : p_wo_(p_wo) {}
  /// p_wo: washout pole, rad/s (>= 0).
  void set_pole(double p_wo) { p_wo_ = p_wo; }
  double update(double x, double dt);
  /// As constructed with the current pole.
  void reset() { *this = Washout(p_wo_); }

 private:
  double p_wo_;
  double x_prev_ = 0.0;
  double y_ = 0.0;
  bool primed_ = false;
};

/// Gains and limits of one PID loop. u = ff + kp e + ki * integral(e) - kd * ydot, saturated to
/// [u_min, u_max]. The derivative acts on the measurement (its rate ydot), not on the error, so
/// a command step gives no derivative kick.
struct PidGains {
  double kp = 0.0;
  double ki = 0.0;  ///< 1/s times kp's unit; 0 disables (and clears) the integrator
  double kd = 0.0;
  double u_min = -std::numeric_limits<double>::infinity();
  double u_max = std::numeric_limits<double>::infinity();
};

/// PID loop with saturation and anti-windup by integrator clamping (conditional integration:
/// the integrator does not grow while the output is saturated in the direction the error
/// pushes; and |ki * integral| never exceeds half the output range). Trapezoidal integration
/// (Beard & McLain, section 6.5).
class Pid {
 public:
  explicit Pid(PidGains g = {}) : g_(g) {}
  void set_gains(const PidGains& g);
  const PidGains& gains() const { return g_; }

  /// One step: error e, measured rate ydot of the controlled quantity, feed-forward ff (added
  /// to the output before saturation), dt in s. Returns the saturated output.
  double update(double e, double ydot, double dt, double ff = 0.0);

  /// Bumpless transfer: sets the integrator so that update(e, ydot, 0, ff) would return u
  /// (as far as the integrator clamp allows). Returns the part of u it could not reach
  /// (0 when the integrator covers it; u - output otherwise).
  double initialise(double u, double e, double ydot, double ff = 0.0);

  /// As constructed with the current gains: integrator, previous error and outputs cleared.
  void reset() { *this = Pid(g_); }
  double integrator() const { return integrator_; }
  double last_output() const { return u_; }
  /// Unsaturated output of the last update.
  double last_unsaturated() const { return u_unsat_; }

 private:
  double clamp_integrator(double I) const;
  double output(double e, double ydot, double ff, double I) const { return ff + g_.kp * e + g_.ki * I - g_.kd * ydot; }
  PidGains g_;
  double integrator_ = 0.0;
  double e_prev_ = 0.0;
  bool primed_ = false;
  double u_ = 0.0;
  double u_unsat_ = 0.0;
};

inline double saturate(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }

}  // namespace tern::control
