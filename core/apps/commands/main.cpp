// tern: the command line. `tern --help` lists the commands; every command has --help. main()
// dispatches: an extension command (`tern aero` runs tern-aero beside this binary), else the
// one parsed of the commands in commands.hpp (one file each).
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "commands/commands.hpp"
#if defined(TERN_WITH_DDS)
#include "dds_bridge.hpp"  // register_dds_mcap_channels
#include "external_link_dds.hpp"
#endif

namespace fs = std::filesystem;
using namespace tern::core;

namespace {

/// git-style extension commands: `tern aero ...` runs `tern-aero ...` from the same directory.
/// Returns only when there is none to run (or it could not be run: then the exit status in `rc`).
bool run_extension(int argc, char** argv, int& rc) {
  if (argc < 2 || argv[1][0] == '-') return false;
  const std::string sub = argv[1];
  static const std::set<std::string> builtin = {"fly",  "check", "plugins", "params",  "serve",  "swap",   "phases", "remote",  "topics",
                                                "echo", "hz",    "param",   "mission", "replay", "import", "tune",   "console", "help"};
  if (builtin.count(sub)) return false;
  const fs::path ext = exe_dir() / ("tern-" + sub);
  if (!fs::exists(ext)) return false;
  std::vector<char*> args;
  std::string prog = ext.string();
  args.push_back(prog.data());
  for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  execv(prog.c_str(), args.data());
  rc = fail(fmt::format("cannot run {}: {}", prog, std::strerror(errno)));
  return true;
}

/// Every command, in the order of `tern --help`.
std::vector<Command> add_commands(CLI::App& app) {
  std::vector<Command> all;
  for (auto* add : {add_fly_command, add_check_command, add_plugins_command, add_replay_command, add_import_command, add_sysid_command,
                    add_validate_command, add_export_command, add_tune_command, add_params_command, add_serve_command})
    all.push_back(add(app));
  for (auto& c : add_control_commands(app)) all.push_back(std::move(c));
#if defined(TERN_WITH_DDS)
  for (auto& c : add_vehicle_commands(app)) all.push_back(std::move(c));
  all.push_back(add_dds_command(app));
#endif
  return all;
}

}  // namespace

int main(int argc, char** argv) {
  if (int rc = 0; run_extension(argc, argv, rc)) return rc;
#if defined(TERN_WITH_DDS)
  register_dds_external_links();  // `plugin: external` instances (external_plugin.hpp)
  register_dds_mcap_channels();   // the MCAP log's ROS-typed channels (core/formats/ros/ros_channels.hpp)
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
  const std::vector<Command> commands = add_commands(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    for (const Command& c : commands)
      if (c.app->parsed()) return c.run();
    return 1;  // unreachable: require_subcommand(1)
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}
