// tern: the command line. `tern --help` lists the commands; every command has --help.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "error.hpp"
#include "host.hpp"
#include "loader.hpp"
#include "serve.hpp"
#if defined(TERN_WITH_DDS)
#include "dds_bridge.hpp"
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

std::string range_text(const ParamBase& p) {
  const auto& s = p.spec();
  if (p.kind() == ParamKind::text) return s.choices.empty() ? (s.is_path ? "path" : "") : fmt::format("{}", fmt::join(s.choices, "|"));
  if (p.kind() == ParamKind::boolean) return "";
  return fmt::format("[{}, {}]{}", s.min, s.max, s.size ? fmt::format(" x{}", s.size) : "");
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
        fmt::print("  in  {:<22} {:<26} {}{}\n", in->name(), in->type().name, in->description(), in->need() == Need::optional ? " (optional)" : "");
      for (auto* out : p->outputs()) fmt::print("  out {:<22} {:<26} {}\n", out->name(), out->type().name, out->description());
      for (auto* prm : p->params())
        fmt::print("  param {:<20} = {:<14} {:<8} {:<18} {}\n", prm->name(), to_string(prm->value()), prm->spec().unit, range_text(*prm),
                   prm->spec().description);
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
    static const std::set<std::string> builtin = {"fly", "check", "plugins", "params", "serve", "swap", "phases", "remote", "help"};
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

  CLI::App app{"tern: a fixed-wing autopilot framework for research.\n"
               "Flies plugins named in a YAML mission config, in the simulator or on an aircraft."};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "help for every command");
  app.footer("More commands: tern plot RUN_DIR (figures of a flight), tern aero (aircraft models, trim),\n"
             "tern new-plugin NAME --kind KIND (a plugin project from a template), tern fcu (FCU parameters).");

  std::string config;
  std::optional<std::uint64_t> seed;
  std::optional<double> duration;
  std::optional<std::string> log_dir;
  bool realtime = false, quiet = false, dot = false, dds = false;
  std::optional<std::uint32_t> dds_domain;
  std::vector<std::string> plugin_dirs;

  auto* fly = app.add_subcommand("fly", "fly a mission (default: configs/missions/default.yaml) and write its flight log");
  fly->add_option("config", config, "mission config (YAML)");
  fly->add_option("--seed", seed, "random seed (overrides the config's seed)");
  fly->add_option("--duration", duration, "flight length in seconds (overrides the config)")->check(CLI::PositiveNumber);
  fly->add_flag("--realtime", realtime, "pace the simulated clock to wall time");
  fly->add_option("--log-dir", log_dir, "directory for the run directory (default: the config's log.dir, else ./runs)");
  fly->add_flag("-q,--quiet", quiet, "print only warnings, errors and where the log went");
  fly->add_flag("--dds", dds, "bridge telemetry, parameters and mission edits to Fast DDS (loopback unless the config's dds: names interfaces)");
  fly->add_option("--dds-domain", dds_domain, "DDS domain id (overrides the config's dds.domain)")->check(CLI::Range(0, 232));

  auto* check = app.add_subcommand("check", "validate a mission config without flying and print its port graph");
  check->add_option("config", config, "mission config (YAML)")->required();
  check->add_flag("--dot", dot, "print the port graph as Graphviz instead of text");

  auto* plugins = app.add_subcommand("plugins", "list the plugins in the search path, with their ports and parameters");
  plugins->add_option("--path", plugin_dirs, "extra plugin directories to search first");

  auto* params = app.add_subcommand("params", "list every parameter of a mission: value, default, unit, range, description");
  params->add_option("config", config, "mission config (YAML)")->required();

  std::string socket = default_socket().string();
  std::string instance, so_path, fallback, remote_cmd;
  std::vector<std::string> phase_args, remote_args;
  auto* serve_cmd = app.add_subcommand("serve", "keep a host alive across flights; control it with swap, phases and remote");
  serve_cmd->add_option("config", config, "mission config (YAML)")->required();
  serve_cmd->add_option("--socket", socket, "control socket")->capture_default_str();
  serve_cmd->add_option("--log-dir", log_dir, "directory for the run directories");
  serve_cmd->add_flag("--realtime", realtime, "pace each flight to wall time");
  serve_cmd->add_flag("--dds", dds, "bridge telemetry, parameters and mission edits to Fast DDS");
  serve_cmd->add_option("--dds-domain", dds_domain, "DDS domain id (overrides the config's dds.domain)")->check(CLI::Range(0, 232));
  auto* swap_cmd = app.add_subcommand("swap", "between flights of `tern serve`: replace an instance's plugin with another .so");
  swap_cmd->add_option("instance", instance, "instance name in the mission config")->required();
  swap_cmd->add_option("path", so_path, "the new plugin: a path to a .so, or a plugin name")->required();
  swap_cmd->add_option("--socket", socket, "control socket of the server")->capture_default_str();
  auto* phases_cmd = app.add_subcommand("phases", "between flights of `tern serve`: set the phase -> controller table");
  phases_cmd->add_option("table", phase_args, "PHASE=INSTANCE ... (takeoff, climb, cruise required)")->required();
  phases_cmd->add_option("--fallback", fallback, "controller used if the active one fails");
  phases_cmd->add_option("--socket", socket, "control socket of the server")->capture_default_str();
  auto* remote = app.add_subcommand("remote", "send a command to `tern serve`: fly [SECONDS], status, quit");
  remote->add_option("command", remote_cmd, "fly, status or quit")->required()->check(CLI::IsMember({"fly", "status", "quit"}));
  remote->add_option("args", remote_args, "fly: flight length in seconds");
  remote->add_option("--socket", socket, "control socket of the server")->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    if (plugins->parsed()) return cmd_plugins(plugin_dirs);
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
    if (remote->parsed()) {
      std::string line = remote_cmd;
      for (const auto& a : remote_args) line += " " + a;
      return client(line);
    }

    HostOptions opt;
    if (serve_cmd->parsed()) {
      if (log_dir) opt.log_dir = fs::path(*log_dir);
      opt.realtime = realtime;
      MissionConfig mc = load_config(config);
#if defined(TERN_WITH_DDS)
      DdsOptions dds_opt = parse_dds_options(mc.dds, mc.file);
      if (dds) dds_opt.enabled = true;
      if (dds_domain) dds_opt.domain = *dds_domain;
#else
      if (dds) return fail("this tern was built without Fast DDS (install libfastrtps-dev and fastddsgen: make deps)");
#endif
      Host host(std::move(mc), opt);
      host.build();
#if defined(TERN_WITH_DDS)
      std::unique_ptr<DdsBridge> bridge;
      if (dds_opt.enabled) bridge = std::make_unique<DdsBridge>(host, dds_opt);
      const int rc = serve(host, socket);
      bridge.reset();
      return rc;
#else
      return serve(host, socket);
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
#if defined(TERN_WITH_DDS)
    DdsOptions dds_opt = parse_dds_options(mc.dds, mc.file);  // checked by `tern check` too
    if (dds) dds_opt.enabled = true;
    if (dds_domain) dds_opt.domain = *dds_domain;
#else
    if (dds) return fail("this tern was built without Fast DDS (install libfastrtps-dev and fastddsgen: make deps)");
#endif
    Host host(std::move(mc), opt);
    host.build();
    if (check->parsed()) {
      if (dot) {
        std::fputs(host.graph_dot().c_str(), stdout);
      } else {
        std::fputs(host.graph_text().c_str(), stdout);
        std::printf("config OK: %s\n", host.config().file.c_str());
      }
      return 0;
    }
    if (params->parsed()) {
      fmt::print("{:<34} {:<16} {:<16} {:<8} {:<20} {}\n", "parameter", "value", "default", "unit", "range", "description");
      for (const auto& [name, p] : host.parameters())
        fmt::print("{:<34} {:<16} {:<16} {:<8} {:<20} {}\n", name, to_string(p->value()), to_string(p->default_value()), p->spec().unit,
                   range_text(*p), p->spec().description);
      return 0;
    }
    install_signal_handlers();
#if defined(TERN_WITH_DDS)
    std::unique_ptr<DdsBridge> bridge;
    if (dds_opt.enabled) bridge = std::make_unique<DdsBridge>(host, dds_opt);
    const FlightResult r = host.fly();
    bridge.reset();
#else
    const FlightResult r = host.fly();
#endif
    if (quiet) std::printf("log: %s\n", r.run_dir.c_str());
    if (!r.ok) return 1;
    if (r.end_reason == "SIGINT") return 130;
    if (r.end_reason == "SIGTERM") return 143;
    return 0;
  } catch (const ConfigError& e) {
    return fail(e.what());
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}
