// core/host/config/config.hpp: the mission config (configs/missions/*.yaml), loaded and validated.
//
// Every key is checked: an unknown key is an error that suggests the closest valid one. Paths
// are relative to the file that names them. See docs/mission-config.md for the format.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "config/failsafe_config.hpp"
#include "tern/msg/phase.hpp"
#include "tern/param.hpp"

namespace tern::core {

namespace fs = std::filesystem;

/// One parameter value from the config or a parameter file, with where it came from.
struct ParamSetting {
  YAML::Node node;     ///< the value
  fs::path file;       ///< file that set it (relative paths resolve against its directory)
  std::string field;   ///< e.g. "plugins[2].params.roll_kp"
  bool strict = true;  ///< unknown names are errors (false for shared ROS 2 parameter files)
  /// The command-line option that set it ("--set slc.roll_kp=0.5"), "" when a file did.
  std::string option{};
  /// Where an error about the value starts: "file:line:col: field" or the option.
  std::string location() const;
  /// Where the value came from, for the flight log's params.csv: the option, else "file:line".
  std::string source() const;
};

struct InstanceConfig {
  std::size_t index = 0;  ///< position in `plugins:`
  std::string field;      ///< where it is in the file: "plugins[2]" ("coordination[0]" in a fleet's)
  /// `field`, or "plugins[<index>]" when none was set.
  std::string label() const { return field.empty() ? "plugins[" + std::to_string(index) + "]" : field; }
  std::string name;                    ///< instance name
  std::string plugin;                  ///< plugin name or a path to a .so
  std::optional<double> rate;          ///< Hz
  std::optional<std::string> trigger;  ///< input port name
  std::optional<double> budget_us;     ///< per-step time budget (default: the period)
  bool isolate = false;                ///< run in a child process (isolated_plugin.hpp)
  std::map<std::string, ParamSetting> params;
  std::map<std::string, std::string> remap;  ///< port -> topic
  YAML::Node node;                           ///< the entry, for error locations
};

/// How much of a flight the log keeps, as PX4's logger profiles do (its default profile logs the
/// sensors at every sample and vehicle_attitude at 20 Hz: src/modules/logger/logged_topics.cpp).
/// summary: config.yaml, params.csv, tern.log, summary.json and timing.json, no topic tables (a
/// campaign flight); decimated: every logged topic, the sensors too, at most `decimated_rate` Hz
/// (cannot be replayed); replay (the default): the replay inputs (sensors, rc, fcu_status,
/// actuators) at every message, the other topics at most `plot_rate` Hz; sysid: as replay, and
/// `truth` and `state` at every message too (system identification); full: the replay inputs at
/// every message, the other topics as `max_rate` says (a config that sets `max_rate` and no
/// level gets full). `rates` overrides any level's per topic.
enum class LogLevel { summary, decimated, replay, sysid, full };
/// "summary", "decimated", "replay", "sysid", "full".
const char* log_level_name(LogLevel level);
/// The level named `name`, nullopt if none.
std::optional<LogLevel> log_level_from_name(const std::string& name);
/// The level names for an error message: "summary, decimated, replay, sysid or full".
std::string log_level_names();

/// Which files hold the logged topics: csv (topics/<t>.csv), mcap (flight.mcap) or both.
enum class LogFormat { csv, mcap, both };
/// "csv", "mcap", "both".
const char* log_format_name(LogFormat format);
/// The format named `name`, nullopt if none.
std::optional<LogFormat> log_format_from_name(const std::string& name);

/// log.zstd_level's range: zstd's fast levels (-7: least CPU) to its slowest without "ultra" memory (19).
constexpr int kZstdLevelMin = -7;
constexpr int kZstdLevelMax = 19;

struct LogConfig {
  fs::path dir;  ///< parent of the run directories
  LogLevel level = LogLevel::replay;
  LogFormat format = LogFormat::csv;
  std::size_t chunk_size = 1024 * 1024;  ///< bytes of messages per MCAP chunk, uncompressed
  bool ros_channels = true;              ///< MCAP: each topic's copy in its ROS 2 type too (core/formats/ros/ros_channels.hpp)
  /// MCAP: the chunks' zstd level, kZstdLevelMin..kZstdLevelMax; unset: FlightRecorder::default_zstd_level
  std::optional<int> zstd_level;
  double decimated_rate = 10.0;  ///< Hz, every topic's limit at level decimated (> 0)
  /// Hz, the limit of the topics not kept in full at levels replay and sysid, and of the ROS-typed
  /// copies there (> 0): PX4's default profile logs vehicle_local_position every 100 ms
  double plot_rate = 10.0;
  bool all_topics = true;
  std::vector<std::string> topics;      ///< when !all_topics
  double max_rate = 100.0;              ///< Hz: a topic's messages closer than 1/max_rate are not logged (0: all)
  std::map<std::string, double> rates;  ///< per-topic max_rate overrides
};

/// `watchdog:`: wall-time budgets of one plugin call (a step; for isolated instances every call).
/// Past `soft` a step is reported (one warning per instance, the count in timing.json); past
/// `hard` the flight ends cleanly (in-process: watchdog.hpp) or the isolated child is killed.
/// The defaults are far above any stock plugin's step (the slowest, sim_aero, takes about
/// 0.1 ms) so that a loaded 2-core machine never trips them.
struct WatchdogConfig {
  double soft_ms = 50.0;    ///< ms
  double hard_ms = 2000.0;  ///< ms
};

/// `check:`: limits of `tern check` (and of `tern fly`'s check before it flies) on the mission.
struct MissionCheckConfig {
  /// m: a waypoint further than this from home (3-D) is an error; 5 km is well beyond a
  /// small UAV's visual-line-of-sight area, and far inside the 20+ km that a latitude/longitude
  /// read as metres (the `lla` flag forgotten) or a missing minus sign gives.
  double max_waypoint_distance = 5000.0;
};

struct MissionConfig {
  fs::path file;  ///< absolute path of the config
  fs::path dir;   ///< its directory
  std::string name;
  std::uint64_t seed = 1;
  double duration = 60.0;           ///< s
  std::optional<double> base_rate;  ///< Hz
  fs::path aircraft;                ///< resolved, empty if none
  std::vector<fs::path> plugin_path;
  LogConfig log;
  WatchdogConfig watchdog;
  std::vector<InstanceConfig> plugins;
  std::map<msg::Phase, std::string> phases;  ///< phase -> controller instance
  std::optional<std::string> fallback;
  std::map<std::string, ParamSetting> phase_params;    ///< `phase_machine:` parameters
  std::map<std::string, ParamSetting> metrics_params;  ///< `metrics:` parameters
  YAML::Node mission;                                  ///< free-form, for the path planner
  YAML::Node dds;                                      ///< free-form, for the DDS bridge
  FailsafeConfig failsafes;                            ///< `failsafes:` (failsafe_config.hpp), the defaults without it
  MissionCheckConfig check;                            ///< `check:`
  YAML::Node root;                                     ///< the whole document as loaded
  /// Command-line options that changed it after loading (cli_overrides.hpp), as given; the
  /// flight log's config.yaml names them.
  std::vector<std::string> overrides;
  std::string phases_option;    ///< the --phases option that set `phases` ("" : the file)
  std::string fallback_option;  ///< the --fallback option that set `fallback` ("" : the file)
  /// A multi-vehicle mission's vehicle names (fleet_config.hpp), for its coordination plugins
  /// (Context::vehicles()); empty in a vehicle's own config and in a one-vehicle mission.
  std::vector<std::string> vehicles;
  /// Which part of a multi-vehicle mission this is: a vehicle's name or "coordination" ("" for a
  /// one-vehicle mission): what an isolated instance's child loads (load_fleet_part).
  std::string fleet_part;
};

/// Loads and validates a mission config. Throws ConfigError (one line: file:line:col: field: what),
/// also for a multi-vehicle mission (`vehicles:`, fleet_config.hpp), which is not one host's.
MissionConfig load_config(const fs::path& file);
/// The same checks on a document already loaded from `file` (relative paths resolve against its
/// directory); `plugins_key` names the list of instances ("plugins"; a fleet's "coordination").
MissionConfig config_from_yaml(const YAML::Node& root, const fs::path& file, const std::string& plugins_key = "plugins");
/// Reads a YAML file (`what`: "config file", in errors). Throws ConfigError: missing, unreadable,
/// a syntax error (file:line:col).
YAML::Node load_yaml(const fs::path& file, const char* what);

// ---- meaning checks, shared by the config, the command line and `tern serve` ----------------

/// The fastest rate the scheduler runs, Hz (an instance rate or the base rate; a tick then has
/// 100 us for every instance due in it).
constexpr double kMaxRateHz = 10'000.0;
/// The longest flight, s (11.6 days: longer is a typo; flight time is int64 nanoseconds).
constexpr double kMaxDurationS = 1e6;
/// What is wrong with `seconds` as a flight length ("" if nothing): finite, > 0, <= kMaxDurationS.
std::string duration_problem(double seconds);
/// A random seed as written: a decimal integer 0 .. 2^64-1 (no sign, no exponent); nullopt else.
std::optional<std::uint64_t> parse_seed(const std::string& text);
/// What is wrong with `name` as an instance name ("" if nothing): an identifier, [A-Za-z_][A-Za-z0-9_]*,
/// since it names parameters (name.param), log columns and files.
std::string identifier_problem(const std::string& name);
/// Throws ConfigError (file:line:col) for a topic named in `log.topics` or `log.rates` that no
/// instance publishes (`published`: the topics that have a writer).
void check_log_topics(const MissionConfig& config, const std::vector<std::string>& published);

/// A YAML scalar or sequence as a parameter value: true/false -> bool, integer literal ->
/// integer, number -> real, sequence of numbers -> vector, anything else (or quoted) -> text.
/// Throws ConfigError for maps and mixed sequences.
ParamValue to_param_value(const YAML::Node& node, const fs::path& file, const std::string& field);

/// Reads a parameter file: a flat map `name: value`, or ROS 2 style
/// `<node>: {ros__parameters: {...}}` where the blocks named `/**`, `instance` or `plugin`
/// apply (in that order, later wins). Throws ConfigError.
std::map<std::string, ParamSetting> load_param_file(const fs::path& file, const std::string& instance, const std::string& plugin);

}  // namespace tern::core
