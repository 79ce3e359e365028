#include "slc.hpp"

#include <algorithm>
#include <cmath>
#include "tern/math.hpp"  // wrap_pi: a course error of 350 deg is one of -10 deg

namespace tern_@NAME@ {

double PiLoop::update(double e, double dt, double kp, double ki, double ff, double lo, double hi) {
  const double I_next = I + e * dt;
  const double u_next = ff + kp * e + ki * I_next;
  if (!((u_next > hi && e > 0.0) || (u_next < lo && e < 0.0))) I = I_next;  // anti-windup
  u_raw = ff + kp * e + ki * I;
  return std::clamp(u_raw, lo, hi);
}

Output Slc::trim() const {
  Output o;
  o.delta_a = std::clamp(g_.trim_a, -g_.max_a, g_.max_a);
  o.delta_e = std::clamp(g_.trim_e, -g_.max_e, g_.max_e);
  o.delta_t = o.delta_t_c = std::clamp(g_.trim_t, 0.0, 1.0);
  return o;
}

Output Slc::update(const Command& c, const State& x, double dt) {
  for (double v : {c.chi_c, c.h_c, c.Va_c, c.phi_ff, x.phi, x.theta, x.chi, x.p, x.q, x.h, x.Va, dt})
    if (!std::isfinite(v)) return trim();
  if (dt < 0.0) return trim();

  Output o;
  // lateral: course -> roll command -> aileron
  o.phi_c = course_.update(tern::wrap_pi(c.chi_c - x.chi), dt, g_.course_kp, g_.course_ki, c.phi_ff, -g_.roll_max, g_.roll_max);
  o.delta_a = std::clamp(g_.trim_a + g_.roll_kp * (o.phi_c - x.phi) - g_.roll_kd * x.p, -g_.max_a, g_.max_a);
  // longitudinal: altitude -> pitch command -> elevator; airspeed -> throttle
  o.theta_c = altitude_.update(c.h_c - x.h, dt, g_.altitude_kp, g_.altitude_ki, 0.0, -g_.theta_max, g_.theta_max);
  o.delta_e = std::clamp(g_.trim_e - g_.pitch_kp * (o.theta_c - x.theta) + g_.pitch_kd * x.q, -g_.max_e, g_.max_e);
  o.delta_t = airspeed_.update(c.Va_c - x.Va, dt, g_.airspeed_kp, g_.airspeed_ki, g_.trim_t, 0.0, 1.0);
  o.delta_t_c = airspeed_.u_raw;
  return o;
}

void Slc::take_over(double delta_t, double Va_error) {
  reset();
  if (g_.airspeed_ki > 0.0 && std::isfinite(delta_t) && std::isfinite(Va_error))
    airspeed_.I = (std::clamp(delta_t, 0.0, 1.0) - g_.trim_t - g_.airspeed_kp * Va_error) / g_.airspeed_ki;
}

}  // namespace tern_@NAME@
