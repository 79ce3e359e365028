#include "control_common/pid.hpp"

#include <cmath>

namespace tern::control {

double DirtyDerivative::update(double y, double dt) {
  if (!primed_) {
    primed_ = true;
    y_prev_ = y;
    ydot_ = 0.0;
    return ydot_;
  }
  if (dt <= 0.0) return ydot_;
  // Tustin discretisation of s / (tau s + 1) (Beard & McLain, section 6.5).
  const double a = (2.0 * tau_ - dt) / (2.0 * tau_ + dt);
  const double b = 2.0 / (2.0 * tau_ + dt);
  ydot_ = a * ydot_ + b * (y - y_prev_);
  y_prev_ = y;
  return ydot_;
}

double Washout::update(double x, double dt) {
  if (!primed_) {
    primed_ = true;
    x_prev_ = x;
    y_ = 0.0;  // starts at rest: a rate present at start-up is treated as steady
    return y_;
  }
  if (dt <= 0.0) return y_;
  const double a = (2.0 - p_wo_ * dt) / (2.0 + p_wo_ * dt);
  const double b = 2.0 / (2.0 + p_wo_ * dt);
  y_ = a * y_ + b * (x - x_prev_);
  x_prev_ = x;
  return y_;
}

void Pid::set_gains(const PidGains& g) {
  g_ = g;
  if (g_.ki == 0.0) integrator_ = 0.0;
  integrator_ = clamp_integrator(integrator_);
}

double Pid::clamp_integrator(double I) const {
  if (g_.ki == 0.0) return 0.0;
  const double span = 0.5 * (g_.u_max - g_.u_min);
  if (!std::isfinite(span)) return I;
  const double lim = span / std::fabs(g_.ki);
  return saturate(I, -lim, lim);
}

double Pid::update(double e, double ydot, double dt, double ff) {
  double I = integrator_;
  if (dt > 0.0 && g_.ki != 0.0) {
    const double e_last = primed_ ? e_prev_ : e;
    const double candidate = clamp_integrator(I + 0.5 * dt * (e + e_last));
    // Conditional integration: do not let the integrator push further into saturation.
    const double u_try = output(e, ydot, ff, candidate);
    const bool grows_out = (u_try > g_.u_max && candidate > I) || (u_try < g_.u_min && candidate < I);
    if (!grows_out) I = candidate;
  }
  integrator_ = I;
  e_prev_ = e;
  primed_ = true;
  u_unsat_ = output(e, ydot, ff, integrator_);
  u_ = saturate(u_unsat_, g_.u_min, g_.u_max);
  return u_;
}

double Pid::initialise(double u, double e, double ydot, double ff) {
  if (g_.ki != 0.0) {
    integrator_ = clamp_integrator((u - (ff + g_.kp * e - g_.kd * ydot)) / g_.ki);
  } else {
    integrator_ = 0.0;
  }
  e_prev_ = e;
  primed_ = true;
  u_unsat_ = output(e, ydot, ff, integrator_);
  u_ = saturate(u_unsat_, g_.u_min, g_.u_max);
  return u - u_;
}

}  // namespace tern::control
