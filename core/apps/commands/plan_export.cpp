// core/apps/commands/plan_export.cpp: a config's mission as a QGroundControl plan (plan_export.hpp).
#include "commands/plan_export.hpp"

#include "commands/mission_check.hpp"
#include "config/error.hpp"
#include "flight/host.hpp"
#include "mavlink/fence_items.hpp"
#include "mavlink/mission_items.hpp"
#include "mavlink/plan_file.hpp"

namespace tern::core {

std::string plan_of(const Host& host) {
  const std::string config = host.config().file.string();
  const std::optional<GeoPoint> origin = world_origin(host);
  if (!origin) throw ConfigError(config + ": no sim_aero instance: a plan needs the home its items are placed about");
  std::optional<path::Mission> m;
  try {
    m = planned_mission(host);
  } catch (const path::MissionError& e) {
    throw ConfigError(e.what());
  }
  if (!m) throw ConfigError(config + ": no path_planner mission to write");
  const GeoOrigin home(*origin);
  m->waypoints = path::resolve_to_ned(m->waypoints, *origin);
  mavlink::Plan plan;
  plan.home = *origin;
  plan.mission = mavlink::to_items(*m, home);
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
