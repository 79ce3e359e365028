// core/apps/commands/tune_command.cpp: `tern tune LOOP`: a step-response test of one control loop, flown
// in fast time (tune.hpp does the work); prints the table and draws tune.png with tern-plot.

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "commands/commands.hpp"
#include "commands/tune.hpp"
#include "config/config.hpp"
#include "config/error.hpp"
#include "commands/override_options.hpp"

namespace tern::core {

namespace {

struct TuneCommand {
  CLI::App* app = nullptr;
  TuneOptions options;
  std::string seed_text;
  bool no_plot = false;
};

/// Runs `program run_dir` with its standard output discarded; true on exit status 0.
bool draw(const fs::path& program, const fs::path& run_dir) {
  const pid_t pid = ::fork();
  if (pid < 0) return false;
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) ::dup2(null, STDOUT_FILENO);
    ::execl(program.c_str(), program.c_str(), run_dir.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

void add_tune_options(CLI::App& app, TuneCommand& tc) {
  auto& o = tc.options;
  tc.app = app.add_subcommand("tune",
                              "step-response test of one control loop in fast time: rise time, overshoot, settling time, "
                              "steady-state error per step, and a plot (docs/tuning.md)");
  tc.app->add_option("loop", o.loop, "the loop: " + tune_loop_names())->required();
  tc.app->add_option("--config", o.config, "mission config (default: configs/missions/default.yaml)");
  tc.app->add_option("--amplitude", o.amplitude, "peak-to-peak step in the loop's unit (rad, m, m/s; default per loop)");
  tc.app->add_option("--period", o.period, "square-wave period, s: two steps per period (default per loop)");
  tc.app->add_option("--seed", tc.seed_text, "random seed (default: the config's)");
  tc.app->add_option("--duration", o.duration, "flight length, s (default: 60 + 2.5 periods)");
  tc.app->add_option("--log-dir", o.log_dir, "directory for the run directory (default: the config's, ./runs)");
  tc.app->add_option("--start-time", o.start_time, "s after the first cruise phase when the signal engages")->capture_default_str();
  add_override_options(tc.app, o.overrides);  // --set: the gains under test
  tc.app->add_flag("--no-plot", tc.no_plot, "do not draw the figures (tern plot)");
}

/// Runs the test, prints the table, draws tune.png with `plot_program` (tern-plot); the exit
/// status: 0 with at least one measured step. Throws ConfigError when no step was measured.
int run_command(TuneCommand& tc, const fs::path& default_config, const fs::path& plot_program) {
  auto& o = tc.options;
  if (o.config.empty()) o.config = default_config;
  if (!tc.seed_text.empty()) {
    o.seed = parse_seed(tc.seed_text);
    if (!o.seed) throw ConfigError(fmt::format("--seed '{}' is not a seed: an integer 0 .. 2^64-1", tc.seed_text));
  }
  if (o.duration) {
    const std::string why = duration_problem(*o.duration);
    if (!why.empty()) throw ConfigError("--duration: " + why);
  }
  const TuneResult r = run_tune(o);
  std::fputs(tune_report(r, o.config.filename().string()).c_str(), stdout);
  if (!r.flight.ok)
    throw ConfigError(fmt::format("the flight failed ({}{}): see {}", r.flight.end_reason,
                                  r.flight.end_detail.empty() ? "" : ": " + r.flight.end_detail, (r.flight.run_dir / "tern.log").string()));
  if (r.steps.empty())
    throw ConfigError(fmt::format("no complete step to measure in {} s (engaged at {}): try a longer --duration", r.duration,
                                  r.engaged_s ? fmt::format("t = {:.1f} s", *r.engaged_s) : "no time: no cruise phase"));
  fmt::print("log: {}\n", r.flight.run_dir.string());
  if (!tc.no_plot) {
    if (draw(plot_program, r.flight.run_dir))
      fmt::print("plot: {}\n", (r.flight.run_dir / "plots" / "tune.png").string());
    else
      std::fprintf(stderr, "tern: warning: %s %s failed: no plot\n", plot_program.c_str(), r.flight.run_dir.c_str());
  }
  return 0;
}

}  // namespace

Command add_tune_command(CLI::App& app) {
  auto tc = std::make_shared<TuneCommand>();
  add_tune_options(app, *tc);
  return {tc->app, [tc] { return run_command(*tc, default_config(), exe_dir() / "tern-plot"); }};
}

}  // namespace tern::core
