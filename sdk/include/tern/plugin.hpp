// tern/plugin.hpp: the plugin base class, its context, and the registration macro.
//
// A plugin is one class derived from tern::Plugin, registered once per shared object with
//
//   TERN_PLUGIN(MyController, "my_controller", tern::PluginKind::controller, "one line");
//
// and built with tern_add_plugin() into libtern_my_controller.so. Its life, driven by the host:
//   configure()  declare ports (declare(input_, "state"); every message between two steps:
//                declare(imu_, "imu", "...", Need::required, Queue{64})) and parameters
//                (declare(kp_, "kp", ...), or a whole config struct at once:
//                declare_struct(config_)); read parameter values, open files. Nothing runs yet.
//   start()      once, before the first step of a flight.
//   step(now)    at the configured rate, or when the trigger input has new data.
//   reset()      between flights of one host (`tern serve`), before the next start(): the
//                plugin must then be as it was after configure(), with the parameters' current
//                values. The host empties every output (OutputBase::clear) and rebinds inputs.
//   take_over(a) when the phase router hands control to this controller; a is the last actuator
//                command, to start from (bumpless). Default: reset().
//   stop()       once, after the last step.
//
// Per-flight state, the contract that keeps flight 2 of a served host identical to flight 1 of
// a fresh one: keep everything a flight changes (integrators, filters, counters for summary(),
// "warned once" flags, scratch that outlives a step) in ONE struct with member initialisers,
// and let reset() replace it wholesale, never field by field (a field added later cannot be
// forgotten):
//
//   struct Flight {
//     double integrator = 0.0;
//     std::optional<Nanos> last_step;
//     std::uint64_t held_steps = 0;
//   } flight_;
//   void reset() override { flight_ = Flight{}; }
//
// Parameters, ports and what configure() read from files stay outside it. An algorithm object
// that is per-flight as a whole is replaced the same way (`filter_ = Filter(config_)`). The SDK
// templates (sdk/templates) follow this; tests/test_served_flights.sh checks the shipped plugins.
// A plugin never sleeps, never keeps a thread running after stop(), and never keeps a pointer
// into another plugin. Exceptions thrown from these functions end the flight with an error line
// naming the instance; the flight log is kept.
// log() is the instance's spdlog logger: log().info("Va = {:.1f} m/s", Va) needs no other include.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <boost/config.hpp>
#include <boost/dll/alias.hpp>
#include <spdlog/logger.h>  // log() returns a usable logger without another include

#include "tern/export.hpp"
#include "tern/msg/all.hpp"
#include "tern/param.hpp"
#include "tern/port.hpp"
#include "tern/param_struct.hpp"
#include "tern/time.hpp"

namespace YAML {
class Node;
}

