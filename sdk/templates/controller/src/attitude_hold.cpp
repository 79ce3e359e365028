#include "attitude_hold.hpp"

#include <algorithm>
#include <cmath>

namespace tern_@NAME@ {

Surfaces AttitudeHold::update(const Setpoint& sp, const Attitude& x, double dt) {
  const bool finite = std::isfinite(sp.phi_c) && std::isfinite(sp.theta_c) && std::isfinite(sp.Va_c) &&
                      std::isfinite(x.phi) && std::isfinite(x.theta) && std::isfinite(x.p) &&
                      std::isfinite(x.q) && std::isfinite(x.Va) && std::isfinite(dt) && dt >= 0.0;
  if (!finite) return {g_.trim_a, g_.trim_e, std::clamp(g_.trim_t, 0.0, 1.0)};

  Surfaces s;
  s.delta_a = std::clamp(g_.trim_a + g_.roll_kp * (sp.phi_c - x.phi) - g_.roll_kd * x.p, -g_.max_a, g_.max_a);
  s.delta_e = std::clamp(g_.trim_e - g_.pitch_kp * (sp.theta_c - x.theta) + g_.pitch_kd * x.q, -g_.max_e, g_.max_e);

  const double e_V = sp.Va_c - x.Va;
  const double integral = Va_integral_ + e_V * dt;
  const double raw = g_.trim_t + g_.airspeed_kp * e_V + g_.airspeed_ki * integral;
  s.delta_t = std::clamp(raw, 0.0, 1.0);
  // anti-windup: integrate only while unsaturated, or while the error drives out of saturation
  if (raw == s.delta_t || (raw > 1.0 && e_V < 0.0) || (raw < 0.0 && e_V > 0.0)) Va_integral_ = integral;
  return s;
}

void AttitudeHold::take_over(double delta_t, double Va_error) {
  if (g_.airspeed_ki <= 0.0 || !std::isfinite(delta_t) || !std::isfinite(Va_error)) {
    Va_integral_ = 0.0;
    return;
  }
  Va_integral_ = (std::clamp(delta_t, 0.0, 1.0) - g_.trim_t - g_.airspeed_kp * Va_error) / g_.airspeed_ki;
}

}  // namespace tern_@NAME@
