// Registers @CLASS@ as the plugin of libtern_@NAME@.so (one TERN_PLUGIN per shared object).
#include "plugin.hpp"

TERN_PLUGIN(@CLASS@, "@NAME@", tern::PluginKind::io,
            "kinematic guidance model of an aircraft under autopilot control (uavbook sec. 9.4)")
