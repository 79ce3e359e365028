// Registers @CLASS@ as the plugin of libtern_@NAME@.so (one TERN_PLUGIN per shared object).
#include "plugin.hpp"

TERN_PLUGIN(@CLASS@, "@NAME@", tern::PluginKind::coordination,
            "gathering: every vehicle loiters over one point at its own altitude; arrivals and separation")
