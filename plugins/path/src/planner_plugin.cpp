// path_planner adapter. See adapters.hpp and tern/path/mission.hpp.
#include <algorithm>
#include <cmath>
#include <cstring>

#include <spdlog/spdlog.h>

#include "adapters.hpp"

namespace tern::path {

namespace {
MissionWaypoint from_msg(const msg::Waypoint& w) {
  MissionWaypoint m;
  m.w = w.w;
  m.lla = w.lla;
  m.chi_d = w.chi_d;
  m.use_chi = w.use_chi;
  m.Va_d = w.Va_d;
  m.type = item_type_of(w.type);
  m.Vg_min = w.Vg_min;
  m.loiter = {w.loiter_radius, w.loiter_direction, w.loiter_time, w.loiter_turns, w.loiter_to_altitude};
  m.land = {w.land_glide_slope, w.land_flare_height, w.land_decision_height};
  return m;
}

msg::Waypoint to_msg(const MissionWaypoint& m) {
  msg::Waypoint w;
  w.w = m.w;
  w.lla = m.lla;
  w.chi_d = m.chi_d;
  w.use_chi = m.use_chi;
  w.Va_d = m.Va_d;
  w.type = msg_item_type(m.type);
  w.loiter_radius = m.loiter.radius;
  w.loiter_direction = static_cast<std::int8_t>(m.loiter.direction >= 0 ? 1 : -1);
  w.loiter_time = m.loiter.time;
  w.loiter_turns = m.loiter.turns;
  w.loiter_to_altitude = m.loiter.to_altitude;
  w.Vg_min = m.Vg_min;
  w.land_glide_slope = m.land.glide_slope;
  w.land_flare_height = m.land.flare_height;
  w.land_decision_height = m.land.decision_height;
  return w;
}

void check_capacity(const Mission& m) {
  if (m.waypoints.size() > msg::WaypointList::kCapacity)
    throw MissionError(m.source + ": " + std::to_string(m.waypoints.size()) + " waypoints, more than the " +
                       std::to_string(msg::WaypointList::kCapacity) + " a WaypointList holds");
}
}  // namespace

void PlannerPlugin::configure() {
  declare(state_, "state", "vehicle state: its origin converts lat/lon waypoints to NED", Need::optional);
  // The host publishes one edit per tick and the planner may step less often (10 Hz under a 400 Hz
  // tick): a queue, so that edits in quick succession (a ground station's upload then set current)
  // are each applied, in order
  declare(edit_, "mission_edit", "runtime mission edits (host command line, DDS bridge, MAVLink)", Need::optional,
          Queue{msg::MissionEdit::kQueue});
  declare(waypoints_, "waypoints", "the mission, NED, republished with a higher revision on every change");
  declare(mission_file_, "mission_file", "",
          ParamSpec("", 0, 0,
                    "waypoint file (tern or ROSplane format) used instead of the config's mission: section; "
                    "empty: the section")
              .as_path()
              .start_only());
  if (context().describing()) return;
  load_configured();
}

void PlannerPlugin::load_configured() {
  if (!mission_file_().empty())
    configured_ = load_mission_file(mission_file_());
  else
    configured_ = parse_mission_section(context().mission(), context().config_dir());
  check_capacity(configured_);
  configured_from_ = mission_file_();
  replace(configured_, "configured");
}

void PlannerPlugin::replace(Mission m, const std::string& why) {
  f_.wps = std::move(m.waypoints);
  f_.loop = m.loop;
  f_.loops = m.loops;
  f_.dirty = true;
  f_.waiting_logged = false;
  if (context().describing()) return;
  log().info("mission {} ({}): {} waypoints{}{}", why, m.source, f_.wps.size(), f_.loop ? ", loop" : "",
             m.has_lla() ? ", some in lat/lon" : "");
}

void PlannerPlugin::start() {
  if (mission_file_() != configured_from_) load_configured();  // changed between flights
  f_.dirty = true;
}

void PlannerPlugin::reset() {
  f_ = Flight{};
  replace(configured_, "reset to the configured one");
}

void PlannerPlugin::add_item(const msg::MissionEdit& e, const std::string& tag) {
  if (e.waypoint.type > msg::Waypoint::land) {
    log().error("{}: refused: type {} is not a mission item type (0 waypoint, 1 loiter, 2 return_home, 3 land)", tag,
                static_cast<int>(e.waypoint.type));
    return;
  }
  const MissionWaypoint wp = from_msg(e.waypoint);
  Mission next;
  next.source = tag;
  next.waypoints = e.set_current_wp ? std::vector<MissionWaypoint>{} : f_.wps;
  next.waypoints.push_back(wp);
  try {
    validate_waypoint(wp, tag);
    check_land_last(next);
  } catch (const MissionError& err) {
    log().error("{}: refused", err.what());
    return;
  }
  if (!e.set_current_wp && next.waypoints.size() > msg::WaypointList::kCapacity) {
    log().error("{}: refused, the mission already holds {} waypoints (the most a WaypointList carries)", tag, f_.wps.size());
    return;
  }
  f_.wps = std::move(next.waypoints);
  f_.immediate = f_.immediate || e.set_current_wp;
  if (e.set_current_wp) f_.loops = 0;  // a new list: not the configured mission's loop count
  log().info("{}: {} added ({} now){}", tag, item_type_name(wp.type), f_.wps.size(), e.set_current_wp ? ", starting a new list" : "");
  if (wp.type == ItemType::land && f_.loop && f_.loops == 0) {
    // a loop without a count would never reach the landing (mission.hpp): the items once more
    f_.loop = false;
    if (!e.set_current_wp) log().info("{}: the mission no longer loops: its items once more from the first, then the landing", tag);
  }
  if (e.publish_now || e.set_current_wp)
    f_.dirty = true;
  else
    f_.held = true;
}

void PlannerPlugin::apply_edit(const msg::MissionEdit& e) {
  ++f_.edits;
  const std::string tag = "mission_edit " + std::to_string(e.id);
  switch (e.op) {
    case msg::MissionEdit::add: add_item(e, tag); return;
    case msg::MissionEdit::clear:
      f_.wps.clear();
      f_.dirty = true;
      log().info("{}: mission cleared", tag);
      return;
    case msg::MissionEdit::set_current: {
      if (e.index >= f_.wps.size()) {
        log().error("{}: set_current index {} refused, the mission has {} waypoints", tag, e.index, f_.wps.size());
        return;
      }
      // The published list starts at the new current waypoint: a looping mission keeps its
      // cycle (rotated; a final land item stays last, after it), a one-pass mission (or one sent
      // to its land item) drops the waypoints before it.
      const bool lands = f_.wps.back().type == ItemType::land;
      const auto cycle_end = lands ? f_.wps.end() - 1 : f_.wps.end();
      if (f_.loop && f_.wps.begin() + e.index < cycle_end)
        std::rotate(f_.wps.begin(), f_.wps.begin() + e.index, cycle_end);
      else
        f_.wps.erase(f_.wps.begin(), f_.wps.begin() + e.index);
      f_.dirty = true;
      log().info("{}: waypoint {} is now the next one (list renumbered from it)", tag, e.index);
      return;
    }
    case msg::MissionEdit::load_file: {
      const auto end = std::find(e.file.begin(), e.file.end(), '\0');
      const std::string file(e.file.begin(), end);
      try {
        Mission m = load_mission_file(file);
        check_capacity(m);
        replace(std::move(m), "loaded by " + tag);
      } catch (const std::exception& err) {
        log().error("{}: load_file refused, the mission is unchanged: {}", tag, err.what());
      }
      return;
    }
    default: log().error("{}: unknown operation {} ignored", tag, static_cast<int>(e.op));
  }
}

void PlannerPlugin::step(Nanos now) {
  if (edit_.missed() > 0) log().error("{} mission edits arrived faster than this planner steps and were lost", edit_.missed());
  for (const msg::MissionEdit& e : edit_.received()) {
    apply_edit(e);
    if (e.publish_now && f_.held) {
      f_.held = false;
      f_.dirty = true;
    }
  }
  if (state_.has_value() && state_->origin_valid) {
    const GeoPoint o{state_->origin_lat, state_->origin_lon, state_->origin_alt};
    const bool changed = !f_.origin || f_.origin->lat != o.lat || f_.origin->lon != o.lon || f_.origin->alt != o.alt;
    if (changed && std::isfinite(o.lat) && std::isfinite(o.lon) && std::isfinite(o.alt) && std::fabs(o.lat) <= 90.0 &&
        std::fabs(o.lon) <= 180.0) {
      const bool had = f_.origin.has_value();
      f_.origin = o;
      const bool any_lla = std::any_of(f_.wps.begin(), f_.wps.end(), [](const auto& w) { return w.lla; });
      if (any_lla) {
        f_.dirty = true;
        if (had) log().warn("origin moved: lat/lon waypoints converted again");
      }
    }
  }
  if (!f_.dirty) return;
  const bool any_lla = std::any_of(f_.wps.begin(), f_.wps.end(), [](const auto& w) { return w.lla; });
  if (any_lla && !f_.origin) {
    if (!f_.waiting_logged) log().info("lat/lon waypoints wait for the estimator's origin before the list is published");
    f_.waiting_logged = true;
    return;
  }
  const auto ned = any_lla ? resolve_to_ned(f_.wps, *f_.origin) : f_.wps;
  msg::WaypointList out;
  out.stamp = now;
  out.revision = ++f_.revision;
  out.loop = f_.loop;
  out.loops = static_cast<std::uint32_t>(f_.loops);
  out.count = static_cast<std::uint32_t>(ned.size());
  out.immediate = f_.immediate;
  for (std::size_t i = 0; i < ned.size(); ++i) out.items[i] = to_msg(ned[i]);
  waypoints_.publish(out);
  f_.dirty = false;
  f_.immediate = false;
}

std::vector<std::pair<std::string, double>> PlannerPlugin::summary() const {
  return {{"mission_revisions", static_cast<double>(f_.revision)}, {"mission_edits", static_cast<double>(f_.edits)}};
}

}  // namespace tern::path
