// core/apps/commands/flown_mission.hpp: the mission a run flew, read back from its log: the path
// planner's last waypoint list (topic `waypoints`, tern/WaypointList), with whatever a ground
// station uploaded or edited and a failsafe added in flight. `tern export plan RUN` writes it as a
// QGroundControl plan (commands/plan_export.hpp).
//
// The list is logged as two tables (core/host/record/flight_recorder.cpp): `waypoints` (one row per
// list: stamp, revision, count, loop, loops, immediate) and `waypoints_items` (one row per item of
// a list: its revision, index and the tern/Waypoint fields). They are read from RUN/topics/ (CSV
// log), else from RUN/flight.mcap (only those two channels decoded, export/mcap_csv_export.hpp,
// into a scratch directory that is removed).
#pragma once

#include <filesystem>
#include <optional>

#include "tern/msg/path.hpp"

namespace tern::core {

/// The last waypoint list run directory `run` logged, its items those of its revision; nullopt
/// when the log has no `waypoints` table or it is empty (no path planner ran). Throws ConfigError
/// (a table that is not numbers, a list whose items are missing or out of range: one line naming
/// the file) and McapError (a corrupt flight.mcap).
std::optional<msg::WaypointList> last_waypoint_list(const std::filesystem::path& run);

}  // namespace tern::core
