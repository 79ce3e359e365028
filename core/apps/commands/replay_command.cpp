// core/apps/commands/replay_command.cpp: `tern replay LOG`: run the estimator over a sensor log's
// recorded sensors (docs/sensor-log.md: a tern flight log, or a real flight `tern import` wrote)
// and compare it with the recorded truth, or without truth with the log's reference and raw GNSS
// (replay/replay_source.hpp, replay/sensor_log_meta.hpp).
#include <cstdio>
#include <memory>

#include "commands/commands.hpp"
#include "commands/estimator_replay.hpp"
#include "replay/replay_report.hpp"

namespace tern::core {

namespace {

int replay(const EstimatorReplay& req) {
  const FlightResult r = replay_estimator(req);
  // The comparisons without truth (and with it): NIS per sensor, estimate vs reference and GNSS.
  const ReplayReport report = make_replay_report(r.run_dir);
  write_replay_report(report);
  if (!req.quiet) std::printf("\n%s", format_replay_table(report).c_str());
  if (req.quiet) std::printf("log: %s\n", r.run_dir.c_str());
  return exit_status(r);
}

}  // namespace

Command add_replay_command(CLI::App& app) {
  auto o = std::make_shared<EstimatorReplay>();
  auto* c = app.add_subcommand("replay",
                               "run the estimator over a sensor log (a flight log, or a real flight from tern import) and "
                               "compare it with the truth, or with the log's reference estimate and raw GNSS");
  c->add_option("log_dir", o->log_dir, "a sensor log directory (runs/<time>-<mission>, or tern import's output)")
      ->required()
      ->check(CLI::ExistingDirectory);
  c->add_option("--config", o->config,
                "mission config naming the estimator(s) to run (default: the log's config.yaml, else configs/replay/estimator.yaml)");
  c->add_option("--log-dir", o->out_dir, "directory for the replay's own run directory (default: ./runs)");
  c->add_option("--set", o->sets,
                "INSTANCE.PARAM=VALUE: an estimator parameter for this replay (VALUE in YAML); repeatable; wins over sensor_log.yaml")
      ->type_name("INSTANCE.PARAM=VALUE");
  c->add_flag("-q,--quiet", o->quiet, "print only the summary");
  return {c, [o] { return replay(*o); }};
}

}  // namespace tern::core
