// core/host/flight/host.hpp: the host: loads a mission's plugin instances, builds their port graph,
// flies flights on one deterministic schedule, and changes things between flights (hot-swap,
// phase table).
//
// A flight (fly()) is a loop of ticks; each tick, at flight time t:
//   1. remote edits queued from other threads are applied     remote_queue.hpp
//   2. every instance due steps, in the port graph's order    scheduler.hpp, port_graph.hpp
//      (a routed controller only when active; after the phase machine, the router follows
//      the phase; after a controller, the router may engage the fallback)  phase_router.hpp
//      then the failsafes look at the tick (failsafe_station.hpp: mission edits, termination)
//   3. what was published is captured in the flight log      flight_recorder.hpp
//   4. the tick observers (DDS bridge, console, tern tune) are called in the order added; then,
//      on the wall clock: log flushes, the status line (status_line.hpp) and, with --realtime,
//      pacing.
// Before every flight but the first, the host makes itself as new: every plugin's reset() (its
// per-flight state replaced, tern/plugin.hpp), every output emptied, the inputs rebound, the
// router back to the first phase; so flight N of `tern serve` is flight 1 of a fresh host.
// Between flights (host_between_flights.cpp) a plugin can be swapped and the phase table changed.
// Every step runs under the watchdog (watchdog.hpp): slow steps are reported, a step stuck past
// the hard budget, or stuck when a stop signal comes, ends the flight and the process (_exit,
// after the log is complete). An isolated instance (`isolate: true`) runs in a child process
// (isolated_plugin.hpp); when the child fails, a routed controller gives way to the fallback and
// any other instance ends the flight (end_reason "plugin_failed").
// The instances themselves (loading, configuring, built-ins) are in instances.hpp, the flight
// log's documents (summary.json, timing.json, config.yaml, console summary) in
// flight_report.hpp.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <spdlog/sinks/dist_sink.h>

#include "graph/realtime.hpp"
#include "config/config.hpp"
#include "safety/failsafe_station.hpp"
#include "record/flight_report.hpp"
#include "record/resolved_config.hpp"
#include "flight/held_messages.hpp"
#include "flight/load_instances.hpp"
#include "record/metrics.hpp"
#include "safety/phase_machine.hpp"
#include "safety/phase_router.hpp"
#include "graph/port_graph.hpp"
#include "graph/remote_queue.hpp"
#include "graph/scheduler.hpp"
#include "tern/plugin.hpp"
#include "runners/watchdog.hpp"

namespace tern::core {

class FlightRecorder;

/// What a swap replaced: the SHA-256 (hex) of the library that ran and of the new one.
struct SwapReport {
  std::string old_sha256, new_sha256;
  bool same() const { return old_sha256 == new_sha256; }
};

struct HostOptions {
  std::optional<std::uint64_t> seed;
  std::optional<double> duration;   ///< s
  std::optional<fs::path> log_dir;  ///< parent of run directories
  bool realtime = false;
  RealtimeOptions rt;       ///< the flight thread's scheduling when realtime (realtime.hpp)
  bool progress = false;    ///< live status line on stdout
  bool describing = false;  ///< configure only (check/params): open no files/devices
  /// Producers::not_checked: an input nothing publishes is no error (`tern params` on a replay's
  /// config, graph/port_graph.hpp), for a describing host.
  Producers producers = Producers::required;
  bool quiet = false;  ///< no console log below warnings
  /// `tern replay`: play the recorded flight this makes (apps/replay/replay_source.hpp: a sensor
  /// log's topics) instead of the config's I/O plugins, and keep only its estimator instances.
  RecordedSourceFactory replay;
  /// The flight log goes exactly here (a multi-vehicle run's `<run>/<vehicle>`), not into a new
  /// directory under log_dir. One flight per host then.
  std::optional<fs::path> run_dir;
  /// The console log's lines start "[level] <console_prefix>/<logger>: " (a vehicle's name), not
  /// "[level] <logger>: ".
  std::string console_prefix;
  /// Outputs of another host's topics (a fleet's mirrors of its vehicles' topics) offered to this
  /// host's port graph as host outputs; they must outlive the host.
  std::vector<const OutputBase*> external_outputs;
  /// Called by build() with the loaded, configured instances before their port graph is built
  /// (a fleet checks its coordination's ports); throws ConfigError to refuse them.
  std::function<void(const std::vector<std::unique_ptr<Instance>>&)> check_instances;
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
  /// fly() is begin_flight(), tick() until it returns false, end_flight().
  FlightResult fly();
  /// The same flight driven by another loop (a multi-vehicle fleet flies its vehicles' hosts
  /// tick by tick, fleet.hpp): begin_flight() prepares it (log, reset, start; false: it ended
  /// before its first tick), tick() flies one tick (false: the flight has ended, the tick done),
  /// end_flight() finishes it (`reason` is the end reason when it is still going: the fleet ended
  /// it) and returns what fly() returns. Nothing between them may call fly().
  bool begin_flight();
  bool tick();
  FlightResult end_flight(const std::string& reason = "aborted");
  /// Flight time of the running flight's current tick (0 before the first).
  Nanos now() const;

