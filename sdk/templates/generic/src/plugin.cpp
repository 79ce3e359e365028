// Registers @CLASS@ as the plugin of libtern_@NAME@.so (one TERN_PLUGIN per shared object).
#include "plugin.hpp"

TERN_PLUGIN(@CLASS@, "@NAME@", tern::PluginKind::generic,
            "flight monitor: low-airspeed warnings and summary figures")
