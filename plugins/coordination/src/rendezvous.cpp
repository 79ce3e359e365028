// Timed rendezvous plan; see tern/coordination/rendezvous.hpp.
#include "tern/coordination/rendezvous.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "tern/math.hpp"

namespace tern::coord {

void RendezvousConfig::validate() const {
  auto need = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("rendezvous: ") + what);
  };
  need(std::isfinite(Va_min) && Va_min > 0.0, "Va_min must be > 0");
  need(std::isfinite(Va_max) && Va_max >= Va_min, "Va_max must be >= Va_min");
  need(Va_nominal >= Va_min && Va_nominal <= Va_max, "Va_nominal must lie in [Va_min, Va_max]");
  need(std::isfinite(turn_radius) && turn_radius > 0.0, "turn_radius must be > 0");
  need(std::isfinite(time_tolerance) && time_tolerance >= 0.0, "time_tolerance must be >= 0");
}

double path_length(const VehicleKinematics& k, const Vec2& point, const RendezvousConfig& cfg) {
  return turn_then_line_length(k.p, k.chi, point, cfg.turn_radius);
}

double time_to_go(const VehicleKinematics& k, const Vec2& point, double length, double Va) {
  const Vec2 q = direction_to(k.p, point, k.chi);
  return length / ground_speed(Va, k.wind, q);
}

double arrival_time(double t, const std::vector<VehicleKinematics>& ks, const Vec2& point, const RendezvousConfig& cfg) {
  double T = t;
  for (const auto& k : ks) T = std::max(T, t + time_to_go(k, point, path_length(k, point, cfg), cfg.Va_nominal));
  return T;
}

double arrival_time_slip(double t, double T, const std::vector<VehicleKinematics>& ks, const Vec2& point, const RendezvousConfig& cfg) {
  for (const auto& k : ks) T = std::max(T, t + time_to_go(k, point, path_length(k, point, cfg), cfg.Va_max));
  return T;
}

double predicted_arrival(double t, const VehicleKinematics& k, const Vec2& point, double Va, const RendezvousConfig& cfg) {
  return t + time_to_go(k, point, path_length(k, point, cfg), Va);
}

namespace {
/// The hold of step 4: a clockwise circle through the vehicle, then the leg at Va_nominal.
VehicleCommand hold_command(double t, double T, const VehicleKinematics& k, const Vec2& point, const RendezvousConfig& cfg) {
  VehicleCommand c;
  c.hold_center = k.p + cfg.turn_radius * Vec2(-std::sin(k.chi), std::cos(k.chi));
  VehicleKinematics from_centre = k;
  from_centre.p = c.hold_center;
  c.path_length = (point - c.hold_center).norm();
  c.Va_d = cfg.Va_nominal;
  c.hold_time = std::max(0.0, (T - t) - time_to_go(from_centre, point, c.path_length, cfg.Va_nominal));
  c.eta = t + c.hold_time + time_to_go(from_centre, point, c.path_length, cfg.Va_nominal);
  return c;
}
}  // namespace

VehicleCommand command_for(double t, double T, const VehicleKinematics& k, const Vec2& point, const RendezvousConfig& cfg) {
  VehicleCommand c;
  c.path_length = path_length(k, point, cfg);
  const Vec2 q = direction_to(k.p, point, k.chi);
  const double remaining = std::max(T - t, 1e-3);
  const double Va_needed = airspeed_for(c.path_length / remaining, k.wind, q);
  c.Va_d = saturate(Va_needed, cfg.Va_min, cfg.Va_max);
  c.eta = t + time_to_go(k, point, c.path_length, c.Va_d);
  if (c.eta < T - cfg.time_tolerance) {
    const VehicleCommand h = hold_command(t, T, k, point, cfg);
    if (h.hold_time > cfg.time_tolerance) return h;
  }
  return c;
}

}  // namespace tern::coord
