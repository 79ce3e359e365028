// core/apps/commands/plan_export.cpp: a config's mission as a QGroundControl plan (plan_export.hpp).
#include "commands/plan_export.hpp"

#include "commands/mission_check.hpp"
#include "config/error.hpp"
#include "flight/host.hpp"
#include "mavlink/fence_items.hpp"
#include "mavlink/mission_items.hpp"
#include "mavlink/plan_file.hpp"

namespace tern::core {
namespace {

/// The items of the mission the config's path planner flies.
std::vector<mavlink::MissionItemInt> config_items(const Host& host, const GeoOrigin& home) {
  std::optional<path::Mission> m;
  try {
    m = planned_mission(host);
  } catch (const path::MissionError& e) {
    throw ConfigError(e.what());
  }
  if (!m) throw ConfigError(host.config().file.string() + ": no path_planner mission to write");
  m->waypoints = path::resolve_to_ned(m->waypoints, home.origin());
  return mavlink::to_items(*m, home);
}

}  // namespace

std::string plan_of(const Host& host, const msg::WaypointList* flown) {
  const std::string config = host.config().file.string();
  const std::optional<GeoPoint> origin = world_origin(host);
  if (!origin) throw ConfigError(config + ": no sim_aero instance: a plan needs the home its items are placed about");
  const GeoOrigin home(*origin);
  mavlink::Plan plan;
  plan.home = *origin;
  plan.mission = flown ? mavlink::to_items(mavlink::to_mission(*flown), home) : config_items(host, home);  // loops kept: DO_JUMP
  const FailsafeConfig& f = host.config().failsafes;
  plan.fence = mavlink::fence_items(f.geofence.zones, home);
  plan.rally = mavlink::rally_items(f.rally, home);
  for (const auto& inst : host.instances())
    if (inst->info.name == "path_manager")
      if (const ParamBase* p = inst->plugin->find_param("default_airspeed")) {
        const ParamValue Va = p->value();
        if (const auto* v = std::get_if<double>(&Va)) plan.cruise_speed = *v;
      }
  return mavlink::plan_json(plan);
}

}  // namespace tern::core
