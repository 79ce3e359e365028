// core/host/flight/load_instances.hpp: every instance of a mission loaded and configured: the
// config's `plugins:` (from their libraries, in a child process with `isolate: true`, or another
// process's DDS topics with `plugin: external`), then the host's built-ins (`phase_machine`,
// `metrics`, and `tern replay`'s `replay` source). The Instance itself and its configuration
// are graph/instances.hpp's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "graph/instances.hpp"
#include "graph/recorded_source.hpp"

namespace tern::core {

class PhaseMachine;
class FlightMetrics;

/// `isolate: true`: moves the configured `inst.plugin` (the shadow) into an IsolatedPlugin that
/// runs the plugin in a child process (isolated_plugin.hpp). Throws ConfigError.
void isolate_instance(Instance& inst, const InstanceSetup& setup);

/// The instances of a mission, and the built-ins among them.
struct LoadedInstances {
  std::vector<std::unique_ptr<Instance>> list;
  PhaseMachine* phase_machine = nullptr;
  std::size_t phase_machine_index = SIZE_MAX;
  FlightMetrics* metrics = nullptr;
  RecordedSource* replay = nullptr;
};

/// Loads and configures every instance of `setup.config` (with `replay`: the replay's source and
/// the estimators only). Throws ConfigError.
LoadedInstances load_instances(const InstanceSetup& setup, const RecordedSourceFactory& replay);

}  // namespace tern::core
