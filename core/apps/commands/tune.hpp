// core/apps/commands/tune.hpp: `tern tune LOOP`: a step-response test of one control loop, flown in fast
// time. The mission config gets a signal_generator instance (plugins/signal_generator) between
// the path follower and the controllers: the follower's `controller_command` output is remapped
// to `follower_command`, which the generator reads, and the generator publishes
// `controller_command` with the loop's command replaced by a square wave. The wave engages
// start_time after the first cruise phase, centred on the command then in force (roll: on wings
// level), peak to peak `amplitude`; every edge after that is one measured step, from the edge to
// the next one (step_response.hpp), on the estimator's state (what the loop closes on).
// The run directory gets tune.csv (t, command, response from the engagement on) and
// tune_steps.csv (one row per step), which `tern plot` draws as tune.png.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "config/cli_overrides.hpp"
#include "record/flight_report.hpp"
#include "commands/step_response.hpp"

namespace tern::core {

/// A loop `tern tune` can test, with its default signal. Symbols are ControllerCommand's.
struct TuneLoop {
  std::string_view name;    ///< roll, pitch, course, altitude, airspeed
  std::string_view symbol;  ///< the command: phi_c, theta_c, chi_c, h_c, Va_c
  std::string_view state;   ///< the response, a State field: phi, theta, chi, h (= -p_d), Va
  std::string_view unit;    ///< rad, m, m/s
  double amplitude;         ///< default peak-to-peak step, in unit
  double period;            ///< default period, s (two steps per period)
  bool absolute;            ///< centred on 0 (roll: wings level) instead of the command in force
};

/// The loop named `name`, or nullptr.
const TuneLoop* find_tune_loop(std::string_view name);
/// "roll, pitch, course, altitude, airspeed".
std::string tune_loop_names();

struct TuneOptions {
  std::string loop;
  std::filesystem::path config;
  std::optional<double> amplitude;  ///< loop unit (default: the loop's)
  std::optional<double> period;     ///< s
  std::optional<double> duration;   ///< flight length, s (default: 60 + 2.5 periods)
  std::optional<std::uint64_t> seed;
  std::optional<std::filesystem::path> log_dir;
  double start_time = 20.0;  ///< s after the first cruise phase
  /// --set (the gains under test), --phases, --fallback: applied to the config before the
  /// flight (cli_overrides.hpp), recorded in the run's config.yaml.
  CliOverrides overrides;
};

struct TuneStep {
  double t = 0.0;     ///< flight time of the edge, s
  double from = 0.0;  ///< command before the edge
  double to = 0.0;    ///< command after it
  StepMetrics m;
};

struct TuneResult {
  const TuneLoop* loop = nullptr;
  double amplitude = 0.0, period = 0.0, duration = 0.0;
  std::uint64_t seed = 0;
  std::vector<std::string> overrides;  ///< the options as given (--set ..., --phases ...)
  std::optional<double> engaged_s;     ///< flight time the signal engaged (nullopt: never)
  std::vector<TuneStep> steps;
  FlightResult flight;
};

/// Flies the test. Throws ConfigError for a bad loop, option or config (one line).
TuneResult run_tune(const TuneOptions& options);
/// The table `tern tune` prints.
std::string tune_report(const TuneResult& r, const std::string& config_name);

}  // namespace tern::core
