#include "formation_plugin.hpp"
TERN_PLUGIN(tern::coord::FormationPlugin, "coord_formation", tern::PluginKind::coordination,
            "leader-follower formation on one orbit: the followers' airspeeds hold an arc spacing behind the leader");
