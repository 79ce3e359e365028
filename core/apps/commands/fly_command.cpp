// core/apps/commands/fly_command.cpp: `tern fly [CONFIG]`: fly a mission (default:
// configs/missions/default.yaml) and write its flight log.
#include <cstdio>
#include <memory>

#include "commands/commands.hpp"
#include "commands/fleet_command.hpp"
#include "commands/fly_mission.hpp"
#include "commands/host_preparation.hpp"

namespace tern::core {

namespace {

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

struct FlyOptions {
  std::string config;
  std::optional<std::uint64_t> seed;
  std::optional<double> duration;
  std::optional<std::string> log_dir;
  bool realtime = false, quiet = false;
  std::string console_vehicle;  ///< a multi-vehicle mission's vehicle the console follows
  RealtimeOptions rt;
  HostPreparation prep;
};

int fly(const FlyOptions& o) {
  if (!o.config.empty() && is_fleet_file(o.config)) {
    FleetFlyOptions f{{o.seed, o.duration, o.log_dir ? std::optional<fs::path>(*o.log_dir) : std::nullopt, o.quiet, false, o.realtime},
                      o.prep,
                      o.console_vehicle};
    return fly_fleet(o.config, f);
  }
  HostOptions opt;
  opt.seed = o.seed;
  opt.duration = o.duration;
  if (o.log_dir) opt.log_dir = fs::path(*o.log_dir);
  opt.realtime = o.realtime;
  opt.rt = o.rt;
  opt.quiet = o.quiet;
  opt.progress = !o.quiet;
  const std::optional<FlightResult> r = fly_mission(o.config.empty() ? default_config().string() : o.config, o.prep, opt, true);
  if (!r) return 1;
  if (o.quiet) std::printf("log: %s\n", r->run_dir.c_str());
  return exit_status(*r);
}

}  // namespace

Command add_fly_command(CLI::App& app) {
  auto o = std::make_shared<FlyOptions>();
  auto* c = app.add_subcommand("fly", "fly a mission (default: configs/missions/default.yaml) and write its flight log");
  c->add_option("config", o->config, "mission config (YAML)");
  c->add_option("--seed", o->seed, "random seed (overrides the config's seed)")->check(kSeedCheck);
  c->add_option("--duration", o->duration, "flight length in seconds (overrides the config)")->check(kDurationCheck);
  add_realtime_options(c, o->realtime, o->rt, "pace the simulated clock to wall time (the real-time figures: docs/companion-computer.md)");
  add_console_options(c, o->prep);
  add_gcs_options(c, o->prep);
  c->add_option(
      "--console-vehicle", o->console_vehicle,
      "a multi-vehicle mission: the vehicle the console follows (default the first; the console draws the others on its track; --gcs "
      "serves every vehicle, each with its MAVLink system id)");
  add_skip_preflight_option(c, o->prep);
  c->add_option("--log-dir", o->log_dir, "directory for the run directory (default: the config's log.dir, else ./runs)");
  add_log_level_option(c, o->prep);
  c->add_flag("-q,--quiet", o->quiet, "print only warnings, errors and where the log went");
  add_dds_options(c, o->prep);
  add_mission_override_options(c, o->prep);
  return {c, [o] { return fly(*o); }};
}

}  // namespace tern::core