  const MissionConfig& config() const { return config_; }
  const HostOptions& options() const { return options_; }
  const std::vector<std::unique_ptr<Instance>>& instances() const { return instances_; }
  /// Instance names in schedule order.
  std::vector<std::string> schedule() const;
  Nanos base_period() const { return base_period_; }
  /// Port graph as text (schedule, rates, topics, feedback edges) or Graphviz.
  std::string graph_text() const;
  std::string graph_dot() const;
  /// Every parameter: "instance.name" -> ParamBase.
  std::vector<std::pair<std::string, const ParamBase*>> parameters() const;
  /// A parameter's value (one of parameters()), read from any thread: a request_param() is applied
  /// under the same lock. Readers off the flight thread (ground station, DDS bridge, console) use it.
  ParamValue param_value(const ParamBase& param) const { return remote_.value_of(param); }
  /// Where each parameter set by something other than its default got its value: the request
  /// applied last (its source: "python", "console", "dds", "mavlink"), else the config's
  /// "file:line" or the command-line option (ParamSetting::source()). For params.csv.
  std::map<std::string, std::string> param_sources() const;
  const std::vector<Handover>& handovers() const { return router_.handovers(); }
  std::shared_ptr<spdlog::logger> logger() const { return logger_; }
  /// Asks for a parameter change ("instance.param"), from any thread (command line, DDS). It is
  /// validated now (throws ConfigError: unknown parameter, tern::ParamError: bad value, or a
  /// start-only parameter in flight: "takes effect next flight"), applied at the start of the
  /// next tick (a start-only one: before the next flight's start()) and recorded in params.csv
  /// with `source`.
  void request_param(const std::string& qualified, const ParamValue& value, const std::string& source);
  /// Queues a mission edit (from any thread: command line, DDS). It is published on topic
  /// `mission_edit` at the start of the next tick, where the path planner applies it. Throws
  /// ConfigError when no instance reads `mission_edit`, or when RemoteQueue::kMaxQueued edits
  /// already wait, unless `own`: an edit of tern's own making (a fleet's coordination or
  /// separation hold) is never refused.
  void edit_mission(const msg::MissionEdit& edit, bool own = false);
  /// Mission edits waiting for a tick (between flights: for the next flight's first ticks, one
  /// per tick). Any thread.
  std::size_t queued_mission_edits() const { return remote_.queued_edits(); }
  /// The operator's go-around (any thread: tern go-around, the DDS service `go_around`), from
  /// `source`: handed to the phase machine at the start of the next tick, which takes it on the
  /// approach or in the flare (phase_machine.hpp) and logs it either way. Throws ConfigError
  /// when the mission has no phase machine (no `phases:`).
  void go_around(const std::string& source);
  /// The ground station was heard (any thread): the DDS bridge calls this on every request and
  /// heartbeat. The link-loss failsafe (failsafe.hpp) acts only once this has been called in a
  /// flight.
  void ground_link_heard() { failsafes_.ground_link_heard(); }
  /// A ground station's geofence zones and rally points (MAVLink's FENCE and RALLY; any thread):
  /// they replace the config's (failsafes.geofence.polygon, failsafes.rally) from the next tick
  /// on, in this flight and the next ones (failsafe_station.hpp).
  void set_fence_zones(std::vector<FenceZone> zones) { failsafes_.set_zones(std::move(zones)); }
  void set_rally_points(std::vector<Eigen::Vector3d> rally) { failsafes_.set_rally(std::move(rally)); }
  /// The zones and rally points in force, and whether the fence is on and breached (any thread).
  FailsafeStation::Geometry fence_geometry() const { return failsafes_.geometry(); }
  FailsafeStation::FenceStatus fence_status() const { return failsafes_.fence_status(); }
  /// The failsafe events of this flight (the flight thread: a tick observer).
  const std::vector<FailsafeEvent>& failsafe_events() const { return failsafes_.events(); }
  /// Hands a pilot's sticks and switches (the console's keyboard or gamepad) to topic `pilot` at
  /// the start of the next tick, the latest one winning; sim_aero reports them on `rc`. Any
  /// thread. Throws ConfigError when no instance reads `pilot`.
  void set_pilot(const msg::Rc& rc);
  bool takes_pilot() const { return remote_.takes_pilot(); }
  /// An instance reads topic `mission_edit` (edit_mission() takes edits).
  bool takes_mission_edits() const { return remote_.takes_mission_edits(); }
  /// Between flights: replaces instance `instance` by the plugin in the shared object `so` (another
  /// plugin or a rebuild of the same one), configured with the instance's parameters. The new
  /// library is loaded from a private copy, so a rebuild at the same path loads too; the old
  /// library is unloaded for real. On any error (flying, unknown instance, handshake mismatch,
  /// ports that do not bind) throws ConfigError and keeps the current plugin. The log line names
  /// both libraries' SHA-256; when they are equal (a rebuild that failed and left the old file)
  /// the swap happens and a warning says so.
  SwapReport swap(const std::string& instance, const fs::path& so);
  /// Between flights: a new phase -> controller table (and fallback). Throws ConfigError (and
  /// keeps the old table) if flying or invalid (a phase or the fallback not a controller).
  void set_phases(const std::map<msg::Phase, std::string>& phases, const std::optional<std::string>& fallback);
  /// Between flights: the seed of the next flights, every instance's derived from it as at build(),
  /// without rebuilding anything (Python's reset(seed)): a flight flown after it is the flight a
  /// host built with that seed flies, for plugins that draw from Context::seed() in start() (tern's
  /// do; plugin.hpp asks it). False, and nothing changed, when an instance runs in a child process
  /// (its seed was given at its spawn): rebuild the host then. Throws ConfigError if flying.
  bool reseed(std::uint64_t seed);
  std::uint64_t seed() const { return seed_; }
  /// Flight length of the next flights (nullopt: the option or the config's duration).
  void set_duration(std::optional<double> seconds) { duration_override_ = seconds; }
  /// Holds fields of `topic`'s message (log column names, e.g. "delta_a" of `actuators`): after
  /// every step of what feeds the topic (topic_source(): for `actuators` the routed controller)
  /// they replace the producer's values before any consumer reads them and before the log
  /// captures them, this flight and the next ones, until release_message() (held_messages.hpp).
  /// Call it between ticks, on the thread that flies. Throws ConfigError naming the topic: no
  /// plugin publishes it, an unknown field (the message's fields listed), a value that is not
  /// finite or does not fit its field. Nothing held: the flight is untouched.
  void hold_message(const std::string& topic, const std::vector<std::pair<std::string, double>>& fields);
  /// Stops holding `topic`; false when nothing was held there.
  bool release_message(const std::string& topic) { return held_.release(topic); }
  /// Topics with a producer, for bridges (DDS): name, message type name, layout fingerprint.
  struct TopicInfo {
    std::string name, type_name;
    std::uint64_t fingerprint;
  };
  std::vector<TopicInfo> topics() const;
  /// The output that currently feeds `topic` (follows the phase router), or nullptr. Read it only
  /// from the flight thread (e.g. in a tick observer): it changes between ticks.
  const OutputBase* topic_source(const std::string& topic) const;
  /// Adds a function called on the flight thread at the end of every tick, after logging (the
  /// DDS bridge, the console, tern tune's recorder; several at once), in the order added. Each
  /// must be quick; one that throws is logged and removed. Add and remove them between flights.
  /// Returns the id remove_tick_observer() takes.
  int add_tick_observer(std::function<void(Nanos now)> observer);
  /// Removes the observer `id` (an unknown id: nothing happens).
  void remove_tick_observer(int id);
  /// A flight is running.
  bool flying() const { return flying_.load(); }
  /// Ends the running flight after its current tick as if its duration had ended (end_reason
  /// "aborted", ok, the log complete); the host stays ready for the next flight. Any thread.
  /// Returns false (and does nothing) when no flight is running.
  bool abort_flight();
  /// Flights flown by this host.
  int flights() const { return flights_; }
  /// When replaying, the first tick at or after the last recorded IMU sample (the flight's
  /// duration that plays it, RecordedSource::end_time()); 0 otherwise.
  Nanos replay_end() const;
  /// Milliseconds from the Host constructor to the first tick of the last flight.
  double start_to_first_tick_ms() const { return start_to_first_tick_ms_; }
  /// Milliseconds from entering fly() to the first tick of the last flight (log, reset, start).
  double flight_start_ms() const { return flight_start_ms_; }

