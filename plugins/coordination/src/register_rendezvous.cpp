#include "rendezvous_plugin.hpp"
TERN_PLUGIN(tern::coord::RendezvousPlugin, "coord_rendezvous", tern::PluginKind::coordination,
            "timed rendezvous: every vehicle at one point at one time, vertically separated (airspeeds, holds)");
