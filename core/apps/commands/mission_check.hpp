// core/apps/commands/mission_check.hpp: the missions a config will fly, checked before it flies (`tern
// check`; `tern fly` and `tern serve` before any flight). For every path_planner instance: the
// file its `mission_file` parameter names, else the config's `mission:` section, read with the planner's
// own parser (tern/path/mission.hpp: keys, types, latitude/longitude ranges) and checked by
// tern/path/mission_check.hpp (below home, too far from home, legs shorter than the turn radius;
// warnings for what looks wrong) against:
//   home          the NED origin; latitude/longitude waypoints are placed about the simulator's
//                 origin (sim_aero's origin_lat, origin_lon, origin_alt), not at all without one
//   distance      check.max_waypoint_distance (config.hpp, default 5 km)
//   turn radius   the path manager's R_min and min_separation (the largest R_min of path_manager
//                 instances)
//   geofence      failsafes.geofence's max_distance, min_altitude, max_altitude, when configured
// and a final land item's approach (entry point in the fence, room for the turn onto the final,
// touchdown altitude, the final's length: tern/path/mission_check.hpp (a)-(d)).
// Each problem is one line naming file:line and the field.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "tern/geodesy.hpp"
#include "tern/path/mission.hpp"

namespace tern::core {

class Host;

struct MissionReport {
  std::vector<std::string> errors;    ///< refuse the flight
  std::vector<std::string> warnings;  ///< fly, but say so
  std::vector<std::string> notes;     ///< expected by design (a landing through the geofence floor): `tern check` says so
};

/// The problems of the missions of `host` (built, describing or not; its parameter values are
/// the configured ones).
MissionReport check_missions(const Host& host);

/// The same for `config`, through a host built to describe it (plugins configured, nothing flown).
/// Throws ConfigError as building a host does.
MissionReport check_missions(const MissionConfig& config);

/// The world's origin of `host`: its first sim_aero instance's origin_lat, origin_lon, origin_alt
/// (none: no simulator; then the origin is the first GNSS fix).
std::optional<GeoPoint> world_origin(const Host& host);

/// The mission `host`'s first path_planner flies: its mission_file, else the config's `mission:`
/// section (none: no planner, or neither). Throws path::MissionError.
std::optional<path::Mission> planned_mission(const Host& host);

}  // namespace tern::core
