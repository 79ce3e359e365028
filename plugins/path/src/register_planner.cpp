#include "adapters.hpp"
TERN_PLUGIN(tern::path::PlannerPlugin, "path_planner", tern::PluginKind::path_planner,
            "mission waypoints (NED, lat/lon, ROSplane files) with runtime edits -> waypoints");
