// tern: the command line. `tern --help` lists the commands; every command has --help.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "console/console.hpp"
#include "config/error.hpp"
#include "flight/host.hpp"
#include "flight/loader.hpp"
#include "config/mission_check.hpp"
#include "config/override_options.hpp"
#include "commands/serve.hpp"
#include "commands/tune_command.hpp"
#if defined(TERN_WITH_DDS)
#include "dds_bridge.hpp"
#include "commands/dds_command.hpp"
#include "external_link_dds.hpp"
#include "topic_tools.hpp"
#endif

#ifndef TERN_SOURCE_DIR
#define TERN_SOURCE_DIR ""
#endif
#ifndef TERN_INSTALL_DATA_DIR
#define TERN_INSTALL_DATA_DIR ""
#endif

namespace fs = std::filesystem;
using namespace tern;
using namespace tern::core;

namespace {

fs::path exe_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

fs::path default_config() {
  // an installed tern: <prefix>/share/tern; a build tree's tern: the source tree
  for (const fs::path& base : {exe_dir() / ".." / "share" / "tern", fs::path(TERN_SOURCE_DIR), fs::path(TERN_INSTALL_DATA_DIR)}) {
    if (base.empty()) continue;
    const fs::path p = (base / "configs" / "missions" / "default.yaml").lexically_normal();
    if (fs::exists(p)) return p;
  }
  return fs::path("configs/missions/default.yaml");
}

int fail(const std::string& msg) {
  std::fprintf(stderr, "tern: error: %s\n", msg.c_str());
  return 1;
}

/// The console for `host` when --console was given (after anything else that sets the tick
/// observer): prints its URL. Throws ConfigError when it cannot be served.
std::unique_ptr<Console> open_console(Host& host, bool wanted, bool realtime, bool dds, std::uint16_t port) {
  if (!wanted) return nullptr;
  if (!realtime) throw ConfigError("--console needs --realtime (a page cannot follow a flight in fast time)");
  if (dds) throw ConfigError("--console and --dds cannot be used together yet (both watch every tick); use one");
  auto c = std::make_unique<Console>(host, console_asset_dir(), port);
  std::printf("console: %s\n", c->url().c_str());
  std::fflush(stdout);
  return c;
}

/// --seed and --duration mean what the config's seed: and duration: mean (config.hpp).
const CLI::Validator kSeedCheck(
    [](std::string& s) { return parse_seed(s) ? std::string() : "'" + s + "' is not a seed: an integer 0 .. 2^64-1"; }, "SEED", "seed");
const CLI::Validator kDurationCheck(
    [](std::string& s) {
      std::size_t used = 0;
      double v = 0;
      try {
        v = std::stod(s, &used);
      } catch (const std::exception&) {
      }
      if (used == 0 || used != s.size()) return "'" + s + "' is not a number of seconds";
      return duration_problem(v);
    },
    "SECONDS", "flight length");

/// Context for listing a plugin's ports and parameters without a mission.
class DescribeContext final : public Context {
 public:
  const std::string& instance_name() const override { return name_; }
  std::optional<ParamValue> configured_value(const std::string&, const ParamSpec&) const override { return std::nullopt; }
  std::uint64_t seed() const override { return 1; }
  std::shared_ptr<spdlog::logger> logger() const override { return nullptr; }
  std::filesystem::path config_dir() const override { return {}; }
  const YAML::Node& mission() const override { return mission_; }
  std::filesystem::path aircraft_file() const override { return {}; }
  bool describing() const override { return true; }

