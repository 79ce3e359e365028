// The control_slc plugin's registration (the class is in control_slc.hpp).
#include "control_slc.hpp"

TERN_PLUGIN(tern::control::ControlSlc, "control_slc", tern::PluginKind::controller,
            "successive loop closure autopilot (uavbook ch. 6, ROSplane 2.0)");
