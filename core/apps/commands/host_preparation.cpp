// core/apps/commands/host_preparation.cpp: the shared preparation of a host (host_preparation.hpp).
#include "commands/host_preparation.hpp"

#include <cstdio>

#include "config/error.hpp"
#include "mavlink/plan_config.hpp"
#include "commands/override_options.hpp"

namespace tern::core {

void add_mission_override_options(CLI::App* cmd, HostPreparation& p) {
  add_override_options(cmd, p.overrides);
  cmd->add_option("--plan", p.plan,
                  "a QGroundControl plan (.plan): its mission replaces the config's, its home is the simulator's origin, its "
                  "geofence and rally points the failsafes' (docs/ground-station.md)")
      ->type_name("FILE.plan");
}

void add_skip_preflight_option(CLI::App* cmd, HostPreparation& p) {
  cmd->add_flag("--skip-preflight", p.skip_preflight,
                "take off at t = 0 without the arming checks (quick experiments; says so in the log)");
}

void add_log_level_option(CLI::App* cmd, HostPreparation& p) {
  cmd->add_option("--log-level", p.log_level,
                  "summary (no topic tables), decimated, replay (the default: sensors in full, the rest at log.plot_rate), sysid "
                  "(replay + truth and state in full) or full (overrides the config's log.level)")
      ->check([](const std::string& v) { return log_level_from_name(v) ? std::string() : "expected " + log_level_names(); });
  cmd->add_option("--log-format", p.log_format,
                  "csv (topics/*.csv), mcap (flight.mcap) or both (overrides the config's log.format; docs/logs.md)")
      ->check(CLI::IsMember({"csv", "mcap", "both"}));
}

void add_dds_options(CLI::App* cmd, HostPreparation& p) {
  cmd->add_flag("--dds", p.dds,
                "bridge telemetry, parameters and mission edits to Fast DDS (loopback unless the config's dds: names interfaces)");
  cmd->add_option("--dds-domain", p.dds_domain, "DDS domain id (overrides the config's dds.domain)")->check(CLI::Range(0, 232));
}

void add_console_options(CLI::App* cmd, HostPreparation& p) {
  cmd->add_flag("--console", p.console, "serve the flight console (a web page on 127.0.0.1; the URL with its token is printed)");
  cmd->add_option("--console-port", p.console_port, "console port (default: a free one)");
}

void add_gcs_options(CLI::App* cmd, HostPreparation& p) {
  cmd->add_option("--gcs", p.gcs,
                  "MAVLink 2 ground-station endpoint over UDP (QGroundControl, Mission Planner: docs/ground-station.md): "
                  "telemetry goes to ADDR:PORT (default 127.0.0.1:14550) and to every GCS heard")
      ->expected(0, 1)
      ->default_str("127.0.0.1:14550")
      ->check([](const std::string& v) {
        try {
          mavlink::check_endpoint(v, "");
        } catch (const std::exception& e) {
          return std::string(e.what());
        }
        return std::string();
      });
  cmd->add_option("--gcs-bind", p.gcs_bind, "with --gcs: the vehicle's own UDP ADDR:PORT (default 127.0.0.1:14580; port 0: a free one)")
      ->check([](const std::string& v) {
        try {
          mavlink::check_endpoint(v, "");
        } catch (const std::exception& e) {
          return std::string(e.what());
        }
        return std::string();
      });
}

void add_realtime_options(CLI::App* cmd, bool& realtime, RealtimeOptions& rt, const std::string& what) {
  auto* pace = cmd->add_flag("--realtime", realtime, what);
  cmd->add_option("--rt-priority", rt.priority, "with --realtime: run the flight thread SCHED_FIFO at this priority (1-99)")
      ->check(CLI::Range(1, 99))
      ->needs(pace);
  cmd->add_option("--cpu", rt.cpu, "with --realtime: pin the flight thread to this CPU (0-based)")
      ->check(CLI::NonNegativeNumber)
      ->needs(pace);
  cmd->add_flag("--mlockall", rt.lock_memory, "with --realtime: lock the process's memory (no page faults from disk in the loop)")
      ->needs(pace);
  cmd->add_option("--speed", rt.speed,
                  "with --realtime: flight time runs FACTOR times as fast as wall time (e.g. 2, 10: PX4's PX4_SIM_SPEED_FACTOR; "
                  "default 1)")
      ->type_name("FACTOR")
      ->check(CLI::Range(1e-3, 1000.0))
      ->needs(pace);
}

namespace {

void apply_skip_preflight(MissionConfig& mc) {
  mc.phase_params["preflight"] = ParamSetting{YAML::Node(false), mc.file, "--skip-preflight", true, "--skip-preflight"};
  mc.overrides.push_back("--skip-preflight");
}

void apply_log_level(MissionConfig& mc, const std::string& level) {
  mc.log.level = *log_level_from_name(level);
  if (!mc.root["log"]) mc.root["log"] = YAML::Node(YAML::NodeType::Map);
  mc.root["log"]["level"] = level;  // config.yaml records the level flown
}

void apply_log_format(MissionConfig& mc, const std::string& format) {
  mc.log.format = *log_format_from_name(format);
  if (!mc.root["log"]) mc.root["log"] = YAML::Node(YAML::NodeType::Map);
  mc.root["log"]["format"] = format;  // config.yaml records the format flown
}

}  // namespace

PreparedMission prepare_mission(const std::string& config_file, const HostPreparation& p) {
  return prepare_loaded(load_config(config_file), p);
}

PreparedMission prepare_loaded(MissionConfig config, const HostPreparation& p) {
  PreparedMission m{std::move(config)};
  MissionConfig& mc = m.config;
  if (p.plan) apply_plan(mc, *p.plan);  // first: a --set of the origin wins over the plan's home
  apply_overrides(mc, p.overrides);
  if (p.skip_preflight) apply_skip_preflight(mc);
  if (p.log_level) apply_log_level(mc, *p.log_level);
  if (p.log_format) apply_log_format(mc, *p.log_format);
#if defined(TERN_WITH_DDS)
  m.dds = parse_dds_options(mc.dds, mc.file);  // checked by `tern check` too
  if (p.dds) m.dds.enabled = true;
  m.dds_enabled = m.dds.enabled;  // the config's dds: counts for --console too
  if (p.dds_domain) {
    m.dds.domain = *p.dds_domain;
    // external instances (external_plugin.hpp) read the domain from dds: too
    if (!mc.dds || !mc.dds.IsMap()) mc.dds = YAML::Node(YAML::NodeType::Map);
    mc.dds["domain"] = *p.dds_domain;
  }
#else
  if (p.dds) throw ConfigError("this tern was built without Fast DDS (install libfastrtps-dev and fastddsgen: make deps)");
#endif
  return m;
}

std::unique_ptr<Host> describing_host(const std::string& config_file, const HostPreparation& p, Producers producers) {
  HostOptions opt;
  opt.describing = true;
  opt.producers = producers;
  opt.quiet = true;
  auto host = std::make_unique<Host>(prepare_mission(config_file, p).config, opt);
  host->build();
  return host;
}

TickObservers::TickObservers(Host& host, const HostPreparation& p, const PreparedMission& m, bool realtime) {
  if (p.console) {
    if (!realtime) throw ConfigError("--console needs --realtime (a page cannot follow a flight in fast time)");
    console_ = std::make_unique<Console>(host, console_asset_dir(), p.console_port);
    std::printf("console: %s\n", console_->url().c_str());
    std::fflush(stdout);
  }
#if defined(TERN_WITH_DDS)
  if (m.dds.enabled) bridge_ = std::make_unique<DdsBridge>(host, m.dds);
#endif
  if (p.gcs) {
    mavlink::LinkedVehicle vehicle;  // the mission's one: system id 1
    vehicle.host = &host;
    gcs_ = std::make_unique<GcsEndpoint>(p, std::vector<mavlink::LinkedVehicle>{vehicle});
  }
}

TickObservers::~TickObservers() = default;

GcsEndpoint::GcsEndpoint(const HostPreparation& p, const std::vector<mavlink::LinkedVehicle>& vehicles) {
  mavlink::GcsOptions g;
  g.send_to = p.gcs && !p.gcs->empty() ? *p.gcs : g.send_to;
  g.bind = p.gcs_bind;
  link_ = std::make_unique<mavlink::GcsLink>(vehicles, g);
  std::printf("mavlink: %s (%zu ids shortened to 16 characters: tern params CONFIG --mavlink)\n", link_->describe().c_str(),
              link_->shortened_ids().size());
  std::fflush(stdout);
}

GcsEndpoint::~GcsEndpoint() {
  const mavlink::Counters c = link_->counters();
  std::printf(
      "mavlink: %llu datagrams, %llu frames; dropped: %llu bad CRC, %llu truncated, %llu unknown ids, %llu MAVLink 1, %llu too long, %llu "
      "noise; %llu for no vehicle here\n",
      static_cast<unsigned long long>(c.datagrams), static_cast<unsigned long long>(c.frames), static_cast<unsigned long long>(c.bad_crc),
      static_cast<unsigned long long>(c.truncated), static_cast<unsigned long long>(c.unknown_id),
      static_cast<unsigned long long>(c.mavlink1), static_cast<unsigned long long>(c.bad_length), static_cast<unsigned long long>(c.noise),
      static_cast<unsigned long long>(c.other_system));
  std::fflush(stdout);
}

std::string TickObservers::console_url() const { return console_ ? console_->url() : std::string(); }

}  // namespace tern::core