namespace tern {

/// Version of the plugin API (this header, ports, parameters, messages). The host refuses a
/// plugin built against another version. 2: ParamSpec::live (start-only parameters).
/// 3: msg::Waypoint's type and loiter fields, msg::WaypointList::immediate (issue 18).
/// 4: Plugin::declare_struct (parameters from a described config struct, tern/param_struct.hpp);
///    log() usable with this header alone (issue 22). SDK package version 0.2.
/// 5: OutputBase::clear() (the host empties every output between flights), per-flight state
///    replaced wholesale by reset(), Plugin::health() and Plugin::timing() (issue 45).
/// 6: PluginKind::coordination and Context::vehicles() (multi-vehicle missions, issue 42).
/// 7: input queues (Queue, Input<T>::received(), an Output's history: every message between two
///    steps reaches a consumer that asks for it; tern/port.hpp), Context::replaying() (issue 61).
/// 8: msg::Gnss::hdop and vdop (the receiver's dilutions of precision, issue 61).
inline constexpr std::uint32_t kSdkApiVersion = 8;

/// What a plugin is for; the host runs `io` plugins first in every tick.
/// `coordination`: runs once per tick after every vehicle of a multi-vehicle mission, sees their
/// topics and sends them mission edits (Context::vehicles()).
enum class PluginKind : std::uint8_t { io, estimator, controller, path_planner, path_manager, path_follower, generic, coordination };
constexpr const char* kind_name(PluginKind k) {
  switch (k) {
    case PluginKind::io: return "io";
    case PluginKind::estimator: return "estimator";
    case PluginKind::controller: return "controller";
    case PluginKind::path_planner: return "path_planner";
    case PluginKind::path_manager: return "path_manager";
    case PluginKind::path_follower: return "path_follower";
    case PluginKind::generic: return "generic";
    case PluginKind::coordination: return "coordination";
  }
  return "generic";
}
inline std::optional<PluginKind> plugin_kind_from_name(std::string_view s) {
  for (auto k : {PluginKind::io, PluginKind::estimator, PluginKind::controller, PluginKind::path_planner, PluginKind::path_manager,
                 PluginKind::path_follower, PluginKind::generic, PluginKind::coordination})
    if (s == kind_name(k)) return k;
  return std::nullopt;
}

/// What the host (or the test harness) offers a plugin instance.
class TERN_API Context {
 public:
  virtual ~Context();
  /// Instance name from the mission config, e.g. "slc".
  virtual const std::string& instance_name() const = 0;
  /// Value the mission config (or its parameter file) sets for this instance's parameter, if any,
  /// already resolved relative to the file that set it when the parameter is a path.
  virtual std::optional<ParamValue> configured_value(const std::string& param, const ParamSpec& spec) const = 0;
  /// Random seed for this instance: derived from the mission seed and the instance name, so that
  /// instances draw independent streams and a flight is repeatable. It may change between flights
  /// (Python's reset(seed) reseeds a built host): draw from it in start(), not in configure().
  virtual std::uint64_t seed() const = 0;
  /// Logger named after the instance, writing to the console and the flight's text log.
  virtual std::shared_ptr<spdlog::logger> logger() const = 0;
  /// Directory of the mission config (for plugin-specific relative paths); empty if none.
  virtual std::filesystem::path config_dir() const = 0;
  /// The mission config's `mission:` section (waypoints etc.); a null node when absent.
  virtual const YAML::Node& mission() const = 0;
  /// The aircraft file named by the mission config's `aircraft:` key, resolved; empty if none.
  virtual std::filesystem::path aircraft_file() const = 0;
  /// True when the host only wants the plugin's ports and parameters (`tern plugins`,
  /// `tern params`): configure() should declare everything and open no file or device.
  virtual bool describing() const { return false; }
  /// True when the inputs come from a recorded log (`tern replay`): the log's clock may start
  /// anywhere and each sensor's first sample may come at any time after the flight's start
  /// (docs/sensor-log.md), so a sensor silent before its first sample is no fault (an estimator
  /// starts its time-out at its first sample).
  virtual bool replaying() const { return false; }
  /// Ends the flight after this step, for a reason only the plugin can see (a simulator's
  /// aircraft hit the ground). `reason` becomes summary.json's `end_reason` (one word: "crash"),
  /// `detail` says what happened (time, place, speeds). The flight ends with ok = false, so
  /// `tern fly` exits 1. The first request of a flight counts. A context that flies nothing
  /// logs it as a warning; the test harness records it (Harness::end_request()).
  virtual void end_flight(const std::string& reason, const std::string& detail);
  /// The vehicles of a multi-vehicle mission (its `vehicles:` names, in the config's order) for
  /// a `coordination` plugin, which declares its ports per vehicle: an input "<vehicle>/state"
  /// (any topic a vehicle publishes, as "<vehicle>/<topic>") and an output
  /// "<vehicle>/mission_edit" (msg::MissionEdit, applied by that vehicle's path planner at the
  /// start of its next tick). Empty for every other plugin and for a one-vehicle mission.
  virtual std::vector<std::string> vehicles() const { return {}; }
};

class TERN_API Plugin {
 public:
  Plugin();
  virtual ~Plugin();
  Plugin(const Plugin&) = delete;
  Plugin& operator=(const Plugin&) = delete;

