// The control_tecs plugin's registration (the class is in control_tecs.hpp).
#include "control_tecs.hpp"

TERN_PLUGIN(tern::control::ControlTecs, "control_tecs", tern::PluginKind::controller,
            "total energy control (longitudinal) with the successive-loop lateral autopilot");
