#include "graph/scheduler.hpp"

#include <algorithm>
#include <cerrno>
#include <bit>
#include <chrono>
#include <cmath>
#include <csignal>
#include <ctime>
#include <fstream>
#include <thread>
#if defined(__x86_64__)
#include <x86intrin.h>
#endif

#include <sys/prctl.h>

#include <fmt/format.h>

#include "config/error.hpp"
#include "graph/realtime.hpp"

namespace tern::core {

namespace {

std::int64_t thread_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// Step timing clock: the CPU's invariant TSC where there is one (a read costs about half of
// clock_gettime's), else steady_clock. Calibrated once per process against steady_clock.
struct CycleClock {
  bool tsc = false;
  double ns_per_cycle = 1.0;
  CycleClock() {
#if defined(__x86_64__)
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string line;
    bool constant = false, nonstop = false;
    while (std::getline(cpuinfo, line) && line.rfind("flags", 0) != 0) {
    }
    constant = line.find(" constant_tsc") != std::string::npos;
    nonstop = line.find(" nonstop_tsc") != std::string::npos;
    if (constant && nonstop) {
      const std::int64_t w0 = wall_ns();
      const std::uint64_t c0 = __rdtsc();
      while (wall_ns() - w0 < 2'000'000) {
      }
      const std::int64_t w1 = wall_ns();
      const std::uint64_t c1 = __rdtsc();
      if (c1 > c0) {
        tsc = true;
        ns_per_cycle = static_cast<double>(w1 - w0) / static_cast<double>(c1 - c0);
      }
    }
#endif
  }
  std::int64_t now() const {
#if defined(__x86_64__)
    if (tsc) return static_cast<std::int64_t>(__rdtsc());
#endif
    return wall_ns();
  }
  Nanos to_ns(std::int64_t cycles) const { return tsc ? static_cast<Nanos>(static_cast<double>(cycles) * ns_per_cycle) : cycles; }
};

const CycleClock& cycle_clock() {
  static const CycleClock c;
  return c;
}

}  // namespace

std::int64_t wall_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void calibrate_step_clock() { (void)cycle_clock(); }
std::int64_t step_clock_now() { return cycle_clock().now(); }
Nanos step_clock_ns(std::int64_t ticks) { return cycle_clock().to_ns(ticks); }

// ---- step statistics ------------------------------------------------------------------------

void StepStats::add(Nanos dt) {
  ++steps;
  total_ns += dt;
  max_ns = std::max(max_ns, dt);
  if (budget_ns > 0 && dt > budget_ns) ++overruns;
  // bucket = 4 log2(dt), from the bit width and the next two bits: no floating point
  const auto u = static_cast<std::uint64_t>(dt < 1 ? 1 : dt);
  const int w = std::bit_width(u);
  const std::size_t frac = w >= 3 ? static_cast<std::size_t>((u >> (w - 3)) & 3u) : 0;
  const std::size_t b = std::min<std::size_t>(histogram.size() - 1, 4 * static_cast<std::size_t>(w - 1) + frac);
  ++histogram[b];
}

Nanos StepStats::percentile(double p) const {
  if (steps == 0) return 0;
  const double target = p * static_cast<double>(steps);
  double cum = 0;
  for (std::size_t b = 0; b < histogram.size(); ++b) {
    cum += histogram[b];
    if (cum >= target) {  // upper edge of the bucket
      const std::size_t w = b / 4, frac = b % 4;
      return static_cast<Nanos>((std::uint64_t{4} + frac + 1) << w) / 4;
    }
  }
  return max_ns;
}

// ---- rates ------------------------------------------------------------------------------------

Rates resolve_rates(std::optional<double> base_rate, const YAML::Node& base_rate_node, const std::vector<const InstanceConfig*>& instances,
                    const fs::path& file) {
  double base = 0;
  if (base_rate) {
    base = *base_rate;
  } else {
    for (const auto* ic : instances)
      if (ic->rate) base = std::max(base, *ic->rate);
  }
  if (base <= 0) throw ConfigError(file.string() + ": base_rate: no instance has a rate and no base_rate is given");
  Rates out;
  try {
    out.base_period = period_from_hz(base);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(where(file, base_rate_node) + "base_rate: " + e.what());
  }
  for (const auto* ic : instances) {
    out.divisors.push_back(0);
    out.budgets.push_back(out.base_period);
    if (ic->rate) {
      const double r = *ic->rate;
      const double ratio = base / r;
      const double rounded = std::round(ratio);
      Nanos period = 0;
      try {
        period = period_from_hz(r);
      } catch (const std::invalid_argument&) {
      }
      if (r > base || rounded < 1 || std::fabs(ratio - rounded) > 1e-9 * rounded || period == 0 ||
          period != out.base_period * static_cast<Nanos>(rounded)) {
        throw ConfigError(
            where(file, ic->node["rate"]) + ic->label() +
            ".rate: " + fmt::format("{} Hz cannot be served by the base rate {} Hz", r, base) +
            fmt::format(
                " (the base rate must be a whole multiple of every rate: {} / {} = {:.4g}); use a rate that divides {} Hz or `trigger:`",
                base, r, ratio, base));
      }
      out.divisors.back() = static_cast<std::int64_t>(rounded);
      out.budgets.back() = period;
    }
    if (ic->budget_us) out.budgets.back() = static_cast<Nanos>(*ic->budget_us * 1e3);
  }
  return out;
}

// ---- the clock of a flight --------------------------------------------------------------------

Scheduler::Scheduler(Nanos base_period, Nanos end, bool realtime, double speed)
    : period_(base_period), end_(end), realtime_(realtime), speed_(speed), wall0_(wall_ns()), cpu0_(thread_cpu_ns()) {
  if (!realtime_) return;
  // a paced thread's sleeps end on time: no timer slack (Linux's default 50 us, added to every
  // wake-up of a SCHED_OTHER thread; SCHED_FIFO threads have none)
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  rt_ = std::make_unique<RealtimeStats>();
  rt_->begin(wall0_);
}

Scheduler::~Scheduler() = default;

const char* signal_end_reason(int sig) { return sig == SIGTERM ? "SIGTERM" : sig == SIGHUP ? "SIGHUP" : "SIGINT"; }

bool Scheduler::next(int stop_signal) {
  ++tick_;
  if (tick_ * period_ > end_) {
    end_reason_ = "duration";
    now_ = (tick_ - 1) * period_;
    return false;
  }
  if (stop_signal != 0) {
    end_reason_ = signal_end_reason(stop_signal);
    now_ = tick_ > 0 ? (tick_ - 1) * period_ : 0;
    return false;
  }
  now_ = tick_ * period_;
  return true;
}

void Scheduler::start_steps() { step_clock_ = cycle_clock().now(); }

Nanos Scheduler::step(Plugin& plugin, std::string& error) {
  // One clock read per step: the end of a step is the start of the next one in the same tick
  // (the few ns spent deciding that an instance is not due count towards the next step).
  const CycleClock& clock = cycle_clock();
  error.clear();
  try {
    plugin.step(now_);
  } catch (const std::exception& e) {
    error = e.what();
  } catch (...) {
    error = "unknown exception";
  }
  const std::int64_t t1 = clock.now();
  const Nanos dt = clock.to_ns(t1 - step_clock_);
  step_clock_ = t1;
  for (auto* in : plugin.inputs()) in->mark_seen();
  return dt;
}

void Scheduler::pace() {
  if (!realtime_) return;
  const std::int64_t deadline =
      wall0_ + (speed_ == 1.0 ? now_ + period_ : static_cast<std::int64_t>(std::llround(static_cast<double>(now_ + period_) / speed_)));
  if (rt_->work_done(wall_ns(), deadline)) return;  // late: no sleep
  // wall_ns() is the steady clock, CLOCK_MONOTONIC on Linux: sleep to the deadline itself
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(deadline % 1'000'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
  rt_->woke(wall_ns(), deadline);
}

double Scheduler::wall_s() const { return static_cast<double>(wall_ns() - wall0_) * 1e-9; }

double Scheduler::cpu_s() const { return static_cast<double>(thread_cpu_ns() - cpu0_) * 1e-9; }

}  // namespace tern::core
