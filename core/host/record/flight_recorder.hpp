// core/host/record/flight_recorder.hpp: what one flight writes, and when: its run directory, the host's
// text log, the topics logged, parameter changes, summary and timing.
//
// The run directory is <parent>/<UTC start time>-<mission> (-2, -3 ... when taken); the files
// are listed in flight_log.hpp. While the recorder lives, the host's log also goes to tern.log.
// Topics logged: `log.topics` (default: every topic with a writer). A topic's message is captured
// at the end of the tick it was published in (flight time of the tick), at most one per
// 1 / rate s of flight time, the rate as `log.level` says (config.hpp: topic_rate below):
// `log.rates.<topic>`, else every message for the sensor topics and `actuators` (so that a flight
// can be replayed: tern replay), else `log.plot_rate` (levels replay and sysid) or `log.max_rate`
// (full). Thinning by flight time keeps the log deterministic. Level summary logs no topic;
// decimated caps every topic, the sensors too, at `log.decimated_rate` Hz (cannot be replayed).
// A topic logged with every message gets every message, also when several are published in one
// tick (a replay's bursts, an FCU link's): its writers hold the last kBurstDepth messages
// (OutputBase::keep_history), and a writer that published more between two captures than it
// held makes the log incomplete (FlightResult::log_error names the topic and the count).
// A logged waypoint list (msg::WaypointList, topic `waypoints`) also writes its items, one row
// per waypoint of each list captured, to topics/<topic>_items.csv (revision, index and the
// Waypoint's columns): the mission as flown, edits in flight included (tern plot draws it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <spdlog/fwd.h>
#include <spdlog/sinks/dist_sink.h>

#include "config/config.hpp"
#include "record/flight_log.hpp"
#include "record/flight_report.hpp"
#include "graph/port_graph.hpp"

namespace tern::core {

/// A new run directory under `parent` for mission `mission`: "<UTC stamp>-<mission>", with "-2",
/// "-3" ... when it exists (not created here).
fs::path new_run_dir(const fs::path& parent, const std::string& mission);

class FlightRecorder {
 public:
  /// Creates the run directory `run_dir` (new_run_dir()) and adds its tern.log to `sinks` (where
  /// the host's logger and the instances' write). Throws ConfigError if the directory cannot be
  /// created. `on_error` hears the log's first write error (once).
  FlightRecorder(const fs::path& run_dir, std::shared_ptr<spdlog::sinks::dist_sink_mt> sinks, FlightLog::ErrorHandler on_error,
                 FlightLog::Format format = {});
  ~FlightRecorder();  ///< removes tern.log from the sinks (flushed), closes the log
  FlightRecorder(const FlightRecorder&) = delete;
  FlightRecorder& operator=(const FlightRecorder&) = delete;

  const fs::path& dir() const { return log_.dir(); }

  /// Writes config.yaml and every parameter's starting value with where it came from: `sources`
  /// (name -> the config's file:line, the command-line option, or the request that set it last:
  /// Host::param_sources()), else "default".
  void start(const std::string& config_yaml, const std::vector<std::pair<std::string, const ParamBase*>>& params,
             const std::map<std::string, std::string>& sources);
  /// Chooses the topics of `graph` to log (see above); warns (naming `config_file`) of topics
  /// `log.topics` names that nobody publishes. The graph must not change until the flight ends.
  /// The log's files as `log` (log.format, log.chunk_size, log.zstd_level) asks.
  static FlightLog::Format format_of(const LogConfig& log);
  /// The chunks' zstd level when log.zstd_level is unset: 2 up to level replay, 1 above (below).
  static int default_zstd_level(LogLevel level);
  void choose_topics(const PortGraph& graph, const LogConfig& log, const fs::path& config_file, spdlog::logger& warn);
  /// Hz: the most messages a second of `topic` that `log` keeps (0: every message).
  static double topic_rate(const LogConfig& log, const std::string& topic);
  /// Messages a writer of a topic logged in full holds for the capture at the end of a tick: 64
  /// covers 160 ms of a 400-Hz IMU arriving at once (a stalled serial link, a replayed burst).
  static constexpr std::size_t kBurstDepth = 64;
  /// A parameter's value from time t on, and who set it.
  void param(Nanos t, const std::string& qualified_name, const ParamBase& p, const std::string& source);
  /// At the end of a tick at flight time `now`: captures what was published on each logged topic.
  void capture(const PortGraph& graph, Nanos now);
  /// Hands buffered rows to the writer and flushes `text_log`, once per FlightLog::kFlushPeriodNs
  /// of wall time.
  void flush_if_due(spdlog::logger& text_log);
  /// Writes summary.json, closes the topic files, then writes timing.json (with the log
  /// writer's CPU time, stored into r.log_cpu_s); r.log_error: the log's first write error, else
  /// the first topic logged in full that lost messages (kBurstDepth).
  void finish(const FlightFacts& facts, FlightResult& r);
  /// Closes the log without a summary (a flight that never started).
  void close(FlightResult& r) {
    log_.close();
    r.log_error = log_.error();
  }

 private:
  struct Logged {                        // per topic of the graph
    std::size_t index = SIZE_MAX;        // FlightLog topic index (SIZE_MAX: not logged)
    std::size_t items = SIZE_MAX;        // FlightLog index of a waypoint list's items table
    const OutputBase* source = nullptr;  // writer of the message last captured
    std::uint64_t seq = 0;               // its sequence number
    Nanos interval = 0;                  // minimum flight time between two captures
    Nanos t = 0;                         // flight time of the last capture
    std::uint64_t lost = 0;              // messages of a logged-in-full topic its writer no longer held
    std::string topic;
  };
  void write(const Logged& l, Nanos now, const void* msg);
  FlightLog log_;
  std::shared_ptr<spdlog::sinks::dist_sink_mt> sinks_;
  std::shared_ptr<spdlog::sinks::sink> file_sink_;
  std::vector<Logged> logged_;
  std::int64_t last_flush_;  // wall_ns()
};

}  // namespace tern::core
