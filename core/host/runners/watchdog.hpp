// core/host/runners/watchdog.hpp: wall-time budgets of plugin steps, and a way out of a flight whose
// thread is stuck in a plugin.
//
// The flight thread brackets every step with enter()/leave(). Budgets (`watchdog:` in the
// mission config, WatchdogConfig in config.hpp: soft 50 ms, hard 2000 ms by default):
//   soft   a step longer than soft_ms is counted (StepStats::slow: timing.json's instance
//          `watchdog_slow_steps` and the console summary; not summary.json, which stays a
//          function of config and seed) and reported with one warning per instance and flight;
//          decided on the flight thread when the step returns.
//   hard   a step of an in-process instance still running after hard_ms: the flight ends.
//          Decided by the watchdog's own thread (it wakes every kTickMs ms), since the flight
//          thread never comes back. An isolated instance polices its own calls (its child is
//          killed past hard_ms, isolated_plugin.hpp), so enter(.., policed = false).
//   stop   SIGINT, SIGTERM or SIGHUP while a step has run for kStopGraceMs: the flight ends
//          with that signal as its reason, instead of waiting for a step that may never end.
// Ending a flight from the watchdog thread: the thread claims the flight (an atomic exchange
// that the flight thread's leave() sees: if the step ever returns, the flight thread parks
// for good), then calls the host's Emergency handler, which writes the log's end (tern.log's
// line naming the instance, summary.json atomically, closes the topic files) and ends the
// process with _exit: a thread cannot be cancelled safely in the middle of foreign code, so
// the process cannot return to its caller. That is why a host that flies (`tern fly`,
// `tern serve`) exits when a plugin hangs, with exit status 1 (hard budget) or the signal's.
// The plugins' stop() is not called in that case.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include <spdlog/fwd.h>

#include "config/config.hpp"
#include "graph/scheduler.hpp"
#include "tern/time.hpp"

namespace tern::core {

class Watchdog {
 public:
  /// Runs on the watchdog thread with the end reason ("watchdog" or "SIGINT"/"SIGTERM"/"SIGHUP"),
  /// a detail naming the instance, and the instance whose step is still running (the handler
  /// must not read that instance's state: its step may write it at any moment); must not return
  /// (it ends the process).
  using Emergency = std::function<void(const std::string& reason, const std::string& detail, const std::string& running)>;
  /// Reads the pending stop signal (0: none).
  using StopSignal = std::function<int()>;

  static constexpr int kTickMs = 10;
  static constexpr int kStopGraceMs = 500;

  Watchdog() = default;
  ~Watchdog() { disarm(); }
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

  /// For one flight: budgets, the emergency handler, the thread.
  void arm(const WatchdogConfig& budgets, StopSignal stop, Emergency emergency);
  /// Ends the thread (the flight is over); idempotent.
  void disarm();

  /// The flight thread starts a step of the instance `name` (which outlives the step) at flight
  /// time `now`; `started`: step_clock_now() at the step's start (the flight loop passes
  /// Scheduler::step_start_ticks(), a read it already made); `policed`: the hard budget applies
  /// (false for isolated instances).
  void enter(const std::string& name, Nanos now, bool policed, std::int64_t started);
  /// The step returned after `dt` ns of wall time: counts a slow step in `stats.slow` and warns
  /// (at the first) on `log`. Never returns if the watchdog has claimed the flight.
  void leave(StepStats& stats, Nanos dt, spdlog::logger& log);

 private:
  void run();
  /// Why the current step must end the flight now ("" if it need not): sets `reason`.
  std::string verdict(std::int64_t started, std::string& reason);

  WatchdogConfig budgets_;
  StopSignal stop_;
  Emergency emergency_;
  std::atomic<std::int64_t> started_{0};  // step_clock_now() at the running step's start; 0: none; -1: claimed
  std::atomic<bool> policed_{false};
  const std::string* name_ = nullptr;  // written before started_ (release), read after it (acquire)
  Nanos step_now_ = 0;
  std::int64_t stop_seen_ = 0;  // wall_ns() when the watchdog first saw a stop signal
  std::thread thread_;
  std::mutex mu_;
  std::condition_variable cv_;
  bool quit_ = false;
};

}  // namespace tern::core
