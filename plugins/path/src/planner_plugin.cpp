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
  m.loiter = {w.loiter_radius, w.loiter_direction, w.loiter_time, w.loiter_turns};
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
  declare(edit_, "mission_edit", "runtime mission edits (host command line, DDS bridge)", Need::optional);
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
  wps_ = std::move(m.waypoints);
  loop_ = m.loop;
  dirty_ = true;
  waiting_logged_ = false;
  if (context().describing()) return;
  log().info("mission {} ({}): {} waypoints{}{}", why, m.source, wps_.size(), loop_ ? ", loop" : "",
             m.has_lla() ? ", some in lat/lon" : "");
}

void PlannerPlugin::start() {
  if (mission_file_() != configured_from_) load_configured();  // changed between flights
  dirty_ = true;
}

void PlannerPlugin::reset() {
  replace(configured_, "reset to the configured one");
  origin_.reset();
}

void PlannerPlugin::apply_edit(const msg::MissionEdit& e) {
  ++edits_;
  const std::string tag = "mission_edit " + std::to_string(e.id);
  switch (e.op) {
    case msg::MissionEdit::add: {
      MissionWaypoint wp = from_msg(e.waypoint);
      try {
        validate_waypoint(wp, tag);
      } catch (const MissionError& err) {
        log().error("{}: refused", err.what());
        return;
      }
      if (e.set_current_wp) {
        wps_.assign(1, wp);
        immediate_ = true;
      } else if (wps_.size() >= msg::WaypointList::kCapacity) {
        log().error("{}: refused, the mission already holds {} waypoints (the most a WaypointList carries)", tag, wps_.size());
        return;
      } else {
        wps_.push_back(wp);
      }
      log().info("{}: waypoint added ({} now){}", tag, wps_.size(), e.set_current_wp ? ", starting a new list" : "");
      if (e.publish_now || e.set_current_wp)
        dirty_ = true;
      else
        held_ = true;
      return;
    }
    case msg::MissionEdit::clear:
      wps_.clear();
      dirty_ = true;
      log().info("{}: mission cleared", tag);
      return;
    case msg::MissionEdit::set_current: {
      if (e.index >= wps_.size()) {
        log().error("{}: set_current index {} refused, the mission has {} waypoints", tag, e.index, wps_.size());
        return;
      }
      // The published list starts at the new current waypoint: a looping mission keeps its
      // cycle (rotated), a one-pass mission drops the waypoints before it.
      if (loop_)
        std::rotate(wps_.begin(), wps_.begin() + e.index, wps_.end());
      else
        wps_.erase(wps_.begin(), wps_.begin() + e.index);
      dirty_ = true;
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
  if (edit_.updated()) {
    apply_edit(*edit_);
    if (edit_->publish_now && held_) {
      held_ = false;
      dirty_ = true;
    }
  }
  if (state_.has_value() && state_->origin_valid) {
    const GeoPoint o{state_->origin_lat, state_->origin_lon, state_->origin_alt};
    const bool changed = !origin_ || origin_->lat != o.lat || origin_->lon != o.lon || origin_->alt != o.alt;
    if (changed && std::isfinite(o.lat) && std::isfinite(o.lon) && std::isfinite(o.alt) && std::fabs(o.lat) <= 90.0 &&
        std::fabs(o.lon) <= 180.0) {
      const bool had = origin_.has_value();
      origin_ = o;
      const bool any_lla = std::any_of(wps_.begin(), wps_.end(), [](const auto& w) { return w.lla; });
      if (any_lla) {
        dirty_ = true;
        if (had) log().warn("origin moved: lat/lon waypoints converted again");
      }
    }
  }
  if (!dirty_) return;
  const bool any_lla = std::any_of(wps_.begin(), wps_.end(), [](const auto& w) { return w.lla; });
  if (any_lla && !origin_) {
    if (!waiting_logged_) log().info("lat/lon waypoints wait for the estimator's origin before the list is published");
    waiting_logged_ = true;
    return;
  }
  const auto ned = any_lla ? resolve_to_ned(wps_, *origin_) : wps_;
  msg::WaypointList out;
  out.stamp = now;
  out.revision = ++revision_;
  out.loop = loop_;
  out.count = static_cast<std::uint32_t>(ned.size());
  out.immediate = immediate_;
  for (std::size_t i = 0; i < ned.size(); ++i) out.items[i] = to_msg(ned[i]);
  waypoints_.publish(out);
  dirty_ = false;
  immediate_ = false;
}

std::vector<std::pair<std::string, double>> PlannerPlugin::summary() const {
  return {{"mission_revisions", static_cast<double>(revision_)}, {"mission_edits", static_cast<double>(edits_)}};
}

}  // namespace tern::path
