#include "adapters.hpp"
TERN_PLUGIN(tern::path::ManagerPlugin, "path_manager", tern::PluginKind::path_manager,
            "waypoints -> current path: lines, fillets, Dubins paths (Beard & McLain ch. 11)");
