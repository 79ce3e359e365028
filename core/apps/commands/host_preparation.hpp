// core/apps/commands/host_preparation.hpp: what `tern fly`, `serve`, `check` and `params` do the
// same way before a host is built, and what watches its ticks while it flies:
//   the mission config loaded, with the command line's --set/--phases/--fallback
//   (cli_overrides.hpp), --skip-preflight and --log-level applied;
//   the config's dds: section checked (every command) and --dds/--dds-domain applied;
//   the tick observers a flight asked for: the console (--console, --console-port), the DDS
//   bridge (--dds or the config's dds.enabled) and the MAVLink endpoint (--gcs, --gcs-bind).
// The options are worded once here for every command that takes them.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "config/cli_overrides.hpp"
#include "config/config.hpp"
#include "console/console.hpp"
#include "flight/host.hpp"
#include "mavlink/gcs_link.hpp"
#if defined(TERN_WITH_DDS)
#include "dds_bridge.hpp"
#endif

namespace tern::core {

/// The command line's changes to a mission and its host, as parsed (each command takes a subset).
struct HostPreparation {
  CliOverrides overrides;
  std::optional<std::string> plan;           ///< --plan FILE.plan: a QGroundControl plan flown (mavlink/plan_config.hpp)
  bool skip_preflight = false;               ///< --skip-preflight: take off at t = 0 without the arming checks
  std::optional<std::string> log_level;      ///< --log-level: summary, decimated or full
  std::optional<std::string> log_format;     ///< --log-format: csv, mcap or both
  bool dds = false;                          ///< --dds: bridge to Fast DDS
  std::optional<std::uint32_t> dds_domain;   ///< --dds-domain: 0 .. 232
  bool console = false;                      ///< --console: serve the flight console (needs --realtime)
  std::uint16_t console_port = 0;            ///< --console-port (0: a free one)
  std::optional<std::string> gcs;            ///< --gcs [ADDR:PORT]: the MAVLink endpoint, sending there first
  std::string gcs_bind = "127.0.0.1:14580";  ///< --gcs-bind ADDR:PORT: the vehicle's own UDP address
};

/// --set, --phases, --fallback (override_options.hpp), --plan FILE.plan.
void add_mission_override_options(CLI::App* cmd, HostPreparation& p);
/// --skip-preflight.
void add_skip_preflight_option(CLI::App* cmd, HostPreparation& p);
/// --log-level.
void add_log_level_option(CLI::App* cmd, HostPreparation& p);
/// --dds, --dds-domain.
void add_dds_options(CLI::App* cmd, HostPreparation& p);
/// --console, --console-port.
void add_console_options(CLI::App* cmd, HostPreparation& p);
/// --gcs [ADDR:PORT], --gcs-bind ADDR:PORT (mavlink/gcs_link.hpp, docs/ground-station.md).
void add_gcs_options(CLI::App* cmd, HostPreparation& p);
/// --realtime and the flight thread's scheduling with it (flight/realtime.hpp): --rt-priority N,
/// --cpu K, --mlockall; `what`: "pace the simulated clock to wall time" or the like.
void add_realtime_options(CLI::App* cmd, bool& realtime, RealtimeOptions& rt, const std::string& what);

/// A mission config ready for a Host, and whether its flights are bridged to DDS.
struct PreparedMission {
  MissionConfig config;
  bool dds_enabled = false;  ///< --dds or the config's dds.enabled
#if defined(TERN_WITH_DDS)
  DdsOptions dds;  ///< the config's dds: with --dds and --dds-domain applied
#endif
};

/// Loads `config_file` and applies `p` (see the file comment). Throws ConfigError with one line:
/// the config's own errors, a bad override, a bad dds: section, or --dds on a tern built without
/// Fast DDS.
PreparedMission prepare_mission(const std::string& config_file, const HostPreparation& p);
/// The same for a config already loaded (a fleet's vehicle, fleet_config.hpp).
PreparedMission prepare_loaded(MissionConfig config, const HostPreparation& p);

/// A built host that only describes the mission (`tern check`, `tern params`): instances
/// configured with `describing` (no file or device opened), port graph bound, nothing flown.
/// `producers`: not_checked lets an input without a producer pass (`tern params` on a replay's
/// config, whose sensors come from a log). Throws ConfigError as prepare_mission() and
/// Host::build() do.
std::unique_ptr<Host> describing_host(const std::string& config_file, const HostPreparation& p, Producers producers = Producers::required);

/// The MAVLink endpoint of --gcs (mavlink/gcs_link.hpp) for one vehicle or a fleet's on one port:
/// its addresses printed on stdout when it opens, what it received and dropped when it closes.
class GcsEndpoint {
 public:
  /// Throws ConfigError: a port that cannot be bound, two vehicles with one system id.
  GcsEndpoint(const HostPreparation& p, const std::vector<mavlink::LinkedVehicle>& vehicles);
  ~GcsEndpoint();
  GcsEndpoint(const GcsEndpoint&) = delete;
  GcsEndpoint& operator=(const GcsEndpoint&) = delete;

 private:
  std::unique_ptr<mavlink::GcsLink> link_;
};

/// The observers of a host's ticks for as long as this lives: the console when --console was
/// given (its URL printed on stdout), then the DDS bridge when the mission is bridged, then the
/// MAVLink endpoint with --gcs (its addresses printed on stdout).
/// Destroyed in the reverse order.
class TickObservers {
 public:
  /// Throws ConfigError when the console cannot be served (it needs `realtime`) or the MAVLink
  /// port cannot be bound. The console, the DDS bridge and the MAVLink endpoint can watch one
  /// host together (Host::add_tick_observer).
  TickObservers(Host& host, const HostPreparation& p, const PreparedMission& m, bool realtime);
  ~TickObservers();
  TickObservers(const TickObservers&) = delete;
  TickObservers& operator=(const TickObservers&) = delete;

  /// The console's URL with its token; empty without a console.
  std::string console_url() const;
  /// The console, nullptr without one.
  Console* console() const { return console_.get(); }

 private:
  std::unique_ptr<Console> console_;
#if defined(TERN_WITH_DDS)
  std::unique_ptr<DdsBridge> bridge_;
#endif
  std::unique_ptr<GcsEndpoint> gcs_;
};

}  // namespace tern::core
