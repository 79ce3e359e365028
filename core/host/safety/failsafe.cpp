#include "safety/failsafe.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

#include <fmt/format.h>

namespace tern::core {

namespace {
bool usable(const msg::State* s) {
  return s != nullptr && s->valid && std::isfinite(s->p_n) && std::isfinite(s->p_e) && std::isfinite(s->p_d);
}
}  // namespace

msg::Actuators termination_command(TerminateAction action, double max_deflection) {
  msg::Actuators a{};
  a.delta_t = 0.0;
  if (action == TerminateAction::spin) {
    a.delta_e = -max_deflection;  // trailing edge up: nose up (B&M sign: negative delta_e pitches up)
    a.delta_a = max_deflection;
    a.delta_r = max_deflection;
  }
  return a;
}

void FailsafeMonitor::restart() {
  last_position_.reset();
  gnss_lost_at_.reset();
  degraded_since_.reset();
  link_lost_at_.reset();
  terminated_ = false;
  fence_breached_at_.reset();
  floor_armed_ = false;
}

std::vector<FailsafeEvent> FailsafeMonitor::check(const FailsafeInputs& in) {
  std::vector<FailsafeEvent> out;
  if (usable(in.state)) last_position_ = Eigen::Vector3d(in.state->p_n, in.state->p_e, in.state->p_d);
  if (config_.gnss_loss.enabled) gnss(in, out);
  if (config_.link_loss.enabled) link(in, out);
  if (config_.geofence.enabled) geofence(in, out);
  return out;
}

void FailsafeMonitor::gnss(const FailsafeInputs& in, std::vector<FailsafeEvent>& out) {
  const GnssLossConfig& c = config_.gnss_loss;
  const bool degraded = in.state != nullptr && (in.state->degraded_sensors & msg::sensor_bit::gnss) != 0;
  if (!degraded)
    degraded_since_.reset();
  else if (!degraded_since_)
    degraded_since_ = in.now;
  if (!in.last_fix) return;  // no fix yet: nothing lost
  const double silent = to_seconds(in.now - *in.last_fix);
  const double flagged = degraded_since_ ? to_seconds(in.now - *degraded_since_) : 0.0;
  const bool lost = silent > c.timeout || flagged > c.timeout;
  if (gnss_lost_at_ && !lost && !degraded) {
    out.push_back(
        {in.now, "gnss_back", "none",
         fmt::format("GNSS fix back after {:.1f} s without; the aircraft keeps loitering (resume the mission with a mission edit)",
                     to_seconds(in.now - *gnss_lost_at_))});
    gnss_lost_at_.reset();
    return;
  }
  if (gnss_lost_at_ || !lost || !in.airborne || !last_position_) return;
  gnss_lost_at_ = in.now;
  const Eigen::Vector3d& p = *last_position_;
  const std::string why = silent > c.timeout ? fmt::format("no valid GNSS fix for {:.1f} s", silent)
                                             : fmt::format("the estimate has reported GNSS degraded for {:.1f} s", flagged);
  out.push_back({in.now, "gnss_loss", "loiter",
                 fmt::format("{} (timeout {} s): loiter at the dead-reckoned position n {:.1f} e {:.1f} m, altitude {:.1f} m", why,
                             c.timeout, p.x(), p.y(), -p.z()),
                 p, c.radius});
}

void FailsafeMonitor::link(const FailsafeInputs& in, std::vector<FailsafeEvent>& out) {
  const LinkLossConfig& c = config_.link_loss;
  if (!in.link_heard) return;  // no ground station: nothing to lose
  const double silent = to_seconds(in.now - *in.link_heard);
  if (link_lost_at_ && silent <= c.timeout) {
    out.push_back({in.now, "link_back", "none",
                   fmt::format("ground station heard again after {:.1f} s of silence; the aircraft keeps loitering at home", silent)});
    link_lost_at_.reset();
    return;
  }
  if (link_lost_at_) {
    if (c.terminate_after && !terminated_ && to_seconds(in.now - *link_lost_at_) >= *c.terminate_after) {
      terminated_ = true;
      FailsafeEvent e{
          in.now, "terminate", "terminate",
          fmt::format("ground link still lost {} s after the return home: flight termination ({}: motor off{})", *c.terminate_after,
                      c.terminate_action == TerminateAction::spin ? "spin" : "glide",
                      c.terminate_action == TerminateAction::spin ? ", full up elevator, full aileron and rudder" : ", surfaces neutral")};
      e.terminate = c.terminate_action;
      out.push_back(e);
    }
    return;
  }
  if (silent <= c.timeout || !in.airborne || !last_position_) return;
  link_lost_at_ = in.now;
  const double h = c.altitude.value_or(-last_position_->z());
  const Return r = return_point(last_position_->head<2>(), h, [](double rally_h) { return rally_h; });
  out.push_back({in.now, "link_loss", "return_home",
                 fmt::format("ground station silent for {:.1f} s (timeout {} s): return, {}", silent, c.timeout, r.detail), r.centre,
                 c.radius});
}

FailsafeMonitor::Breach FailsafeMonitor::fence_breach(const msg::State& s) const {
  const GeofenceConfig& c = config_.geofence;
  const double h = s.altitude();
  if (c.max_distance && std::hypot(s.p_n, s.p_e) > *c.max_distance) return Breach::max_distance;
  if (c.max_altitude && h > *c.max_altitude) return Breach::max_altitude;
  if (c.min_altitude && floor_armed_ && h < *c.min_altitude) return Breach::min_altitude;
  if (!inside_zones(c.zones, {s.p_n, s.p_e})) return Breach::zone;
  return Breach::none;
}

std::string FailsafeMonitor::describe(Breach b, const msg::State& s) const {
  const GeofenceConfig& c = config_.geofence;
  switch (b) {
    case Breach::max_distance:
      return fmt::format("{:.1f} m from home, beyond max_distance {} m", std::hypot(s.p_n, s.p_e), *c.max_distance);
    case Breach::max_altitude: return fmt::format("altitude {:.1f} m above max_altitude {} m", s.altitude(), *c.max_altitude);
    case Breach::min_altitude: return fmt::format("altitude {:.1f} m below min_altitude {} m", s.altitude(), *c.min_altitude);
    case Breach::zone: return fmt::format("n {:.1f} e {:.1f} m outside the fence's zones", s.p_n, s.p_e);
    case Breach::none: break;
  }
  return "";
}

void FailsafeMonitor::geofence(const FailsafeInputs& in, std::vector<FailsafeEvent>& out) {
  const GeofenceConfig& c = config_.geofence;
  if (!usable(in.state)) return;
  floor_armed_ = !in.landing && (floor_armed_ || (in.airborne && (!c.min_altitude || in.state->altitude() > *c.min_altitude)));
  const Breach breach = fence_breach(*in.state);
  if (fence_breached_at_ && breach == Breach::none) {
    out.push_back({in.now, "geofence_inside", "none",
                   fmt::format("inside the geofence again after {:.1f} s; the aircraft keeps loitering at home",
                               to_seconds(in.now - *fence_breached_at_))});
    fence_breached_at_.reset();
    return;
  }
  if (fence_breached_at_ || breach == Breach::none || !in.airborne) return;
  fence_breached_at_ = in.now;
  const double lo = c.min_altitude ? *c.min_altitude + c.altitude_margin : -1e9;
  const double hi = c.max_altitude ? *c.max_altitude - c.altitude_margin : 1e9;
  const auto clamped = [&](double h) { return std::clamp(h, lo, std::max(lo, hi)); };
  const std::string what = "geofence breached: " + describe(breach, *in.state);
  const Eigen::Vector3d here(in.state->p_n, in.state->p_e, -clamped(in.state->altitude()));
  switch (c.action) {
    case FenceAction::report: out.push_back({in.now, "geofence", "report", what + ": reported, the mission goes on"}); return;
    case FenceAction::loiter:
      out.push_back({in.now, "geofence", "loiter",
                     fmt::format("{}: loiter here (n {:.1f} e {:.1f} m) at altitude {:.1f} m", what, here.x(), here.y(), -here.z()), here,
                     c.radius});
      return;
    case FenceAction::return_home: {
      const Return r = return_point(here.head<2>(), clamped(in.state->altitude()), clamped);
      out.push_back({in.now, "geofence", "return_home", fmt::format("{}: return inside, {}", what, r.detail), r.centre, c.radius});
      return;
    }
  }
}

FailsafeMonitor::Return FailsafeMonitor::return_point(const Eigen::Vector2d& from, double home_h,
                                                      const std::function<double(double)>& clamp_h) const {
  const std::optional<std::size_t> i = nearest_rally(config_.rally, config_.geofence.zones, from);
  if (!i) return {Eigen::Vector3d(0.0, 0.0, -home_h), fmt::format("loiter at home at altitude {:.1f} m", home_h)};
  const Eigen::Vector3d& p = config_.rally[*i];
  const double h = clamp_h(p.z());
  return {Eigen::Vector3d(p.x(), p.y(), -h),
          fmt::format("loiter at rally point {} (n {:.1f} e {:.1f} m) at altitude {:.1f} m", *i, p.x(), p.y(), h)};
}

}  // namespace tern::core
