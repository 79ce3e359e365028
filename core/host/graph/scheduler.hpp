// core/host/graph/scheduler.hpp: the schedule of a flight: ticks, rates, triggers, step times, pacing.
//
// One thread, one clock: tick k happens at flight time t = k * base_period (integer ns), from
// t = 0 to the flight's end, inclusive. The base rate is the config's `base_rate`, else the
// fastest instance rate; every instance rate r must divide it, and the instance steps in the
// ticks where k % (base / r) == 0 (its divisor). A triggered instance steps in the tick where
// its trigger input received a message. Within a tick, instances step in the port graph's
// order (port_graph.hpp); the scheduler decides whether one is due and times its step.
// Step times are wall clock (the CPU's invariant TSC where there is one, else steady_clock)
// and never reach the deterministic log: timing.json and the console summary only. A step
// longer than its budget (the instance's period; `budget_us` in the config) is an overrun.
// With `realtime` the flight is paced: tick k does not end before (k + 1) * base_period / speed
// of wall time after the first tick (speed 1: real time).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "config/config.hpp"
#include "tern/plugin.hpp"

namespace tern::core {

/// Steady clock, ns since an arbitrary epoch: wall-clock measurements only, never flight time.
std::int64_t wall_ns();
/// The end reason of a flight stopped by signal `sig`: "SIGTERM", "SIGHUP", else "SIGINT".
const char* signal_end_reason(int sig);
/// Calibrates the step-timing clock (once per process, about 2 ms); call before timing anything.
void calibrate_step_clock();
/// The step-timing clock: the CPU's invariant time-stamp counter where it has one (constant and
/// nonstop TSC), else wall_ns(); a read costs a few ns against clock_gettime's tens. Ticks, to
/// be differenced and turned into ns by step_clock_ns().
std::int64_t step_clock_now();
/// A difference of step_clock_now() ticks in ns.
Nanos step_clock_ns(std::int64_t ticks);

/// Step-time statistics of one instance (wall clock; not part of the deterministic log).
struct StepStats {
  std::uint64_t steps = 0;
  std::uint64_t overruns = 0;  ///< steps longer than budget_ns
  std::uint64_t slow = 0;      ///< steps longer than the watchdog's soft budget (watchdog.hpp)
  Nanos budget_ns = 0;
  Nanos max_ns = 0;
  Nanos total_ns = 0;
  std::array<std::uint32_t, 96> histogram{};  ///< log-spaced buckets (ratio 2^(1/4)) from 1 ns
  void add(Nanos dt);
  Nanos percentile(double p) const;  ///< approximate (bucket upper bound), 0 when no steps
};

/// The tick period and how each instance is served at it.
struct Rates {
  Nanos base_period = 0;               ///< ns
  std::vector<std::int64_t> divisors;  ///< per instance: steps every divisor-th tick (0: triggered)
  std::vector<Nanos> budgets;          ///< per instance: step-time budget, ns
};

/// The base period and every instance's divisor and budget, from the config's `base_rate`
/// (`base_rate_node`: where it is written, for errors) and the instances' `rate:`, `budget_us`.
/// Throws ConfigError naming the field when a rate does not divide the base rate, or when no
/// rate is given anywhere.
Rates resolve_rates(std::optional<double> base_rate, const YAML::Node& base_rate_node, const std::vector<const InstanceConfig*>& instances,
                    const fs::path& file);

/// What the clock of a paced flight measured (defined in realtime.hpp).
class RealtimeStats;

/// The clock of one flight.
class Scheduler {
 public:
  /// Ticks every `base_period` from t = 0 to `end` (ns, inclusive); `realtime`: paced to wall
  /// time, flight time running `speed` (> 0) times as fast. Starts the wall and CPU stopwatches.
  Scheduler(Nanos base_period, Nanos end, bool realtime, double speed = 1.0);
  ~Scheduler();

  /// Starts the next tick. False when the flight is over: past its end (end_reason()
  /// "duration") or stopped by a signal (`stop_signal`, 0 for none: "SIGINT", "SIGTERM" or "SIGHUP");
  /// now() is then the last tick flown.
  bool next(int stop_signal);
  std::int64_t tick() const { return tick_; }
  Nanos now() const { return now_; }
  const std::string& end_reason() const { return end_reason_; }

  /// Whether an instance steps in this tick: its `trigger` input has news, or (without one) the
  /// tick is a multiple of its `divisor`.
  bool due(std::int64_t divisor, const InputBase* trigger) const { return trigger ? trigger->updated() : tick_ % divisor == 0; }
  /// Marks the start of this tick's steps (for the first step's time).
  void start_steps();
  /// Steps `plugin` at now() and marks its inputs seen; `error` gets what it threw ("" if
  /// nothing). Returns the step's duration, ns, for the caller to add to the instance's StepStats
  /// once the watchdog has let the step go (Watchdog::leave, watchdog.hpp): a step the watchdog
  /// gave up on must not write them while the watchdog thread writes the flight's end from them.
  Nanos step(Plugin& plugin, std::string& error);

  /// Every 64th tick, or every tick when paced: time to look at the wall clock (flush the log,
  /// redraw the status line, pace).
  bool wall_check_due() const { return (tick_ & 63) == 0 || realtime_; }
  /// Paced flights: waits until this tick's end in wall time (clock_nanosleep, absolute), and
  /// measures the tick (realtime.hpp). Otherwise returns at once.
  void pace();
  /// A paced flight's figures (realtime.hpp); nullptr for an unpaced one.
  RealtimeStats* realtime_stats() { return rt_.get(); }

  /// step_clock_now() where the next step starts: the end of the previous one of this tick, or
  /// start_steps() (the watchdog's start of a step without a clock read of its own).
  std::int64_t step_start_ticks() const { return step_clock_; }
  std::int64_t wall_start() const { return wall0_; }  ///< wall_ns() at construction
  double wall_s() const;                              ///< wall time since construction, s
  double cpu_s() const;                               ///< CPU time of this thread since construction, s

 private:
  Nanos period_, end_;
  bool realtime_;
  double speed_;  ///< flight time per wall time when realtime_
  std::int64_t tick_ = -1;
  Nanos now_ = 0;
  std::string end_reason_;
  std::int64_t step_clock_ = 0;  // cycle clock at the end of the previous step of this tick
  std::int64_t wall0_, cpu0_;
  std::unique_ptr<RealtimeStats> rt_;  // paced flights only
};

}  // namespace tern::core
