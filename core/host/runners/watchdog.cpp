#include "runners/watchdog.hpp"

#include <unistd.h>

#include <chrono>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "graph/scheduler.hpp"

namespace tern::core {

void Watchdog::arm(const WatchdogConfig& budgets, StopSignal stop, Emergency emergency) {
  disarm();
  budgets_ = budgets;
  stop_ = std::move(stop);
  emergency_ = std::move(emergency);
  started_.store(0);
  stop_seen_ = 0;
  {
    std::lock_guard<std::mutex> lock(mu_);
    quit_ = false;
  }
  thread_ = std::thread([this] { run(); });
}

void Watchdog::disarm() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mu_);
    quit_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void Watchdog::enter(const std::string& name, Nanos now, bool policed, std::int64_t started) {
  name_ = &name;
  step_now_ = now;
  policed_.store(policed, std::memory_order_relaxed);
  started_.store(started, std::memory_order_release);
}

void Watchdog::leave(StepStats& stats, Nanos dt, spdlog::logger& log) {
  std::int64_t s = started_.load(std::memory_order_relaxed);
  if (s < 0 || !started_.compare_exchange_strong(s, 0)) {
    for (;;) ::pause();  // the watchdog thread owns the flight's end and will _exit the process
  }
  if (dt <= static_cast<Nanos>(budgets_.soft_ms * 1e6)) return;
  if (stats.slow++ == 0)
    log.warn(
        "t={:.3f} s: {}: a step took {:.1f} ms of wall time, over the watchdog's soft budget of {} ms (watchdog.soft_ms); "
        "all are counted in timing.json (watchdog_slow_steps) and the console summary",
        to_seconds(step_now_), *name_, static_cast<double>(dt) * 1e-6, budgets_.soft_ms);
}

std::string Watchdog::verdict(std::int64_t started, std::string& reason) {
  const std::int64_t ticks = step_clock_now();
  const double ran_ms = static_cast<double>(step_clock_ns(ticks - started)) * 1e-6;
  const std::int64_t now = wall_ns();
  if (policed_.load(std::memory_order_relaxed) && ran_ms > budgets_.hard_ms) {
    reason = "watchdog";
    return fmt::format(
        "{} at t={:.3f} s: a step still running after {:.0f} ms of wall time, past the watchdog's hard budget of {} ms "
        "(watchdog.hard_ms); the process ends without stopping the plugins",
        *name_, to_seconds(step_now_), ran_ms, budgets_.hard_ms);
  }
  const int sig = stop_ ? stop_() : 0;
  if (sig == 0) return "";
  if (stop_seen_ == 0) stop_seen_ = now;
  if ((now - stop_seen_) * 1e-6 < kStopGraceMs || ran_ms < kStopGraceMs) return "";
  reason = signal_end_reason(sig);
  return fmt::format("{} at t={:.3f} s: stuck in a step for {:.0f} ms when {} came; the process ends without stopping the plugins", *name_,
                     to_seconds(step_now_), ran_ms, reason);
}

void Watchdog::run() {
  std::unique_lock<std::mutex> lock(mu_);
  while (!cv_.wait_for(lock, std::chrono::milliseconds(kTickMs), [this] { return quit_; })) {
    std::int64_t s = started_.load(std::memory_order_acquire);
    if (s <= 0) continue;
    std::string reason;
    const std::string detail = verdict(s, reason);
    if (detail.empty() || !started_.compare_exchange_strong(s, -1)) continue;
    lock.unlock();
    emergency_(reason, detail, *name_);  // does not return
    return;
  }
}

}  // namespace tern::core
