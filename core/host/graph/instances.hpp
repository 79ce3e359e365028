// core/host/graph/instances.hpp: a plugin instance of a mission and its configuration.
//
// One instance per entry of the config's `plugins:` (instances of one plugin share its library),
// then the host's built-ins (flight/load_instances.hpp loads them all). Configuring an instance
// gives it a Context (its parameter values, its seed, a logger, the config's paths), runs its
// configure(), refuses parameters it does not declare (a warning for shared ROS 2 parameter
// files), applies its `remap:` and finds its `trigger:` input. Errors are ConfigError, one line
// naming file, field and value.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/fwd.h>

#include "config/config.hpp"
#include "graph/loader.hpp"
#include "graph/scheduler.hpp"
#include "tern/plugin.hpp"

namespace tern::core {

class InstanceContext;
class IsolatedPlugin;

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
  /// The context configure_instance() attached to the plugin.
  Context& context();
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
  bool replaying = false;                     ///< `tern replay`: the inputs come from a log (Context::replaying())
};

/// Attaches a context to `inst.plugin` and configures it (see above). Throws ConfigError.
void configure_instance(Instance& inst, const InstanceSetup& setup);

/// Gives a configured instance the seed of flights flown with `flight_seed` (as configure_instance
/// derives it). The plugin reads it at its next start (Context::seed()); what it drew from the
/// old seed at configure time stays, so only plugins that draw at start may be reseeded
/// (Host::reseed).
void reseed_instance(Instance& inst, std::uint64_t flight_seed);

}  // namespace tern::core
