// core/src/host.hpp: the host: builds the port graph from a mission config, runs flights on a
// deterministic single-threaded schedule, routes the controller per flight phase, and writes
// the flight log.
#pragma once

#include <array>
#include <functional>
#include <atomic>
#include <mutex>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "config.hpp"
#include "loader.hpp"
#include "metrics.hpp"
#include "phase_machine.hpp"
#include "tern/plugin.hpp"

namespace tern::core {

class FlightLog;
class InstanceContext;

/// Step-time statistics of one instance (wall clock; not part of the deterministic log).
struct StepStats {
  std::uint64_t steps = 0;
  std::uint64_t overruns = 0;  ///< steps longer than budget_ns
  Nanos budget_ns = 0;
  Nanos max_ns = 0;
  Nanos total_ns = 0;
  std::array<std::uint32_t, 96> histogram{};  ///< log-spaced buckets (ratio 2^(1/4)) from 1 ns
  void add(Nanos dt);
  Nanos percentile(double p) const;  ///< approximate (bucket upper bound), 0 when no steps
};

struct Instance {
  InstanceConfig cfg;
  std::shared_ptr<PluginLibrary> lib;      // outlives `plugin`
  std::unique_ptr<InstanceContext> ctx;
  std::unique_ptr<Plugin> plugin;          // destroyed first
  PluginInfo info;
  fs::path source;                         // the .so as named (swaps load a private copy)
  std::int64_t divisor = 0;                // rate instances: step when tick % divisor == 0
  InputBase* trigger = nullptr;            // trigger instances
  bool routed = false;                     // a controller behind the phase router
  bool builtin = false;
  StepStats stats;
};

struct HostOptions {
  std::optional<std::uint64_t> seed;
  std::optional<double> duration;          ///< s
  std::optional<fs::path> log_dir;         ///< parent of run directories
  bool realtime = false;
  bool progress = false;                   ///< live status line on stdout
  bool describing = false;                 ///< configure only (check/params): open no files/devices
  bool quiet = false;                      ///< no console log below warnings
  /// `tern replay`: play this flight log's sensor and truth topics instead of an I/O plugin, and
  /// keep only the config's estimator instances.
  std::optional<fs::path> replay_dir;
};

struct Handover {
  Nanos t;
  std::string from, to, reason;
};

struct FlightResult {
  fs::path run_dir;
  std::string end_reason;  ///< "duration", "SIGINT", "SIGTERM", "SIGHUP", "error: ..."
  bool ok = true;
  std::string log_error;   ///< the flight log's first write error: some of the log is missing ("" if none)
  Nanos flown = 0;
  double wall_s = 0;
  double flight_cpu_s = 0;  ///< CPU time of the flight thread (the plugins and the host's loop)
  double log_cpu_s = 0;     ///< CPU time of the flight log's writer thread (CSV formatting, writes)
};

/// Request the running flight to end (signal handlers call this). Thread- and signal-safe.
void request_stop(int signal_number);
/// Installs SIGINT/SIGTERM/SIGHUP handlers that call request_stop; ignores SIGXFSZ (a file-size
/// limit then fails the log's writes, which the flight log reports, instead of killing the flight).
void install_signal_handlers();
/// The signal that asked for a stop (0: none since the last flight started).
int stop_signal();

class Host {
 public:
  Host(MissionConfig config, HostOptions options);
  ~Host();  ///< unbinds, destroys every instance, then unloads every library
  Host(const Host&) = delete;
  Host& operator=(const Host&) = delete;

  /// Loads plugins, configures instances, binds ports, orders the schedule. Throws ConfigError.
  void build();
  /// Flies one flight (build() first). Never throws for plugin failures: see FlightResult.
  FlightResult fly();

