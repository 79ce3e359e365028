// core/apps/mavlink/plan_config.cpp: a QGroundControl plan flown in simulation (plan_config.hpp).
#include "mavlink/plan_config.hpp"

#include <cstdio>

#include <yaml-cpp/yaml.h>

#include "config/cli_overrides.hpp"
#include "config/error.hpp"
#include "mavlink/fence_items.hpp"
#include "mavlink/mission_items.hpp"
#include "mavlink/plan_file.hpp"

namespace tern::core {

namespace {

std::string exact(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

/// --set INSTANCE.origin_*=... for every sim_aero instance: the world's origin at the plan's home;
/// a path_planner's own mission_file is cleared (the plan's mission is the config's section).
void place_world(MissionConfig& config, const GeoPoint& home) {
  CliOverrides o;
  for (const InstanceConfig& i : config.plugins) {
    if (i.plugin == "path_planner" && i.params.count("mission_file") != 0) o.sets.push_back(i.name + ".mission_file=''");
    if (i.plugin != "sim_aero") continue;
    o.sets.push_back(i.name + ".origin_lat=" + exact(home.lat));
    o.sets.push_back(i.name + ".origin_lon=" + exact(home.lon));
    o.sets.push_back(i.name + ".origin_alt=" + exact(home.alt));
  }
  apply_overrides(config, o);
}

}  // namespace

void apply_plan(MissionConfig& config, const std::string& file) {
  try {
    const mavlink::Plan plan = mavlink::read_plan(file);
    const GeoOrigin home(plan.home);
    const path::Mission mission = mavlink::to_mission(plan.mission, home);
    if (mission.waypoints.empty()) throw ConfigError(file + ": mission.items: no item to fly");
    config.mission = YAML::Load(mavlink::mission_text(mission));
    config.root["mission"] = config.mission;
    place_world(config, plan.home);
    if (!plan.fence.empty()) {
      config.failsafes.geofence.zones = mavlink::to_zones(plan.fence, home);
      config.failsafes.geofence.enabled = true;
    }
    if (!plan.rally.empty()) config.failsafes.rally = mavlink::to_rally(plan.rally, home);
    config.overrides.push_back("--plan " + file);
  } catch (const mavlink::PlanError& e) {
    throw ConfigError(std::string("--plan: ") + e.what());
  } catch (const mavlink::ItemError& e) {
    throw ConfigError("--plan: " + file + ": " + e.what());
  }
}

}  // namespace tern::core
