// core/apps/mavlink/plan_config.hpp: a QGroundControl plan flown in simulation unchanged
// (`tern fly CONFIG --plan FILE.plan`; plan_file.hpp reads it; docs/ground-station.md, "Plan files").
#pragma once

#include <string>

#include "config/config.hpp"

namespace tern::core {

/// Makes `config` fly the plan in `file`: its mission items (converted as a MAVLink upload is,
/// mission_items.hpp: what an upload refuses is refused here, naming the item) replace the
/// config's `mission:` section (and a path_planner's own mission_file); its planned home becomes
/// every sim_aero instance's origin (origin_lat, origin_lon, origin_alt, as --set would set them);
/// its geofence and rally points become the failsafes' zones and rally points (fence_items.hpp).
/// config.yaml records `--plan FILE`. Throws ConfigError, one line naming the file and the item
/// or field.
void apply_plan(MissionConfig& config, const std::string& file);

}  // namespace tern::core