  const MissionConfig& config() const { return config_; }
  const std::vector<std::unique_ptr<Instance>>& instances() const { return instances_; }
  /// Instance names in schedule order.
  std::vector<std::string> schedule() const;
  Nanos base_period() const { return base_period_; }
  /// Port graph as text (schedule, rates, topics, feedback edges) or Graphviz.
  std::string graph_text() const;
  std::string graph_dot() const;
  /// Every parameter: "instance.name" -> ParamBase.
  std::vector<std::pair<std::string, const ParamBase*>> parameters() const;
  const std::vector<Handover>& handovers() const { return handovers_; }
  std::shared_ptr<spdlog::logger> logger() const { return logger_; }
  /// Asks for a parameter change ("instance.param"), from any thread (command line, DDS). It is
  /// validated now (throws ConfigError: unknown parameter, tern::ParamError: bad value, or a
  /// start-only parameter in flight: "takes effect next flight"), applied at the start of the
  /// next tick (a start-only one: before the next flight's start()) and recorded in params.csv
  /// with `source`.
  void request_param(const std::string& qualified, const ParamValue& value, const std::string& source);
  /// Queues a mission edit (from any thread: command line, DDS). It is published on topic
  /// `mission_edit` at the start of the next tick, where the path planner applies it. Throws
  /// ConfigError when no instance reads `mission_edit`.
  void edit_mission(const msg::MissionEdit& edit);
  /// Between flights: replaces instance `instance` by the plugin in the shared object `so` (another
  /// plugin or a rebuild of the same one), configured with the instance's parameters. The new
  /// library is loaded from a private copy, so a rebuild at the same path loads too; the old
  /// library is unloaded for real. On any error (flying, unknown instance, handshake mismatch,
  /// ports that do not bind) throws ConfigError and keeps the current plugin.
  void swap(const std::string& instance, const fs::path& so);
  /// Between flights: a new phase -> controller table (and fallback). Throws ConfigError (and
  /// keeps the old table) if flying or invalid.
  void set_phases(const std::map<msg::Phase, std::string>& phases, const std::optional<std::string>& fallback);
  /// Flight length of the next flights (nullopt: the option or the config's duration).
  void set_duration(std::optional<double> seconds) { duration_override_ = seconds; }
  /// Topics with a producer, for bridges (DDS): name, message type name, layout fingerprint.
  struct TopicInfo {
    std::string name, type_name;
    std::uint64_t fingerprint;
  };
  std::vector<TopicInfo> topics() const;
  /// The output that currently feeds `topic` (follows the phase router), or nullptr. Read it only
  /// from the flight thread (e.g. in a tick observer): it changes between ticks.
  const OutputBase* topic_source(const std::string& topic) const;
  /// Called on the flight thread at the end of every tick, after logging (e.g. the DDS bridge).
  /// Must be quick; exceptions are logged and the observer is removed. Set between flights.
  void set_tick_observer(std::function<void(Nanos now)> observer) { tick_observer_ = std::move(observer); }
  /// A flight is running.
  bool flying() const { return flying_.load(); }
  /// Flights flown by this host.
  int flights() const { return flights_; }
  /// Flight time of the last recorded IMU sample when replaying (0 otherwise).
  Nanos replay_end() const;
  /// Milliseconds from the Host constructor to the first tick of the last flight.
  double start_to_first_tick_ms() const { return start_to_first_tick_ms_; }
  /// Milliseconds from entering fly() to the first tick of the last flight (log, reset, start).
  double flight_start_ms() const { return flight_start_ms_; }

 private:
  struct Topic;
  struct Edge {
    std::size_t from, to;
    std::string topic;
    bool feedback = false;
  };
  void load_instances();
  void update_routing_roles();
  void rebuild_graph();
  void configure_instance(Instance& inst);
  void bind_ports();
  void order_schedule();
  void resolve_rates();
  void route_to(std::size_t idx, Nanos now, const std::string& reason, bool from_failure);
  /// No controller runs (the flight waits disarmed); routed topics lose their writer.
  void route_none(Nanos now, const std::string& reason);
  bool step_instance(Instance& inst, Nanos now, std::string& error);
  void engage_fallback(Nanos now, const std::string& why);
  void apply_start_only_requests(FlightLog& log);
  std::string resolved_config_yaml() const;
  std::string sensor_profile() const;
  std::string summary_json(const FlightResult& r) const;
  std::string timing_json(const FlightResult& r) const;
  void print_summary(const FlightResult& r) const;

  MissionConfig config_;
  HostOptions options_;
  std::shared_ptr<spdlog::logger> logger_;
  std::vector<std::unique_ptr<Instance>> instances_;
  std::vector<std::size_t> order_;
  std::vector<Edge> edges_;
  std::vector<std::unique_ptr<Topic>> topics_;
  Nanos base_period_ = 0;
  std::uint64_t seed_ = 1;
  // phase router
  PhaseMachine* phase_machine_ = nullptr;
  FlightMetrics* metrics_ = nullptr;
  class ReplaySource* replay_ = nullptr;
  std::size_t phase_machine_idx_ = SIZE_MAX;
  std::uint64_t phase_seen_ = 0;
  std::optional<std::size_t> active_;      // active controller instance
  std::optional<std::size_t> fallback_;
  bool fallback_engaged_ = false;
  std::vector<Handover> handovers_;
  msg::Actuators last_good_{};
  std::vector<std::shared_ptr<spdlog::sinks::sink>> extra_sinks_;
  std::int64_t created_ns_ = 0;
  std::int64_t step_clock_ = 0;  // cycle clock at the end of the previous step of this tick
  double start_to_first_tick_ms_ = 0;
  double flight_start_ms_ = 0;
  bool built_ = false;
  std::atomic<bool> flying_{false};
  int flights_ = 0;
  std::optional<double> duration_override_;
  std::function<void(Nanos)> tick_observer_;
  int swaps_ = 0;
  fs::path swap_dir_;  // private copies of swapped-in libraries
  struct ParamRequest {
    ParamBase* param;
    std::string name;
    ParamValue value;
    std::string source;
  };
  std::mutex param_mu_;
  std::vector<ParamRequest> param_requests_;
  std::atomic<bool> param_pending_{false};
  std::unique_ptr<Output<msg::MissionEdit>> mission_edit_out_;  // the host's own writer
  std::vector<msg::MissionEdit> mission_edits_;                  // under param_mu_
};

}  // namespace tern::core
