// Registers @CLASS@ as the plugin of libtern_@NAME@.so (one TERN_PLUGIN per shared object).
#include "plugin.hpp"

TERN_PLUGIN(@CLASS@, "@NAME@", tern::PluginKind::path_manager,
            "waypoint-to-waypoint straight lines (uavbook Algorithm 5)")
