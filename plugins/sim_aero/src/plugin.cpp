// Registers the sim_aero plugin (libtern_sim_aero.so).
#include "sim_aero_plugin.hpp"

TERN_PLUGIN(tern::sim_aero::SimAero, "sim_aero", tern::PluginKind::io,
            "6-DOF fixed-wing simulator (uavbook model) with wind, turbulence, ground and sensors");
