#include "control_common/loops.hpp"

#include <cmath>

#include "tern/math.hpp"

namespace tern::control {

bool VehicleState::finite() const {
  return std::isfinite(phi) && std::isfinite(theta) && std::isfinite(chi) && std::isfinite(p) && std::isfinite(q) && std::isfinite(r) &&
         std::isfinite(h) && std::isfinite(h_dot) && std::isfinite(Va);
}

bool Surfaces::finite() const {
  return std::isfinite(delta_a) && std::isfinite(delta_e) && std::isfinite(delta_r) && std::isfinite(delta_t);
}

// ---- lateral ----------------------------------------------------------------------------------

void LateralLoops::set_gains(const LateralGains& g) {
  g_ = g;
  course_.set_gains({g.course_kp, g.course_ki, g.course_kd, -g.roll_max, g.roll_max});
  roll_.set_gains({g.roll_kp, g.roll_ki, g.roll_kd, -g.max_a, g.max_a});
  washout_.set_pole(g.yaw_p_wo);
}

double LateralLoops::course(double chi_c, double chi, double r, double phi_ff, double dt) {
  return course_.update(tern::wrap_pi(chi_c - chi), r, dt, phi_ff);
}

double LateralLoops::shape_roll(double phi_c, double dt) {
  if (shaped_ && g_.roll_rate_max > 0.0 && dt > 0.0) {
    const double step = g_.roll_rate_max * dt;
    phi_c = saturate(phi_c, phi_c_prev_ - step, phi_c_prev_ + step);
  }
  p_c_ = phi_c_dot_.update(phi_c, dt);
  phi_c_prev_ = phi_c;
  shaped_ = true;
  return phi_c;
}

void LateralLoops::initialise_shape(double phi_c) {
  phi_c_dot_.reset();
  p_c_ = phi_c_dot_.update(phi_c, 0.0);
  phi_c_prev_ = phi_c;
  shaped_ = true;
}

double LateralLoops::roll(double phi_c, double phi, double p, double dt) {
  return roll_.update(phi_c - phi, p, dt, g_.trim_a + g_.roll_ff * p_c_);
}

double LateralLoops::yaw_damper(double r, double dt) {
  return saturate(g_.trim_r + g_.yaw_kr * washout_.update(r, dt), -g_.max_r, g_.max_r);
}

double LateralLoops::roll_command_for(double delta_a, double phi, double p) const {
  if (g_.roll_kp <= 0.0) return 0.0;
  const double phi_c = phi + (delta_a - g_.trim_a + g_.roll_kd * p) / g_.roll_kp;
  return saturate(phi_c, -g_.roll_max, g_.roll_max);
}

void LateralLoops::initialise_course(double phi_c, double chi_c, double chi, double r, double phi_ff) {
  course_.initialise(phi_c, tern::wrap_pi(chi_c - chi), r, phi_ff);
}

void LateralLoops::initialise_roll(double delta_a, double phi_c, double phi, double p) {
  roll_.initialise(delta_a, phi_c - phi, p, g_.trim_a + g_.roll_ff * p_c_);
}

void LateralLoops::reset() {
  course_.reset();
  roll_.reset();
  washout_.reset();
  phi_c_dot_.reset();
  phi_c_prev_ = 0.0;
  shaped_ = false;
  p_c_ = 0.0;
}

// ---- pitch ------------------------------------------------------------------------------------
// The PID computes u = -trim_e + kp e + ki int(e) - kd q on [-max_e, max_e]; delta_e = -u.

void PitchLoop::set_gains(const PitchGains& g) {
  g_ = g;
  pid_.set_gains({g.kp, g.ki, g.kd, -g.max_e, g.max_e});
}

double PitchLoop::update(double theta_c, double theta, double q, double dt) { return -pid_.update(theta_c - theta, q, dt, -g_.trim_e); }

double PitchLoop::pitch_command_for(double delta_e, double theta, double q) const {
  if (g_.kp <= 0.0) return theta;
  return theta + (g_.trim_e - delta_e + g_.kd * q) / g_.kp;
}

void PitchLoop::initialise(double delta_e, double theta_c, double theta, double q) {
  pid_.initialise(-delta_e, theta_c - theta, q, -g_.trim_e);
}

// ---- altitude ---------------------------------------------------------------------------------

void AltitudeLoop::set_gains(const AltitudeGains& g) {
  g_ = g;
  pid_.set_gains({g.kp, g.ki, g.kd, g.theta_min, g.theta_max});
}

double AltitudeLoop::update(double h_c, double h, double h_dot, double dt) { return pid_.update(h_c - h, h_dot, dt); }

void AltitudeLoop::initialise(double theta_c, double h_c, double h, double h_dot) { pid_.initialise(theta_c, h_c - h, h_dot); }

// ---- airspeed ---------------------------------------------------------------------------------

void AirspeedThrottleLoop::set_gains(const AirspeedGains& g) {
  g_ = g;
  pid_.set_gains({g.kp, g.ki, g.kd, g.min_t, g.max_t});
  Va_dot_.set_tau(g.tau_d);
}

double AirspeedThrottleLoop::update(double Va_c, double Va, double dt) {
  const double Va_dot = Va_dot_.update(Va, dt);
  return pid_.update(Va_c - Va, Va_dot, dt, g_.trim_t);
}

void AirspeedThrottleLoop::initialise(double delta_t, double Va_c, double Va) {
  pid_.initialise(delta_t, Va_c - Va, Va_dot_.value(), g_.trim_t);
}

void AirspeedThrottleLoop::reset() {
  pid_.reset();
  Va_dot_.reset();
}

}  // namespace tern::control
