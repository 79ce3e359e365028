// core/apps/commands/replay_command.cpp: `tern replay LOG`: run the estimator over a sensor log's
// recorded sensors (docs/sensor-log.md: a tern flight log, or a real flight `tern import` wrote)
// and compare it with the recorded truth, or without truth with the log's reference and raw GNSS
// (replay/replay_source.hpp, replay/sensor_log_meta.hpp).
#include <cstdio>
#include <memory>

#include "commands/commands.hpp"
#include "config/cli_overrides.hpp"
#include "flight/host.hpp"
#include "replay/replay_report.hpp"
#include "replay/replay_source.hpp"
#include "export/mcap_csv_export.hpp"
#include "replay/sensor_log_meta.hpp"

namespace tern::core {

namespace {

struct ReplayOptions {
  std::string log_dir;
  std::string config;  ///< empty: the log's config.yaml, else configs/replay/estimator.yaml
  std::optional<std::string> out_dir;
  std::vector<std::string> sets;
  bool quiet = false;
};

/// The replay's mission config: --config, the flight's own config.yaml, or (a real flight's log)
/// the shipped estimator-only config beside the default mission.
fs::path replay_config(const ReplayOptions& o) {
  if (!o.config.empty()) return o.config;
  const fs::path own = fs::path(o.log_dir) / "config.yaml";
  if (fs::exists(own)) return own;
  return default_config().parent_path().parent_path() / "replay" / "estimator.yaml";
}

/// A flight logged as MCAP only (log.format mcap): its tables exported into LOG/topics first, as
/// `tern export csv LOG` writes them (export/mcap_csv_export.hpp), which the replay then reads.
void tables_from_mcap(const fs::path& log_dir) {
  const fs::path mcap = log_dir / "flight.mcap";
  if (fs::exists(log_dir / "topics") || !fs::exists(mcap)) return;
  const CsvExportReport r = export_csv(mcap, log_dir / "topics");
  std::fprintf(stderr, "replay: %zu topic tables exported from %s into topics/ (tern export csv)%s\n", r.rows.size(), mcap.c_str(),
               r.stopped.empty() ? "" : (": the file stops early, " + r.stopped).c_str());
}

int replay(const ReplayOptions& o) {
  tables_from_mcap(o.log_dir);
  MissionConfig mc = load_config(replay_config(o).string());
  mc.phases.clear();  // an estimator alone: no controllers, no phases, no mission
  mc.fallback.reset();
  mc.phase_params.clear();
  mc.mission = YAML::Node();
  // a real flight's log (no config.yaml of its own) is named after its directory
  if (o.config.empty() && !fs::exists(fs::path(o.log_dir) / "config.yaml"))
    mc.name = fs::absolute(o.log_dir).lexically_normal().filename().string();
  mc.name = mc.name + "-replay";
  if (mc.log.format == LogFormat::mcap) mc.log.format = LogFormat::both;  // the replay report reads the tables
  apply_sensor_log_settings(mc, read_sensor_log_settings(o.log_dir));
  CliOverrides cli;
  cli.sets = o.sets;
  apply_overrides(mc, cli);
  HostOptions opt;
  opt.replay = replay_source(fs::absolute(o.log_dir));
  opt.quiet = o.quiet;
  if (o.out_dir) opt.log_dir = fs::path(*o.out_dir);
  Host host(std::move(mc), opt);
  host.build();
  host.set_duration(to_seconds(host.replay_end()));
  install_signal_handlers();
  const FlightResult r = host.fly();
  const fs::path meta = fs::path(o.log_dir) / "sensor_log.yaml";
  if (fs::exists(meta)) fs::copy_file(meta, fs::path(r.run_dir) / "sensor_log.yaml", fs::copy_options::overwrite_existing);
  // The comparisons without truth (and with it): NIS per sensor, estimate vs reference and GNSS.
  const ReplayReport report = make_replay_report(r.run_dir);
  write_replay_report(report);
  if (!o.quiet) std::printf("\n%s", format_replay_table(report).c_str());
  if (o.quiet) std::printf("log: %s\n", r.run_dir.c_str());
  return exit_status(r);
}

}  // namespace

Command add_replay_command(CLI::App& app) {
  auto o = std::make_shared<ReplayOptions>();
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
