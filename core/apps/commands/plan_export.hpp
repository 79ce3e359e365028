// core/apps/commands/plan_export.hpp: a config's mission as a QGroundControl plan (`tern export plan`;
// mavlink/plan_file.hpp writes the file; docs/ground-station.md, "Plan files").
#pragma once

#include <string>

#include "tern/msg/path.hpp"

namespace tern::core {

class Host;

/// The plan of what `host` (built; describing will do) flies, as QGroundControl's .plan JSON: the
/// first path_planner's mission as MISSION items (mission_items.hpp to_items: its loops as
/// DO_JUMP), home at the simulator's origin, the failsafes' geofence zones and rally points, the
/// path manager's default_airspeed as cruiseSpeed. Throws ConfigError (no simulator: no home to
/// place the items about; no mission; a mission that cannot be read). With `flown` (a run's last
/// waypoint list, commands/flown_mission.hpp), that list is the plan's mission instead of the
/// config's: the mission as the run flew it, ground-station uploads and edits included.
std::string plan_of(const Host& host, const msg::WaypointList* flown = nullptr);

}  // namespace tern::core
