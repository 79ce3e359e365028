// Registers @CLASS@ as the plugin of libtern_@NAME@.so (one TERN_PLUGIN per shared object).
#include "plugin.hpp"

TERN_PLUGIN(@CLASS@, "@NAME@", tern::PluginKind::controller,
            "successive loop closure: course, altitude and airspeed hold (uavbook ch. 6)")