 private:
  void rebuild_graph();
  InstanceSetup setup() const {
    return {config_, seed_, sinks_, options_.describing, *logger_, options_.realtime, static_cast<bool>(options_.replay)};
  }
  FlightFacts facts(double duration_s) const;
  double flight_duration() const;
  // fly(), in order
  struct Running;  // a flight between begin_flight() and end_flight() (host.cpp)
  std::unique_ptr<Running> running_;
  void reset_for_next_flight();
  bool apply_realtime_options(FlightResult& r);
  bool start_instances(FlightResult& r);
  EndRequest run_tick(Scheduler& clock);
  void notify_observer(Nanos now);
  /// Records a parameter's change in the flight's log and keeps its source (param_sources()).
  RemoteQueue::ParamRecorder param_recorder(Running& f);
  void finish_flight(FlightRecorder& recorder, FlightResult& r, double duration_s);
  /// The watchdog's way out (watchdog.hpp), on its thread: the log's end, then _exit.
  [[noreturn]] void emergency_end(FlightRecorder& recorder, FlightResult& r, double duration_s);

  MissionConfig config_;
  HostOptions options_;
  std::shared_ptr<spdlog::sinks::dist_sink_mt> sinks_;  // the console, and tern.log while flying
  std::shared_ptr<spdlog::logger> logger_;
  std::vector<std::unique_ptr<Instance>> instances_;
  PortGraph graph_;  // over instances_ (node i = instance i)
  PhaseRouter router_{instances_, graph_, logger_};
  RemoteQueue remote_;
  FailsafeStation failsafes_{logger_};
  Nanos base_period_ = 0;
  std::uint64_t seed_ = 1;
  void take_go_around(Nanos now);
  PhaseMachine* phase_machine_ = nullptr;  // built-ins, owned by instances_
  FlightMetrics* metrics_ = nullptr;
  RecordedSource* replay_ = nullptr;
  std::size_t phase_machine_idx_ = SIZE_MAX;
  std::int64_t created_ns_ = 0;
  double start_to_first_tick_ms_ = 0;
  double flight_start_ms_ = 0;
  ResolvedConfig resolved_config_;  // config.yaml, emitted again only when more than the seed changed
  bool built_ = false;
  std::atomic<bool> flying_{false};
  std::atomic<bool> abort_{false};  // abort_flight() asked; cleared when a flight starts
  int flights_ = 0;
  std::optional<double> duration_override_;
  std::vector<std::pair<int, std::function<void(Nanos)>>> tick_observers_;  // id, observer
  int next_observer_id_ = 1;
  Watchdog watchdog_;
  HeldMessages held_;
  std::map<std::string, std::string> requested_sources_;  // flight thread: the source of each request applied, by "instance.param"
  int swaps_ = 0;
  fs::path swap_dir_;  // private copies of swapped-in libraries
};

}  // namespace tern::core
