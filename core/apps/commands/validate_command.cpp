// core/apps/commands/validate_command.cpp: `tern validate LOG --aircraft FILE [--aircraft FILE2 ...]`:
// the simulator scored against a flight log (sysid/validate.hpp: the method; validate_report.hpp:
// what is printed and written). By default the estimate is tern's own: the estimator replayed over
// the log at log level sysid (commands/estimator_replay.hpp), as it must be for a real flight's
// log, which records no state at every message; a tern flight's log is treated alike (--estimate
// names a run to take it from instead, e.g. a previous validate's estimate/). Writes
// DIR/validate.json, DIR/index.html (default DIR: LOG/validate), and with --keep-estimate the
// replay's run as DIR/estimate.
// Exit status 0, or 1 with one error line (an aircraft file, no actuators table, an estimate
// never valid, no airborne window).
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands/commands.hpp"
#include "commands/estimator_replay.hpp"
#include "config/error.hpp"
#include "sysid/sysid_output.hpp"
#include "sysid/validate_report.hpp"

namespace tern::core {

namespace {

struct ValidateRequest {
  std::string log_dir;
  std::vector<std::string> aircraft;
  std::optional<std::string> out_dir;
  std::string config;    ///< the replay's estimator config (empty: estimator_replay.hpp's default)
  std::string estimate;  ///< a run whose topics/state.csv is the estimate (empty: replay the log)
  sysid::ValidateOptions options;
  bool quiet = false;
  bool keep_estimate = false;
};

/// Every aircraft file read before the replay, so that a bad file fails at once (one line).
std::vector<Aircraft> load_all(const std::vector<std::string>& files) {
  std::vector<Aircraft> out;
  for (const auto& f : files) out.push_back(load_aircraft(f));
  return out;
}

/// The estimator replayed over the log into DIR/estimate (replacing a previous one); its path.
fs::path replayed_estimate(const ValidateRequest& o, const fs::path& dir) {
  const fs::path estimate = dir / "estimate", scratch = dir / "estimate.tmp";
  fs::remove_all(estimate);
  fs::remove_all(scratch);
  EstimatorReplay req;
  req.log_dir = o.log_dir;
  req.config = o.config;
  req.out_dir = scratch.string();
  req.level = LogLevel::sysid;
  req.quiet = true;
  req.kinematic = true;  // the estimate not shaped by any file's coefficients (estimator_replay.hpp)
  req.estimate_only = true;
  const FlightResult r = replay_estimator(req);
  if (exit_status(r) != 0)
    throw ConfigError(fmt::format("{}: the estimator's replay ended with {} {}", o.log_dir, r.end_reason, r.end_detail));
  fs::rename(r.run_dir, estimate);
  fs::remove_all(scratch);
  return estimate;
}

/// Each file scored on the series loaded with its own servo lag and delays (servos.tau, delay_*);
/// the windows (and the measured channels) from the first, the same samples for all.
void score_all(sysid::ValidationRun& run, const std::vector<Aircraft>& aircraft, const std::vector<std::string>& files,
               const sysid::FlightTables& tables, const fs::path& estimate) {
  sysid::read_installation(estimate, run.series);
  for (std::size_t i = 0; i < aircraft.size(); ++i) {
    run.series.servo_tau = aircraft[i].servo_tau;
    run.series.command_delay_s = {aircraft[i].servo_delay_a, aircraft[i].servo_delay_e, aircraft[i].servo_delay_r};
    sysid::FlightSeries s = sysid::series_from_tables(tables, run.series);
    sysid::put_ground_at_zero(s, run.options.ground);  // the model's gear at the log's ground, not at its first fix
    if (i == 0) {
      run.windows = sysid::airborne_windows(s, run.options, run.log);
      run.airborne = sysid::airborne_mask(s, run.options.ground).rule;
      run.t = s.t;
      for (std::size_t c = 0; c < sysid::kChannels; ++c) run.measured[c] = s.*sysid::kChannelSpecs[c].measured;
    }
    run.files.push_back(sysid::score_aircraft(s, aircraft[i], files[i], run.windows, run.options));
  }
}

int validate(const ValidateRequest& o) {
  const std::vector<Aircraft> aircraft = load_all(o.aircraft);
  const fs::path log(o.log_dir);
  tables_from_mcap(log);  // a run directory logged as MCAP only
  sysid::check_sensor_log(log, o.estimate.empty());
  sysid::FlightTables tables = sysid::read_log_tables(log);  // read once for every file, their units checked before the replay
  const fs::path dir = o.out_dir ? fs::path(*o.out_dir) : log / "validate";
  fs::create_directories(dir);
  const fs::path estimate = o.estimate.empty() ? replayed_estimate(o, dir) : fs::path(o.estimate);
  const ReplayScratch scratch(o.estimate.empty() ? estimate : fs::path(), o.keep_estimate);
  sysid::ValidationRun run;
  run.log = o.log_dir;
  run.estimate = o.estimate.empty() ? fmt::format("tern replay of the log (its estimator, log level sysid: the state at every message), {}",
                                                  o.keep_estimate ? "kept as estimate/" : "not kept (--keep-estimate)")
                                    : "topics/state.csv of " + o.estimate + " (--estimate)";
  run.options = o.options;
  sysid::read_estimate_table(tables, estimate);
  score_all(run, aircraft, o.aircraft, tables, estimate);
  sysid::write_text_file(dir / "validate.json", sysid::validate_json(run).dump(2) + "\n");
  sysid::write_text_file(dir / "index.html", sysid::validate_html(run));
  if (!o.quiet) std::printf("%s\n", sysid::format_validate_table(run).c_str());
  std::printf("validate: %s (validate.json, index.html)\n", dir.c_str());
  return 0;
}

}  // namespace

Command add_validate_command(CLI::App& app) {
  auto o = std::make_shared<ValidateRequest>();
  auto* c = app.add_subcommand("validate",
                               "score aircraft files against a flight log: the logged commands drive the simulator open loop from the "
                               "logged state, re-initialised every window; NRMSE and Theil's U per channel, one-step residuals");
  c->add_option("log_dir", o->log_dir, "a sensor log with actuators (a flight's run directory, or tern import's output)")
      ->required()
      ->check(CLI::ExistingDirectory);
  c->add_option("--aircraft", o->aircraft, "an aircraft file to score (repeatable: the files side by side)")->required();
  c->add_option("--out", o->out_dir, "directory for validate.json, index.html and the estimate (default: LOG/validate)");
  c->add_option("--window", o->options.window_s, "seconds between re-initialisations of the simulation from the log")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  c->add_option("--min-height", o->options.ground.min_height,
                "m above the ground where the aircraft stood still for a sample to count as airborne (a log without "
                "sensor_log.yaml's airborne window)")
      ->capture_default_str();
  c->add_option("--min-airspeed", o->options.min_Va, "m/s of airspeed for a sample to count as airborne")->capture_default_str();
  c->add_option("--config", o->config,
                "mission config naming the estimator to replay (default: the log's config.yaml, else configs/replay/estimator.yaml)");
  c->add_option("--estimate", o->estimate,
                "a run directory whose topics/state.csv is the estimate at every message (e.g. a previous validate's estimate/), "
                "instead of replaying the log")
      ->check(CLI::ExistingDirectory);
  c->add_flag("--keep-estimate", o->keep_estimate,
              "keep the estimator's replay of the log as DIR/estimate (the state at every message: hundreds of MB for a long "
              "flight; --estimate DIR/estimate takes it next time)");
  c->add_flag("-q,--quiet", o->quiet, "print only where the results went");
  return {c, [o] { return validate(*o); }};
}

}  // namespace tern::core
