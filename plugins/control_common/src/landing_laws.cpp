// The flare law. See control_common/landing_laws.hpp.
#include "control_common/landing_laws.hpp"

#include <algorithm>
#include <cmath>

namespace tern::control {

void FlareLaw::start(double h0, double sink0, double theta0, double delta_t0) {
  h0_ = std::max(h0, 0.1);
  sink0_ = std::max(sink0, 0.0);
  theta0_ = theta0;
  delta_t0_ = std::clamp(delta_t0, 0.0, 1.0);
  integral_ = 0.0;
  deficit_integral_ = 0.0;
}

double FlareLaw::throttle(double h, double Va, double Va_floor, double dt, const LandingSettings& s) {
  const double schedule = delta_t0_ * std::clamp(h / h0_, 0.0, 1.0);
  const double deficit = std::isfinite(Va) && std::isfinite(Va_floor) ? Va_floor - Va : 0.0;
  // integrated deficit, never below 0 and no more than full throttle's worth (no wind-up)
  const double i_max = s.flare_throttle_ki > 0.0 ? 1.0 / s.flare_throttle_ki : 0.0;
  deficit_integral_ = std::clamp(deficit_integral_ + deficit * dt, 0.0, i_max);
  const double floor = s.flare_throttle_kp * deficit + s.flare_throttle_ki * deficit_integral_;
  return std::clamp(std::max(schedule, floor), 0.0, 1.0);
}

double FlareLaw::h_dot_command(double h, const LandingSettings& s) const {
  const double sink0 = std::max(sink0_, s.flare_sink_td);
  const double k = std::clamp(h / h0_, 0.0, 1.0);
  return -(s.flare_sink_td + (sink0 - s.flare_sink_td) * k);
}

double FlareLaw::update(double h, double h_dot, double dt, const LandingSettings& s) {
  const double e = h_dot_command(h, s) - h_dot;
  const double unclamped = theta0_ + s.flare_kp * e + s.flare_ki * (integral_ + e * dt);
  // integrate only while the command is within its limits (no wind-up at a stop)
  if (unclamped > s.flare_pitch_min && unclamped < s.flare_pitch_max) integral_ += e * dt;
  return std::clamp(theta0_ + s.flare_kp * e + s.flare_ki * integral_, s.flare_pitch_min, s.flare_pitch_max);
}

}  // namespace tern::control
