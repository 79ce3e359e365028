// The coordination plugins' shared ports, frames and edits; see fleet.hpp.
#include "fleet.hpp"

#include <cmath>

#include <spdlog/spdlog.h>

namespace tern::coord {

namespace {
bool finite_state(const msg::State& x) {
  return std::isfinite(x.p_n) && std::isfinite(x.p_e) && std::isfinite(x.p_d) && std::isfinite(x.chi) && std::isfinite(x.w_n) &&
         std::isfinite(x.w_e) && std::isfinite(x.origin_lat) && std::isfinite(x.origin_lon) && std::isfinite(x.origin_alt) &&
         std::fabs(x.origin_lat) <= 90.0;
}
}  // namespace

void FleetPlugin::declare_fleet() {
  names_ = context().vehicles();
  declare(origin_, "origin", std::vector<double>{0.0, 0.0, 0.0},
          ParamSpec("deg|m", -1000.0, 20000.0, "common frame origin [lat deg, lon deg, alt m MSL] the positions are given in")
              .of_size(3)
              .start_only());
  declare(start_phase_, "start_phase", "cruise",
          ParamSpec("", 0, 0, "plan once every vehicle is: cruise (in the cruise phase, estimate valid) or valid (estimate valid)")
              .one_of({"cruise", "valid"}));
  const auto& o = origin_();
  if (std::fabs(o[0]) > 90.0 || std::fabs(o[1]) > 180.0)
    throw ParamError(context().instance_name() + ".origin: latitude must lie in [-90, 90] and longitude in [-180, 180]");
  if (names_.empty() && !context().describing())
    throw ParamError(context().instance_name() + ": a coordination plugin needs a multi-vehicle mission (vehicles:)");
  for (const auto& v : names_) {
    auto p = std::make_unique<VehiclePorts>();
    declare(p->state, v + "/state", "vehicle " + v + "'s estimate (its own NED frame)");
    declare(p->phase, v + "/flight_phase", "vehicle " + v + "'s flight phase (start_phase = cruise)", Need::optional);
    declare(p->edit, v + "/mission_edit", "mission edits for vehicle " + v + "'s path planner");
    ports_.push_back(std::move(p));
  }
  fleet_ = FleetFlight(names_.size());
}

std::optional<std::size_t> FleetPlugin::index_of(const std::string& name) const {
  for (std::size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == name) return i;
  return std::nullopt;
}

bool FleetPlugin::phase_ok(std::size_t i) {
  if (start_phase_() != "cruise") return true;
  const auto& in = ports_[i]->phase;
  if (!in.connected()) {
    if (!fleet_.warned_phase[i]) log().warn("{}/flight_phase is not connected: {} counts once its estimate is valid", names_[i], names_[i]);
    fleet_.warned_phase[i] = true;
    return true;
  }
  return in.has_value() && in->phase == msg::Phase::cruise;
}

std::optional<Observed> FleetPlugin::observe(std::size_t i, bool for_start) {
  const auto& in = ports_[i]->state;
  if (!in.has_value()) return std::nullopt;
  const msg::State& x = *in;
  if (!x.valid || !x.origin_valid) return std::nullopt;
  if (!finite_state(x)) {
    if (!fleet_.warned_nan[i]) log().warn("{}/state has a non-finite field or origin: ignored while it lasts", names_[i]);
    fleet_.warned_nan[i] = true;
    return std::nullopt;
  }
  if (for_start && !phase_ok(i)) return std::nullopt;
  const GeoPoint g = GeoOrigin(x.origin_lat, x.origin_lon, x.origin_alt).to_geodetic(Eigen::Vector3d(x.p_n, x.p_e, x.p_d));
  Observed o;
  o.ned = frame().to_ned(g);
  o.chi = x.chi;
  o.wind = Vec2(x.w_n, x.w_e);
  return o;
}

GeoOrigin FleetPlugin::frame() const {
  const auto& o = origin_();
  return GeoOrigin(o[0], o[1], o[2]);
}

msg::Waypoint FleetPlugin::lla_waypoint(const Eigen::Vector3d& ned) const {
  const GeoPoint g = frame().to_geodetic(ned);
  msg::Waypoint wp;
  wp.lla = true;
  wp.w = Eigen::Vector3d(g.lat, g.lon, g.alt);
  return wp;
}

void FleetPlugin::queue_add(std::size_t i, const msg::Waypoint& wp, bool set_current) {
  msg::MissionEdit e;
  e.op = msg::MissionEdit::add;
  e.waypoint = wp;
  e.set_current_wp = set_current;
  e.publish_now = true;
  e.id = fleet_.next_id++;
  if (set_current) fleet_.pending[i].clear();  // a new list replaces what was still to come
  fleet_.pending[i].push_back(e);
}

void FleetPlugin::send_queued(Nanos now) {
  for (std::size_t i = 0; i < ports_.size(); ++i) {
    auto& q = fleet_.pending[i];
    if (q.empty()) continue;
    msg::MissionEdit e = q.front();
    q.pop_front();
    e.stamp = now;
    ports_[i]->edit.publish(e);
    ++fleet_.sent;
  }
}

}  // namespace tern::coord
