// Registers @CLASS@ as the plugin of libtern_@NAME@.so (one TERN_PLUGIN per shared object).
#include "plugin.hpp"

TERN_PLUGIN(@CLASS@, "@NAME@", tern::PluginKind::estimator,
            "complementary attitude filter with GNSS position and pitot airspeed")