 private:
  std::string name_ = "describe";
  YAML::Node mission_;
};

/// A parameter's description, marked when it is read only when a flight starts.
std::string description_text(const ParamBase& p) { return p.spec().description + (p.spec().live ? "" : " [start-only]"); }

std::string range_text(const ParamBase& p) {
  const auto& s = p.spec();
  if (p.kind() == ParamKind::text) return s.choices.empty() ? (s.is_path ? "path" : "") : fmt::format("{}", fmt::join(s.choices, "|"));
  if (p.kind() == ParamKind::boolean) return "";
  return fmt::format("[{}, {}]{}", s.min, s.max, s.size ? fmt::format(" x{}", s.size) : "");
}

/// Prints the warnings and errors of `r` on stderr; true when there are no errors.
bool report_missions(const MissionReport& r) {
  for (const auto& w : r.warnings) std::fprintf(stderr, "tern: warning: %s\n", w.c_str());
  for (const auto& e : r.errors) std::fprintf(stderr, "tern: error: %s\n", e.c_str());
  return r.errors.empty();
}

int cmd_plugins(const std::vector<std::string>& extra_dirs) {
  std::vector<fs::path> dirs(extra_dirs.begin(), extra_dirs.end());
  const auto search = plugin_search_path(dirs);
  const auto found = discover_plugins(search);
  fmt::print("plugin search path:\n");
  for (const auto& d : search) fmt::print("  {}\n", d.string());
  if (found.empty()) fmt::print("no plugins found\n");
  for (const auto& path : found) {
    try {
      auto lib = open_plugin(path);
      DescribeContext ctx;
      std::unique_ptr<Plugin> p = lib->create();
      p->attach(&ctx);
      fmt::print("\n{} ({}) - {}\n  {}\n", lib->info().name, kind_name(lib->info().kind), lib->info().description, path.string());
      try {
        p->configure();
      } catch (const std::exception& e) {
        fmt::print("  (configure failed: {})\n", e.what());
      }
      for (auto* in : p->inputs())
        fmt::print("  in  {:<22} {:<26} {}{}\n", in->name(), in->type().name, in->description(),
                   in->need() == Need::optional ? " (optional)" : "");
      for (auto* out : p->outputs()) fmt::print("  out {:<22} {:<26} {}\n", out->name(), out->type().name, out->description());
      for (auto* prm : p->params())
        fmt::print("  param {:<20} = {:<14} {:<8} {:<18} {}\n", prm->name(), to_string(prm->value()), prm->spec().unit, range_text(*prm),
                   description_text(*prm));
      p.reset();  // before the library goes
    } catch (const ConfigError& e) {
      fmt::print("\n{}: {}\n", path.string(), e.what());
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // git-style extension commands: `tern aero ...` runs `tern-aero ...` from the same directory.
  if (argc >= 2 && argv[1][0] != '-') {
    const std::string sub = argv[1];
    static const std::set<std::string> builtin = {"fly",  "check", "plugins", "params",  "serve",  "swap", "phases",  "remote", "topics",
                                                  "echo", "hz",    "param",   "mission", "replay", "tune", "console", "help"};
    if (!builtin.count(sub)) {
      const fs::path ext = exe_dir() / ("tern-" + sub);
      if (fs::exists(ext)) {
        std::vector<char*> args;
        std::string prog = ext.string();
        args.push_back(prog.data());
        for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
        args.push_back(nullptr);
        execv(prog.c_str(), args.data());
        return fail(fmt::format("cannot run {}: {}", prog, std::strerror(errno)));
      }
    }
  }

#if defined(TERN_WITH_DDS)
  register_dds_external_links();  // `plugin: external` instances (external_plugin.hpp)
#endif
  CLI::App app{
      "tern: a fixed-wing autopilot framework for research.\n"
      "Flies plugins named in a YAML mission config, in the simulator or on an aircraft."};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "help for every command");
  app.failure_message([](const CLI::App*, const CLI::Error& e) { return fmt::format("tern: error: {} (see --help)\n", e.what()); });
  app.footer(
      "More commands: tern plot RUN_DIR [RUN_B ...] (figures of a flight, index.html; several runs: overlaid), tern aero (aircraft models, "
      "trim),\n"
      "tern campaign FILE (Monte Carlo flights: a table, a summary and plots),\n"
      "tern new-plugin NAME --kind KIND (a plugin project from a template), tern fcu (FCU parameters).");

  std::string config;
  std::optional<std::uint64_t> seed;
  std::optional<double> duration;
  std::optional<std::string> log_dir;
  bool realtime = false, quiet = false, dot = false, dds = false, skip_preflight = false;
  std::optional<std::uint32_t> dds_domain;
  std::vector<std::string> plugin_dirs;
  bool console = false;
  std::uint16_t console_port = 0;
  const auto console_opts = [&](CLI::App* c) {
    c->add_flag("--console", console, "serve the flight console (a web page on 127.0.0.1; the URL with its token is printed)");
    c->add_option("--console-port", console_port, "console port (default: a free one)");
  };

  auto* fly = app.add_subcommand("fly", "fly a mission (default: configs/missions/default.yaml) and write its flight log");
  fly->add_option("config", config, "mission config (YAML)");
  fly->add_option("--seed", seed, "random seed (overrides the config's seed)")->check(kSeedCheck);
  fly->add_option("--duration", duration, "flight length in seconds (overrides the config)")->check(kDurationCheck);
  fly->add_flag("--realtime", realtime, "pace the simulated clock to wall time");
  console_opts(fly);
  fly->add_flag("--skip-preflight", skip_preflight, "take off at t = 0 without the arming checks (quick experiments; says so in the log)");
  fly->add_option("--log-dir", log_dir, "directory for the run directory (default: the config's log.dir, else ./runs)");
  std::optional<std::string> log_level;
  fly->add_option("--log-level", log_level, "summary (no topic tables), decimated or full (overrides the config's log.level)")
      ->check(CLI::IsMember({"summary", "decimated", "full"}));
  fly->add_flag("-q,--quiet", quiet, "print only warnings, errors and where the log went");
  fly->add_flag("--dds", dds,
                "bridge telemetry, parameters and mission edits to Fast DDS (loopback unless the config's dds: names interfaces)");
  fly->add_option("--dds-domain", dds_domain, "DDS domain id (overrides the config's dds.domain)")->check(CLI::Range(0, 232));

  CliOverrides overrides;
  add_override_options(fly, overrides);

  auto* check = app.add_subcommand("check", "validate a mission config and its waypoints without flying and print its port graph");
  check->add_option("config", config, "mission config (YAML)")->required();
  check->add_flag("--dot", dot, "print the port graph as Graphviz instead of text");
  add_override_options(check, overrides);

  auto* plugins = app.add_subcommand("plugins", "list the plugins in the search path, with their ports and parameters");
  plugins->add_option("--path", plugin_dirs, "extra plugin directories to search first");

  std::string replay_dir;
  auto* replay =
      app.add_subcommand("replay", "run the estimator over a flight log's recorded sensors and compare it with the recorded truth");
  replay->add_option("run_dir", replay_dir, "a flight log directory (runs/<time>-<mission>)")->required()->check(CLI::ExistingDirectory);
  replay->add_option("--config", config, "mission config naming the estimator(s) to run (default: the run's config.yaml)");
  replay->add_option("--log-dir", log_dir, "directory for the replay's own run directory (default: ./runs)");
  replay->add_flag("-q,--quiet", quiet, "print only the summary");

  TuneCommand tune;
  add_tune_command(app, tune);
  auto* params = app.add_subcommand("params", "list every parameter of a mission: value, default, unit, range, description");
  params->add_option("config", config, "mission config (YAML)")->required();
  add_override_options(params, overrides);

  std::string socket = default_socket().string();
  std::string instance, so_path, fallback, remote_cmd;
  std::vector<std::string> phase_args, remote_args;
  auto* serve_cmd = app.add_subcommand("serve", "keep a host alive across flights; control it with swap, phases and remote");
  serve_cmd->add_option("config", config, "mission config (YAML)")->required();
  serve_cmd->add_option("--socket", socket, "control socket")->capture_default_str();
  serve_cmd->add_option("--log-dir", log_dir, "directory for the run directories");
  serve_cmd->add_flag("--realtime", realtime, "pace each flight to wall time");
  console_opts(serve_cmd);
  serve_cmd->add_flag("--dds", dds, "bridge telemetry, parameters and mission edits to Fast DDS");
  serve_cmd->add_option("--dds-domain", dds_domain, "DDS domain id (overrides the config's dds.domain)")->check(CLI::Range(0, 232));
  add_override_options(serve_cmd, overrides);
  auto* swap_cmd = app.add_subcommand("swap", "between flights of `tern serve`: replace an instance's plugin with another .so");
  swap_cmd->add_option("instance", instance, "instance name in the mission config")->required();
  swap_cmd->add_option("path", so_path, "the new plugin: a path to a .so, or a plugin name")->required();
  swap_cmd->add_option("--socket", socket, "control socket of the server")->capture_default_str();
  auto* phases_cmd = app.add_subcommand("phases", "between flights of `tern serve`: set the phase -> controller table");
  phases_cmd->add_option("table", phase_args, "PHASE=INSTANCE ... (the phases named change; the others keep their controller)")->required();
  phases_cmd->add_option("--fallback", fallback, "controller used if the active one fails");
  phases_cmd->add_option("--socket", socket, "control socket of the server")->capture_default_str();
  auto* console_cmd = app.add_subcommand("console", "the URL of the console of a `tern serve --realtime --console` (open it in a browser)");
  console_cmd->add_option("--socket", socket, "control socket of the server")->capture_default_str();
  auto* remote = app.add_subcommand(
      "remote",
      "send a command to `tern serve`: fly [SECONDS] (prints the summary tables), abort (ends the flight, keeps the server), status, quit");
  remote->add_option("command", remote_cmd, "fly, abort, status or quit")
      ->required()
      ->check(CLI::IsMember({"fly", "abort", "status", "quit"}));
  remote->add_option("args", remote_args, "fly: flight length in seconds");
  remote->add_option("--socket", socket, "control socket of the server")->capture_default_str();

#if defined(TERN_WITH_DDS)
  // ---- against a running `tern fly --dds` (or serve --dds) ----
  std::string client_config, client_ns = "tern", topic, param_name, param_value, file_arg, param_prefix;
  std::uint32_t client_domain = 0;
  double client_timeout = 3.0;
  std::string field;
  std::optional<std::uint64_t> request_id;
  std::optional<std::string> client_keystore, client_enclave;
  std::optional<double> hz_duration;
  bool overwrite = false;
  bool once = false, wp_lla = false, wp_use_chi = false, wp_set_current = false;
  double wp_chi = 0, wp_Va = 0;
  std::vector<double> wp_w;
  std::vector<CLI::App*> client_cmds;
  auto client_opts = [&](CLI::App* c) {
    c->add_option("--domain", client_domain, "DDS domain id of the vehicle")->check(CLI::Range(0, 232));
    c->add_option("--namespace", client_ns, "vehicle namespace")->capture_default_str();
    c->add_option("--config", client_config, "take domain, namespace, interfaces and peers from this mission config's dds:");
    c->add_option("--timeout", client_timeout, "seconds to wait for the vehicle")->capture_default_str()->check(CLI::Range(0.001, 86400.0));
    // 1 .. 2^63-1: the ids a vehicle remembers (answered_requests.hpp); another would be applied again
    c->add_option("--request-id", request_id, "repeat a request that timed out with the id its error gave (applied once)")
        ->check(CLI::Range(std::uint64_t{1}, (std::uint64_t{1} << 63) - 1));
    c->add_option("--keystore", client_keystore, "DDS Security keystore (tern dds keystore create; default: $TERN_DDS_KEYSTORE)");
    c->add_option("--enclave", client_enclave, "enclave of the keystore to use (default: $TERN_DDS_ENCLAVE, else ground)");
    client_cmds.push_back(c);
    return c;
  };
  auto* topics_cmd = client_opts(app.add_subcommand("topics", "list the vehicle's DDS topics and their types"));
  auto* echo_cmd = client_opts(app.add_subcommand("echo", "print a bridged topic's live values"));
  echo_cmd->add_option("topic", topic, "tern topic name, e.g. state")->required();
  echo_cmd->add_flag("--once", once, "print one sample and exit");
  echo_cmd->add_option("--field", field, "print only this field (e.g. p_n, quat, header.stamp)");
  auto* hz_cmd = client_opts(app.add_subcommand("hz", "the receive rate of a topic, every second (as ros2 topic hz)"));
  hz_cmd->add_option("topic", topic, "tern topic name, e.g. state")->required();
  hz_cmd->add_option("--duration", hz_duration, "stop after this many seconds")->check(CLI::PositiveNumber);
  auto* param_cmd = client_opts(app.add_subcommand("param", "the vehicle's parameters over DDS: list, get, set, save"));
  param_cmd->require_subcommand(1);
  param_cmd->fallthrough();  // --domain etc. may follow `param set NAME VALUE`
  auto* param_list = param_cmd->add_subcommand("list", "every parameter (or those starting with PREFIX)");
  param_list->add_option("prefix", param_prefix, "e.g. slc.");
  auto* param_get = param_cmd->add_subcommand("get", "one parameter");
  param_get->add_option("name", param_name, "instance.param")->required();
  auto* param_describe = param_cmd->add_subcommand("describe", "one parameter's descriptor (rcl_interfaces describe_parameters)");
  param_describe->add_option("name", param_name, "instance.param")->required();
  auto* param_set = param_cmd->add_subcommand("set", "change a parameter (validated; applied at the next tick; logged)");
  param_set->add_option("name", param_name, "instance.param")->required();
  param_set->add_option("value", param_value, "a number, true/false, text, or [a, b, c]")->required();
  auto* param_save = param_cmd->add_subcommand("save", "write every parameter to a YAML file on the vehicle");
  param_save->add_option("file", file_arg, "file name on the vehicle (inside its log directory or dds.param_dirs)")->required();
  param_save->add_flag("--overwrite", overwrite, "replace an existing file");
  auto* mission_cmd = client_opts(app.add_subcommand("mission", "the vehicle's mission over DDS: add, clear, load, print"));
  mission_cmd->require_subcommand(1);
  mission_cmd->fallthrough();
  auto* m_add = mission_cmd->add_subcommand("add", "add a waypoint (ROSplane's AddWaypoint)");
  m_add->add_option("w", wp_w, "north east down (m), or lat lon alt with --lla")->required()->expected(3);
  m_add->add_flag("--lla", wp_lla, "w is latitude (deg), longitude (deg), altitude (m MSL)");
  m_add->add_option("--chi", wp_chi, "desired course at the waypoint, rad");
  m_add->add_flag("--use-chi", wp_use_chi, "fly a Dubins path to arrive at --chi");
  m_add->add_option("--Va", wp_Va, "desired airspeed, m/s")->required()->check(CLI::PositiveNumber);
  m_add->add_flag("--set-current", wp_set_current, "start a new list with this waypoint, now");
  auto* m_clear = mission_cmd->add_subcommand("clear", "remove every waypoint (the aircraft orbits the origin)");
  auto* m_load = mission_cmd->add_subcommand("load", "replace the mission with a waypoint file on the vehicle");
  m_load->add_option("file", file_arg, "tern or ROSplane waypoint file")->required();
  auto* m_print = mission_cmd->add_subcommand("print", "the vehicle's current waypoints");
  (void)m_clear;
  DdsCommand dds_cmd;
  add_dds_command(app, dds_cmd);
#endif

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    if (plugins->parsed()) return cmd_plugins(plugin_dirs);
    if (tune.app->parsed()) return run_tune_command(tune, default_config(), exe_dir() / "tern-plot");
#if defined(TERN_WITH_DDS)
    if (dds_cmd.app->parsed()) return run_dds_command(dds_cmd);
    for (auto* c : client_cmds) {
      if (!c->parsed()) continue;
      DdsOptions dopt;
      if (!client_config.empty()) {
        const MissionConfig mc = load_config(client_config);
        dopt = parse_dds_options(mc.dds, mc.file);
      }
      if (c->count("--domain")) dopt.domain = client_domain;
      if (c->count("--namespace") || client_config.empty()) dopt.ns = client_ns;
      try {
        apply_client_security(dopt, client_keystore, client_enclave);
        DdsClient client(dopt, std::chrono::milliseconds(static_cast<long>(client_timeout * 1000)));
        if (request_id) client.set_request_id(*request_id);
        if (c == hz_cmd) return topic_hz(client, topic, hz_duration);
        if (c == topics_cmd) {
          const DdsStatus st = client.status();
          fmt::print("vehicle: mission '{}' ({}), {}{}\n", st.mission, st.config_file, st.flying ? "flying" : "idle",
                     st.flying ? fmt::format(" t={:.1f} s phase {}", st.flight_time, st.phase) : "");
          for (const auto& [name, type] : st.topics) fmt::print("{:<40} {}\n", name, type);
        } else if (c == echo_cmd) {
          client.echo(topic, [&](const std::string& sample) {
            const auto f = field.empty() ? std::optional<std::string>(sample) : sample_field(sample, field);
            if (!f) throw DdsError("topic '" + topic + "' has no field '" + field + "'");
            fmt::print("{}---\n", *f);
            std::fflush(stdout);
            return !once && stop_signal() == 0;
          });
        } else if (c == param_cmd) {
          auto show = [](const DdsParam& p) {
            fmt::print("{:<34} {:<16} (default {}, {}{}) {}\n", p.name, to_string(p.value), to_string(p.default_value),
                       p.unit.empty() ? "" : p.unit + ", ", fmt::format("[{}, {}]", p.min, p.max), p.description);
          };
          if (param_list->parsed()) {
            for (const auto& p : client.param_list(param_prefix)) show(p);
          } else if (param_get->parsed()) {
            show(client.param_get(param_name));
          } else if (param_describe->parsed()) {
            fmt::print("{}", describe_param(client.param_get(param_name)));
          } else if (param_set->parsed()) {
            const ParamValue v = to_param_value(YAML::Load(param_value), "command line", param_name);
            client.param_set(param_name, v);
            fmt::print("{} = {} (applied at the vehicle's next tick)\n", param_name, to_string(v));
          } else if (param_save->parsed()) {
            fmt::print("saved: {}\n", client.param_save(file_arg, overwrite));
          }
        } else if (c == mission_cmd) {
          if (m_add->parsed()) {
            msg::Waypoint wp;
            wp.w = Eigen::Vector3d(wp_w[0], wp_w[1], wp_w[2]);
            wp.lla = wp_lla;
            wp.chi_d = wp_chi;
            wp.use_chi = wp_use_chi;
            wp.Va_d = wp_Va;
            client.mission_add(wp, wp_set_current, true);
            fmt::print("waypoint added\n");
          } else if (m_load->parsed()) {
            client.mission_load(file_arg);
            fmt::print("mission loaded: {}\n", file_arg);
          } else if (m_print->parsed()) {
            fmt::print("{}\n", client.mission_print());
          } else {
            client.mission_clear();
            fmt::print("mission cleared\n");
          }
        }
      } catch (const DdsError& e) {
        return fail(e.what());
      }
      return 0;
    }
#endif
    auto client = [&](const std::string& line) {
      const std::string reply = send_command(socket, line);
      std::puts(reply.c_str());
      return reply.rfind("ok", 0) == 0 ? 0 : 1;
    };
    if (swap_cmd->parsed()) {
      std::string p = so_path;
      if (p.find('/') != std::string::npos) p = fs::absolute(p).string();
      return client("swap " + instance + " " + p);
    }
    if (phases_cmd->parsed()) {
      std::string line = "phases";
      for (const auto& a : phase_args) line += " " + a;
      if (!fallback.empty()) line += " fallback=" + fallback;
      return client(line);
    }
    if (console_cmd->parsed()) {
      const std::string reply = send_command(socket, "console");
      if (reply.rfind("ok: ", 0) != 0) return fail(reply);
      std::printf("console: %s\n", reply.substr(4).c_str());
      return 0;
    }
    if (remote->parsed()) {
      std::string line = remote_cmd;
      for (const auto& a : remote_args) line += " " + a;
      return client(line);
    }

    HostOptions opt;
    if (replay->parsed()) {
      MissionConfig mc = load_config(config.empty() ? (fs::path(replay_dir) / "config.yaml").string() : config);
      mc.phases.clear();  // an estimator alone: no controllers, no phases, no mission
      mc.fallback.reset();
      mc.phase_params.clear();
      mc.mission = YAML::Node();
      mc.name = mc.name + "-replay";
      opt.replay_dir = fs::absolute(replay_dir);
      opt.quiet = quiet;
      if (log_dir) opt.log_dir = fs::path(*log_dir);
      Host host(std::move(mc), opt);
      host.build();
      host.set_duration(to_seconds(host.replay_end()));
      install_signal_handlers();
      const FlightResult r = host.fly();
      if (quiet) std::printf("log: %s\n", r.run_dir.c_str());
      return exit_status(r);
    }
    if (serve_cmd->parsed()) {
      if (log_dir) opt.log_dir = fs::path(*log_dir);
      opt.realtime = realtime;
      MissionConfig mc = load_config(config);
      apply_overrides(mc, overrides);
#if defined(TERN_WITH_DDS)
      DdsOptions dds_opt = parse_dds_options(mc.dds, mc.file);
      if (dds) dds_opt.enabled = true;
      dds = dds_opt.enabled;  // the config's dds: counts for --console too
      if (dds_domain) dds_opt.domain = *dds_domain;
#else
      if (dds) return fail("this tern was built without Fast DDS (install libfastrtps-dev and fastddsgen: make deps)");
#endif
      Host host(std::move(mc), opt);
      host.build();
      if (!report_missions(check_missions(host))) return 1;  // as tern fly: refused before any flight
      const auto page = open_console(host, console, realtime, dds, console_port);
#if defined(TERN_WITH_DDS)
      std::unique_ptr<DdsBridge> bridge;
      if (dds_opt.enabled) bridge = std::make_unique<DdsBridge>(host, dds_opt);
      const int rc = serve(host, socket, page ? page->url() : "");
      bridge.reset();
      return rc;
#else
      return serve(host, socket, page ? page->url() : "");
#endif
    }
    if (fly->parsed()) {
      if (config.empty()) config = default_config().string();
      opt.seed = seed;
      opt.duration = duration;
      if (log_dir) opt.log_dir = fs::path(*log_dir);
      opt.realtime = realtime;
      opt.quiet = quiet;
      opt.progress = !quiet;
    } else {
      opt.describing = true;
      opt.quiet = true;
    }
    MissionConfig mc = load_config(config);
    apply_overrides(mc, overrides);
    if (skip_preflight) {
      mc.phase_params["preflight"] = ParamSetting{YAML::Node(false), mc.file, "--skip-preflight", true, "--skip-preflight"};
      mc.overrides.push_back("--skip-preflight");
    }
    if (log_level) {
      mc.log.level = *log_level_from_name(*log_level);
      if (!mc.root["log"]) mc.root["log"] = YAML::Node(YAML::NodeType::Map);
      mc.root["log"]["level"] = *log_level;  // config.yaml records the level flown
    }
#if defined(TERN_WITH_DDS)
    DdsOptions dds_opt = parse_dds_options(mc.dds, mc.file);  // checked by `tern check` too
    if (dds) dds_opt.enabled = true;
    dds = dds_opt.enabled;  // the config's dds: counts for --console too
    if (dds_domain) dds_opt.domain = *dds_domain;
    if (dds_domain) {  // external instances (external_plugin.hpp) read the domain from dds: too
      if (!mc.dds || !mc.dds.IsMap()) mc.dds = YAML::Node(YAML::NodeType::Map);
      mc.dds["domain"] = *dds_domain;
    }
#else
    if (dds) return fail("this tern was built without Fast DDS (install libfastrtps-dev and fastddsgen: make deps)");
#endif
    if (fly->parsed() && !report_missions(check_missions(mc))) return 1;  // refused before anything flies
    Host host(std::move(mc), opt);
    host.build();
    if (check->parsed()) {
      std::fputs((dot ? host.graph_dot() : host.graph_text()).c_str(), stdout);
      std::fflush(stdout);
      const bool ok = report_missions(check_missions(host));
      if (ok && !dot) std::printf("config OK: %s\n", host.config().file.c_str());
      return ok ? 0 : 1;
    }
    if (params->parsed()) {
      fmt::print("{:<34} {:<16} {:<16} {:<8} {:<20} {}\n", "parameter", "value", "default", "unit", "range", "description");
      for (const auto& [name, p] : host.parameters())
        fmt::print("{:<34} {:<16} {:<16} {:<8} {:<20} {}\n", name, to_string(p->value()), to_string(p->default_value()), p->spec().unit,
                   range_text(*p), description_text(*p));
      return 0;
    }
    install_signal_handlers();
    const auto page = open_console(host, console, realtime, dds, console_port);
#if defined(TERN_WITH_DDS)
    std::unique_ptr<DdsBridge> bridge;
    if (dds_opt.enabled) bridge = std::make_unique<DdsBridge>(host, dds_opt);
    const FlightResult r = host.fly();
    bridge.reset();
#else
    const FlightResult r = host.fly();
#endif
    if (quiet) std::printf("log: %s\n", r.run_dir.c_str());
    return exit_status(r);
  } catch (const ConfigError& e) {
    return fail(e.what());
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}
