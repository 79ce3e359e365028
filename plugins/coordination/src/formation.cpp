// Leader-follower spacing on a common orbit; see tern/coordination/formation.hpp.
#include "tern/coordination/formation.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "tern/math.hpp"

namespace tern::coord {

void FormationConfig::validate(int followers) const {
  auto need = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("formation: ") + what);
  };
  need(center.allFinite(), "center must be finite");
  need(std::isfinite(radius) && radius > 0.0, "radius must be > 0");
  need(direction == 1 || direction == -1, "direction must be 1 (clockwise) or -1 (counter-clockwise)");
  need(std::isfinite(spacing) && spacing > 0.0 && spacing < kPi * radius, "spacing must lie in (0, pi * radius)");
  need(followers * spacing < 2.0 * kPi * radius, "the followers at this spacing need more than one orbit");
  need(std::isfinite(gain) && gain >= 0.0, "gain must be >= 0");
  need(std::isfinite(Va_min) && Va_min > 0.0, "Va_min must be > 0");
  need(std::isfinite(Va_max) && Va_max >= Va_min, "Va_max must be >= Va_min");
  need(Va_nominal >= Va_min && Va_nominal <= Va_max, "Va_nominal must lie in [Va_min, Va_max]");
}

double orbit_angle(const Vec2& p, const Vec2& center) { return std::atan2(p.y() - center.y(), p.x() - center.x()); }

double spacing_error(double theta_leader, double theta_k, int k, const FormationConfig& cfg) {
  const double behind = cfg.direction * (theta_leader - theta_k);
  return cfg.radius * wrap_pi(behind - k * cfg.spacing / cfg.radius);
}

Vec2 orbit_tangent(double theta, const FormationConfig& cfg) { return cfg.direction * Vec2(-std::sin(theta), std::cos(theta)); }

double follower_airspeed(double e, const OrbitPlace& leader, const OrbitPlace& follower, const FormationConfig& cfg) {
  const double Vg_leader = ground_speed(cfg.Va_nominal, leader.wind, orbit_tangent(leader.theta, cfg));
  const double Vg = std::max(Vg_leader + cfg.gain * e, 0.0);
  return saturate(airspeed_for(Vg, follower.wind, orbit_tangent(follower.theta, cfg)), cfg.Va_min, cfg.Va_max);
}

}  // namespace tern::coord
