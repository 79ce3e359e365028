#include "adapters.hpp"
TERN_PLUGIN(tern::path::FollowerPlugin, "path_follower", tern::PluginKind::path_follower,
            "current path -> course/altitude/airspeed commands by vector fields (Beard & McLain ch. 10)");
