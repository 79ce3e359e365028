#include "control_tecs/tecs.hpp"

#include <algorithm>
#include "tern/math.hpp"

namespace tern::control {

namespace {}

void Tecs::set_gains(const TecsGains& g) {
  g_ = g;
  throttle_.set_gains({g.energy_kp, g.energy_ki, 0.0, g.min_t, g.max_t});
  pitch_.set_gains({g.balance_kp, g.balance_ki, 0.0, g.theta_min, g.theta_max});
  Va_dot_.set_tau(g.Va_dot_tau);
}

Tecs::Errors Tecs::errors(const VehicleState& x, const Command& c, double Va_dot) const {
  const double Va = std::max(x.Va, 1.0);
  const double gamma = x.h_dot / Va;
  const double h_dot_c = saturate(g_.h_kp * (c.h_c - x.h), -g_.sink_rate_max, g_.climb_rate_max);
  const double gamma_c = h_dot_c / Va;
  const double Va_c = saturate(c.Va_c, g_.Va_min, std::max(g_.Va_min, g_.Va_max));
  const double Va_dot_c = saturate(g_.Va_kp * (Va_c - x.Va), -g_.Va_dot_max, g_.Va_dot_max);
  const double w_gamma = underspeed_ ? 0.0 : 1.0;
  const double w_V = underspeed_ ? 2.0 : 1.0;
  Errors e;
  e.e_E = (gamma_c - gamma) + (Va_dot_c - Va_dot) / kGravity;
  e.e_B = w_gamma * (gamma_c - gamma) - w_V * (Va_dot_c - Va_dot) / kGravity;
  e.ff_t = g_.trim_t + g_.energy_ff * (gamma_c + Va_dot_c / kGravity);
  e.ff_theta = g_.balance_ff * (w_gamma * gamma_c - w_V * Va_dot_c / kGravity);
  return e;
}

LongitudinalLaw::Output Tecs::update(const VehicleState& x, const Command& c, bool /*climb*/, double dt) {
  const double Va_dot = Va_dot_.update(x.Va, dt);
  // underspeed protection with hysteresis
  const bool was_under = underspeed_;
  if (x.Va < g_.Va_min)
    underspeed_ = true;
  else if (x.Va > g_.Va_min + g_.underspeed_hysteresis)
    underspeed_ = false;
  const Errors e = errors(x, c, Va_dot);
  if (was_under != underspeed_) {
    // the balance weights changed: restart the pitch integrator from the current command
    pitch_.initialise(pitch_.last_output(), e.e_B, 0.0, e.ff_theta);
    if (!underspeed_) throttle_.initialise(g_.max_t, e.e_E, 0.0, e.ff_t);  // leave full throttle smoothly
  }
  Output o;
  const double theta_c = pitch_.update(e.e_B, 0.0, dt, e.ff_theta);
  if (have_theta_c_ && dt > 0.0) {
    const double step = g_.theta_rate_max * dt;
    theta_c_ = saturate(theta_c, theta_c_ - step, theta_c_ + step);
  } else if (!have_theta_c_) {
    theta_c_ = theta_c;
  }
  have_theta_c_ = true;
  o.theta_c = theta_c_;
  if (underspeed_) {
    o.delta_t = o.delta_t_c = g_.max_t;
  } else {
    o.delta_t = throttle_.update(e.e_E, 0.0, dt, e.ff_t);
    o.delta_t_c = throttle_.last_unsaturated();
  }
  return o;
}

void Tecs::initialise(const VehicleState& x, const Command& c, double theta_c, double delta_t) {
  underspeed_ = x.Va < g_.Va_min;
  const Errors e = errors(x, c, Va_dot_.value());
  pitch_.initialise(theta_c, e.e_B, 0.0, e.ff_theta);
  throttle_.initialise(delta_t, e.e_E, 0.0, e.ff_t);
  theta_c_ = saturate(theta_c, g_.theta_min, g_.theta_max);
  have_theta_c_ = true;
}

void Tecs::reset() {
  throttle_.reset();
  pitch_.reset();
  Va_dot_.reset();
  underspeed_ = false;
  have_theta_c_ = false;
  theta_c_ = 0.0;
}

}  // namespace tern::control