  virtual void configure() = 0;
  virtual void start() {}
  virtual void step(Nanos now) = 0;
  /// Between flights: back to the state after configure() (see "Per-flight state" above).
  virtual void reset() {}
  /// The phase router made this controller the active one. `last_command` is what the
  /// outgoing controller commanded last: start from it (bumpless transfer: no surface jump).
  /// The default resets the plugin.
  virtual void take_over(const msg::Actuators& last_command) {
    (void)last_command;
    reset();
  }
  virtual void stop() {}
  /// Figures this plugin adds to the flight's summary.json (name, value), after stop(): a
  /// function of the config and the seed (summary.json is the same bytes for the same flight).
  virtual std::vector<std::pair<std::string, double>> summary() const { return {}; }
  /// Figures that depend on the wall clock (a link's round trip, frames of a wall-paced link),
  /// for the flight's timing.json, after stop().
  virtual std::vector<std::pair<std::string, double>> timing() const { return {}; }
  /// One short line for the terminal at the end of a flight when this plugin has something to
  /// say about its health (e.g. "0 resets, baro 0.9 % rejected"), "" when not; after stop().
  /// The figures behind it belong in summary(), which summary.json keeps.
  virtual std::string health() const { return {}; }

  // ---- host side ----
  void attach(Context* ctx) { ctx_ = ctx; }
  const std::vector<InputBase*>& inputs() const { return inputs_; }
  const std::vector<OutputBase*>& outputs() const { return outputs_; }
  const std::vector<ParamBase*>& params() const { return params_; }
  InputBase* find_input(std::string_view name) const;
  OutputBase* find_output(std::string_view name) const;
  ParamBase* find_param(std::string_view name) const;

 protected:
  Context& context() const;
  spdlog::logger& log() const;
  /// Host side: a proxy (core's isolated instance) presents the ports and parameters of
  /// `other`, which it keeps alive, as its own.
  void present_ports_of(const Plugin& other) {
    inputs_ = other.inputs_;
    outputs_ = other.outputs_;
    params_ = other.params_;
  }

  template <class T>
  void declare(Input<T>& port, std::string name, std::string description = {}, Need need = Need::required) {
    port.set_need(need);
    add_input(port, std::move(name), std::move(description));
  }
  /// An input that reads every message published between two steps, up to `queue.depth` of
  /// them (Input<T>::received(), tern/port.hpp): e.g. a sensor a replay may deliver in bursts.
  template <class T>
  void declare(Input<T>& port, std::string name, std::string description, Need need, Queue queue) {
    port.set_queue(queue);
    declare(port, std::move(name), std::move(description), need);
  }
  template <class T>
  void declare(Output<T>& port, std::string name, std::string description = {}) {
    add_output(port, std::move(name), std::move(description));
  }
  /// Declares a parameter with its default and spec, then applies the configured value if the
  /// mission config sets one (throws ParamError if that value is invalid).
  template <class T>
  void declare(Param<T>& param, std::string name, T default_value, ParamSpec spec = {}) {
    param.init(default_value);
    add_param(param, std::move(name), ParamValue(std::move(default_value)), std::move(spec));
  }
  /// String literals declare text parameters.
  void declare(Param<std::string>& param, std::string name, const char* default_value, ParamSpec spec = {}) {
    declare(param, std::move(name), std::string(default_value), std::move(spec));
  }
  /// Declares every field that `S::describe()` names (tern/param_struct.hpp) as a parameter:
  /// its name and spec from describe(), its default the value the field holds now (normally the
  /// struct's member initialiser). The field then takes the configured value, and every valid
  /// change (command line, DDS, between flights) is written into `config` before `on_change`
  /// runs. `config` must outlive the plugin's parameters (make it a member of the plugin).
  /// Throws ParamError as declare() does.
  template <class S>
  void declare_struct(S& config, std::function<void()> on_change = {}) {
    param_struct::Binder<S> b{config,
                              [this](std::unique_ptr<ParamBase> p, std::string name, ParamValue def, ParamSpec spec) -> ParamBase& {
                                ParamBase& ref = *p;
                                owned_params_.push_back(std::move(p));
                                add_param(ref, std::move(name), std::move(def), std::move(spec));
                                return ref;
                              },
                              std::make_shared<std::function<void()>>(std::move(on_change))};
    S::describe(b);
  }

