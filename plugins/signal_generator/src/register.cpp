#include "signal_generator_plugin.hpp"
TERN_PLUGIN(tern::signal::SignalGeneratorPlugin, "signal_generator", tern::PluginKind::generic,
            "step, square, sine, triangle, sawtooth or doublet on one loop's command, for tuning (after rosplane_tuning)");
