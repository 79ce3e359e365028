// The missions of a config, checked before flying. See mission_check.hpp.
#include "commands/mission_check.hpp"

#include <algorithm>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "config/error.hpp"
#include "flight/host.hpp"
#include "tern/path/mission_check.hpp"

namespace tern::core {

namespace {

std::optional<double> number(const Instance& inst, const std::string& name) {
  const ParamBase* p = inst.plugin->find_param(name);
  if (p == nullptr) return std::nullopt;
  const ParamValue v = p->value();
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  return std::nullopt;
}

std::string text(const Instance& inst, const std::string& name) {
  const ParamBase* p = inst.plugin->find_param(name);
  if (p == nullptr) return "";
  const ParamValue v = p->value();
  const auto* s = std::get_if<std::string>(&v);
  return s ? *s : "";
}

/// What the checks compare against: the simulator's origin, the path manager's turn radius, the
/// config's limits.
path::MissionLimits limits_of(const Host& host) {
  const MissionConfig& c = host.config();
  path::MissionLimits l;
  l.max_distance = c.check.max_waypoint_distance;
  l.max_distance_name = "check.max_waypoint_distance";
  l.origin = world_origin(host);
  for (const auto& inst : host.instances()) {
    if (inst->info.name == "path_manager") {
      const auto r = number(*inst, "R_min");
      if (r && (!l.R_min || *r > *l.R_min)) {
        l.R_min = r;
        l.R_min_name = inst->cfg.name + ".R_min";
        l.min_separation = number(*inst, "min_separation").value_or(l.min_separation);
      }
    }
  }
  const GeofenceConfig& fence = c.failsafes.geofence;
  if (fence.enabled) {
    l.fence_max_distance = fence.max_distance;
    l.fence_min_altitude = fence.min_altitude;
    l.fence_max_altitude = fence.max_altitude;
  }
  return l;
}

/// One line for a mission that cannot be read; an unknown key gets the closest valid one.
std::string read_error(const path::MissionError& e) {
  if (e.unknown_key().empty()) return e.what();
  const std::string hint = did_you_mean(e.unknown_key(), e.expected_keys());
  if (hint.empty()) return e.what();
  return e.where() + "unknown key '" + e.unknown_key() + "'" + hint;
}

void check_one(const path::Mission& m, const path::MissionLimits& l, MissionReport& r) {
  for (const auto& p : path::check_mission(m, l)) (p.error ? r.errors : p.note ? r.notes : r.warnings).push_back(p.text);
}

}  // namespace

MissionReport check_missions(const Host& host) {
  const MissionConfig& c = host.config();
  const path::MissionLimits limits = limits_of(host);
  MissionReport r;
  std::set<std::string> seen;  // planners reading the same mission: checked once
  for (const auto& inst : host.instances()) {
    if (inst->info.name != "path_planner") continue;
    const std::string file = text(*inst, "mission_file");
    if (!seen.insert(file).second) continue;
    try {
      if (!file.empty())
        check_one(path::load_mission_file(file), limits, r);
      else if (c.mission && !c.mission.IsNull())
        check_one(path::parse_mission_section(c.mission, c.dir, c.file.string()), limits, r);
    } catch (const path::MissionError& e) {
      r.errors.push_back(read_error(e));
    }
  }
  return r;
}

std::optional<GeoPoint> world_origin(const Host& host) {
  for (const auto& inst : host.instances()) {
    if (inst->info.name != "sim_aero") continue;
    const auto lat = number(*inst, "origin_lat"), lon = number(*inst, "origin_lon"), alt = number(*inst, "origin_alt");
    if (lat && lon && alt) return GeoPoint{*lat, *lon, *alt};
  }
  return std::nullopt;
}

std::optional<path::Mission> planned_mission(const Host& host) {
  const MissionConfig& c = host.config();
  for (const auto& inst : host.instances()) {
    if (inst->info.name != "path_planner") continue;
    const std::string file = text(*inst, "mission_file");
    if (!file.empty()) return path::load_mission_file(file);
    if (c.mission && !c.mission.IsNull()) return path::parse_mission_section(c.mission, c.dir, c.file.string());
    return std::nullopt;
  }
  return std::nullopt;
}

MissionReport check_missions(const MissionConfig& config) {
  HostOptions o;
  o.describing = true;
  o.quiet = true;
  Host host(config, o);
  host.build();
  return check_missions(host);
}

}  // namespace tern::core
