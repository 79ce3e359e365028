// core/src/flight/instances.hpp: the plugin instances of a mission: loaded, configured, and the host's
// built-in ones.
//
// One instance per entry of the config's `plugins:` (instances of one plugin share its library),
// then the built-ins: `phase_machine` (when the config has `phases:`) and `metrics` (when some
// instance publishes `state`), triggered by `state` and set from their own config sections.
// `tern replay` adds a built-in `replay` I/O instance and keeps only the estimators.
// Configuring an instance gives it a Context (its parameter values, its seed, a logger, the
// config's paths), runs its configure(), refuses parameters it does not declare (a warning for
// shared ROS 2 parameter files), applies its `remap:` and finds its `trigger:` input.
// With `isolate: true` (and not describing) the configured plugin is moved into an IsolatedPlugin,
// which runs it in a child process. Errors are ConfigError, one line naming file, field and value.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/fwd.h>

#include "config/config.hpp"
#include "flight/loader.hpp"
#include "flight/scheduler.hpp"
#include "tern/plugin.hpp"

namespace tern::core {

class InstanceContext;
class PhaseMachine;
class FlightMetrics;
class ReplaySource;
class IsolatedPlugin;

/// The seed of a part named `name` of a flight seeded `seed`: splitmix64(seed ^ FNV-1a(name)), an
/// instance's (Context::seed) and a fleet vehicle's (fleet.hpp).
std::uint64_t derived_seed(std::uint64_t seed, const std::string& name);

/// A plugin's request to end the flight (Context::end_flight).
struct EndRequest {
  std::string reason, detail;
  bool ok = false;  ///< the flight is complete, not cut short (the phase machine's "landed")
};

struct Instance {
  Instance();
  ~Instance();  ///< plugin, then context (code in the .so), then the library
  /// Destroys the plugin object, then its context; the library stays loaded (unload it after).
  void drop_plugin();
  /// The plugin's first end_flight() since the last call, if any (and forgets it).
  std::optional<EndRequest> take_end_request();
  InstanceConfig cfg;
  std::shared_ptr<PluginLibrary> lib;  // outlives `plugin`
  std::unique_ptr<InstanceContext> ctx;
  std::unique_ptr<Plugin> plugin;  // destroyed first
  PluginInfo info;
  fs::path source;               // the .so as named (swaps load a private copy)
  std::int64_t divisor = 0;      // rate instances: step when tick % divisor == 0
  InputBase* trigger = nullptr;  // trigger instances
  bool routed = false;           // a controller behind the phase router
  bool idle = false;             // a controller the phase table does not name: never steps, no ports in the graph
  bool builtin = false;
  IsolatedPlugin* isolated = nullptr;  // `plugin` when it runs in a child process
  StepStats stats;
  /// Why an isolated instance failed this flight ("" while it works, and for in-process ones).
  std::string failure() const;
};

/// What configuring an instance takes from the host.
struct InstanceSetup {
  const MissionConfig& config;
  std::uint64_t seed;                         ///< the flight's; instance i gets splitmix64(seed ^ fnv1a(name))
  std::shared_ptr<spdlog::sinks::sink> sink;  ///< where the instances' loggers write
  bool describing;                            ///< check/params: configure only, open no files or devices
  spdlog::logger& log;                        ///< the host's logger (warnings)
  bool realtime = false;                      ///< --realtime: external instances take the latest output, no lockstep
};

/// Attaches a context to `inst.plugin` and configures it (see above). Throws ConfigError.
void configure_instance(Instance& inst, const InstanceSetup& setup);

/// `isolate: true`: moves the configured `inst.plugin` (the shadow) into an IsolatedPlugin that
/// runs the plugin in a child process (isolated_plugin.hpp). Throws ConfigError.
void isolate_instance(Instance& inst, const InstanceSetup& setup);

/// The instances of a mission, and the built-ins among them.
struct LoadedInstances {
  std::vector<std::unique_ptr<Instance>> list;
  PhaseMachine* phase_machine = nullptr;
  std::size_t phase_machine_index = SIZE_MAX;
  FlightMetrics* metrics = nullptr;
  ReplaySource* replay = nullptr;
};

/// Loads and configures every instance of `setup.config` (with `replay_dir`: the replay source
/// and the estimators only). Throws ConfigError.
LoadedInstances load_instances(const InstanceSetup& setup, const std::optional<fs::path>& replay_dir);

}  // namespace tern::core