 private:
  void add_input(InputBase& port, std::string name, std::string description);
  void add_output(OutputBase& port, std::string name, std::string description);
  void add_param(ParamBase& param, std::string name, ParamValue default_value, ParamSpec spec);

  Context* ctx_ = nullptr;
  std::vector<InputBase*> inputs_;
  std::vector<OutputBase*> outputs_;
  std::vector<ParamBase*> params_;
  std::vector<std::unique_ptr<ParamBase>> owned_params_;  ///< made by declare_struct()
};

}  // namespace tern

// ---- the handshake: plain C, checked by the host before any C++ is called ----------------------

extern "C" {
struct tern_message_fingerprint {
  const char* type_name;
  std::uint64_t fingerprint;
};
struct tern_plugin_handshake {
  std::uint32_t magic;            ///< TERN_HANDSHAKE_MAGIC
  std::uint32_t sdk_api_version;  ///< tern::kSdkApiVersion the plugin was built with
  const char* abi_tag;            ///< TERN_ABI_TAG the plugin was built with
  const char* plugin_name;
  const char* kind;  ///< tern::kind_name(PluginKind)
  const char* description;
  std::uint32_t message_count;
  const tern_message_fingerprint* messages;  ///< the standard messages as the plugin sees them
};
}

#define TERN_HANDSHAKE_MAGIC 0x4E524554u /* "TERN" */
#define TERN_HANDSHAKE_SYMBOL tern_plugin_handshake_v1
#define TERN_FACTORY_ALIAS tern_create_plugin

#define TERN_STR_(x) #x
#define TERN_STR(x) TERN_STR_(x)
#if defined(_LIBCPP_VERSION)
#define TERN_STDLIB_TAG_ "libc++" TERN_STR(_LIBCPP_VERSION)
#else
#define TERN_STDLIB_TAG_ "libstdc++" TERN_STR(_GLIBCXX_RELEASE) ";cxx11abi=" TERN_STR(_GLIBCXX_USE_CXX11_ABI)
#endif
/// What must match between host and plugin besides the API version: the C++ standard library
/// and its string ABI, and Eigen's version and static alignment (which -march can change).
#define TERN_ABI_TAG                                                                                       \
  TERN_STDLIB_TAG_ ";eigen=" TERN_STR(EIGEN_WORLD_VERSION) "." TERN_STR(EIGEN_MAJOR_VERSION) "." TERN_STR( \
      EIGEN_MINOR_VERSION) ";eigen_align=" TERN_STR(EIGEN_MAX_STATIC_ALIGN_BYTES)

#define TERN_FINGERPRINT_ENTRY_(T) {T::type_name.data(), ::tern::reflect::fingerprint<T>()},

/// Registers `Class` as this shared object's plugin. Use once, in one .cpp file of the plugin.
#define TERN_PLUGIN(Class, name, kind, description)                                                                   \
  namespace {                                                                                                         \
  ::tern::Plugin* tern_plugin_factory_() { return new Class(); }                                                      \
  constexpr tern_message_fingerprint tern_plugin_fingerprints_[] = {TERN_STANDARD_MESSAGES(TERN_FINGERPRINT_ENTRY_)}; \
  }                                                                                                                   \
  extern "C" BOOST_SYMBOL_EXPORT const tern_plugin_handshake TERN_HANDSHAKE_SYMBOL;                                   \
  extern "C" BOOST_SYMBOL_EXPORT const tern_plugin_handshake TERN_HANDSHAKE_SYMBOL = {                                \
      TERN_HANDSHAKE_MAGIC,                                                                                           \
      ::tern::kSdkApiVersion,                                                                                         \
      TERN_ABI_TAG,                                                                                                   \
      name,                                                                                                           \
      ::tern::kind_name(kind),                                                                                        \
      description,                                                                                                    \
      sizeof(tern_plugin_fingerprints_) / sizeof(tern_plugin_fingerprints_[0]),                                       \
      tern_plugin_fingerprints_};                                                                                     \
  BOOST_DLL_ALIAS(tern_plugin_factory_, TERN_FACTORY_ALIAS)
