// core/src/commands/replay_command.cpp: `tern replay RUN_DIR`: run the estimator over a flight
// log's recorded sensors and compare it with the recorded truth (flight/replay.hpp).
#include <cstdio>
#include <memory>

#include "commands/commands.hpp"
#include "flight/host.hpp"

namespace tern::core {

namespace {

struct ReplayOptions {
  std::string run_dir;
  std::string config;  ///< empty: the run's config.yaml
  std::optional<std::string> log_dir;
  bool quiet = false;
};

int replay(const ReplayOptions& o) {
  MissionConfig mc = load_config(o.config.empty() ? (fs::path(o.run_dir) / "config.yaml").string() : o.config);
  mc.phases.clear();  // an estimator alone: no controllers, no phases, no mission
  mc.fallback.reset();
  mc.phase_params.clear();
  mc.mission = YAML::Node();
  mc.name = mc.name + "-replay";
  HostOptions opt;
  opt.replay_dir = fs::absolute(o.run_dir);
  opt.quiet = o.quiet;
  if (o.log_dir) opt.log_dir = fs::path(*o.log_dir);
  Host host(std::move(mc), opt);
  host.build();
  host.set_duration(to_seconds(host.replay_end()));
  install_signal_handlers();
  const FlightResult r = host.fly();
  if (o.quiet) std::printf("log: %s\n", r.run_dir.c_str());
  return exit_status(r);
}

}  // namespace

Command add_replay_command(CLI::App& app) {
  auto o = std::make_shared<ReplayOptions>();
  auto* c = app.add_subcommand("replay", "run the estimator over a flight log's recorded sensors and compare it with the recorded truth");
  c->add_option("run_dir", o->run_dir, "a flight log directory (runs/<time>-<mission>)")->required()->check(CLI::ExistingDirectory);
  c->add_option("--config", o->config, "mission config naming the estimator(s) to run (default: the run's config.yaml)");
  c->add_option("--log-dir", o->log_dir, "directory for the replay's own run directory (default: ./runs)");
  c->add_flag("-q,--quiet", o->quiet, "print only the summary");
  return {c, [o] { return replay(*o); }};
}

}  // namespace tern::core
