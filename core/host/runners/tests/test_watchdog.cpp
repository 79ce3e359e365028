// Watchdog alone, on this thread as the flight thread: a step stuck past the hard budget calls
// the emergency handler from the watchdog's thread, naming the instance; an isolated instance's
// step (not policed) never does; a stop signal ends a stuck step after the grace time; a slow
// step that returns is counted and warned about once per flight; a quick one is not.
#include <doctest/doctest.h>

#include <chrono>
#include <csignal>
#include <future>
#include <memory>
#include <sstream>
#include <string>
#include <thread>

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include "runners/watchdog.hpp"

using namespace tern;
using namespace tern::core;
using namespace std::chrono_literals;

namespace {

struct Emergency {
  std::string reason, detail, running;
};

/// Arms `w` with soft/hard budgets (ms) and a stop signal read from `sig`; the emergency
/// handler fulfils the returned future (and returns, which the watchdog's thread allows: it
/// then ends).
std::future<Emergency> arm(Watchdog& w, double soft_ms, double hard_ms, const std::atomic<int>& sig) {
  auto done = std::make_shared<std::promise<Emergency>>();
  WatchdogConfig budgets;
  budgets.soft_ms = soft_ms;
  budgets.hard_ms = hard_ms;
  w.arm(
      budgets, [&sig] { return sig.load(); },
      [done](const std::string& reason, const std::string& detail, const std::string& running) {
        done->set_value({reason, detail, running});
      });
  return done->get_future();
}

struct TextLog {
  std::ostringstream text;
  spdlog::logger log{"host", std::make_shared<spdlog::sinks::ostream_sink_st>(text)};
};

}  // namespace

TEST_CASE("watchdog: a policed step stuck past hard_ms ends the flight from the watchdog's thread, naming the instance") {
  Watchdog w;
  std::atomic<int> sig{0};
  auto emergency = arm(w, 10, 100, sig);
  const std::string name = "stuck_controller";
  const auto t0 = std::chrono::steady_clock::now();
  w.enter(name, from_seconds(12.5), true, step_clock_now());  // ... and the step never returns
  REQUIRE(emergency.wait_for(5s) == std::future_status::ready);
  const auto waited = std::chrono::steady_clock::now() - t0;
  CHECK(waited >= 100ms);
  const Emergency e = emergency.get();
  CHECK(e.reason == "watchdog");
  CHECK(e.detail.find("stuck_controller at t=12.500 s") == 0);
  CHECK(e.detail.find("hard budget of 100 ms") != std::string::npos);
  CHECK(e.running == "stuck_controller");  // the host does not read its summary()
  w.disarm();
}

TEST_CASE("watchdog: an isolated instance's step (not policed) is left to its own time-out") {
  Watchdog w;
  std::atomic<int> sig{0};
  auto emergency = arm(w, 10, 50, sig);
  const std::string name = "isolated";
  w.enter(name, 0, false, step_clock_now());
  CHECK(emergency.wait_for(300ms) == std::future_status::timeout);
  TextLog tl;
  StepStats stats;
  w.leave(stats, 300'000'000, tl.log);  // returns: the flight was not claimed
  CHECK(stats.slow == 1);
  w.disarm();
  CHECK(emergency.wait_for(0ms) == std::future_status::timeout);
}

TEST_CASE("watchdog: a stop signal ends a step stuck for the grace time, with the signal as the reason") {
  Watchdog w;
  std::atomic<int> sig{0};
  auto emergency = arm(w, 10, 1e6, sig);  // the hard budget never trips here
  const std::string name = "sleeper";
  w.enter(name, from_seconds(3.0), true, step_clock_now());
  CHECK(emergency.wait_for(200ms) == std::future_status::timeout);  // no signal: waits on
  sig = SIGTERM;
  const auto t0 = std::chrono::steady_clock::now();
  REQUIRE(emergency.wait_for(5s) == std::future_status::ready);
  CHECK(std::chrono::steady_clock::now() - t0 >= std::chrono::milliseconds(Watchdog::kStopGraceMs - Watchdog::kTickMs));
  const Emergency e = emergency.get();
  CHECK(e.reason == "SIGTERM");
  CHECK(e.detail.find("sleeper at t=3.000 s: stuck in a step") == 0);
  w.disarm();
}

TEST_CASE("watchdog: steps over the soft budget are counted, warned about once; quick steps are not") {
  Watchdog w;
  std::atomic<int> sig{0};
  auto emergency = arm(w, 20, 2000, sig);
  TextLog tl;
  StepStats stats;
  const std::string name = "slow_estimator";
  w.enter(name, from_seconds(1.0), true, step_clock_now());
  w.leave(stats, 5'000'000, tl.log);  // 5 ms
  CHECK(stats.slow == 0);
  w.enter(name, from_seconds(2.0), true, step_clock_now());
  w.leave(stats, 25'000'000, tl.log);  // 25 ms
  w.enter(name, from_seconds(3.0), true, step_clock_now());
  w.leave(stats, 30'000'000, tl.log);
  CHECK(stats.slow == 2);
  const std::string text = tl.text.str();
  CHECK(text.find("t=2.000 s: slow_estimator: a step took 25.0 ms of wall time, over the watchdog's soft budget of 20 ms") !=
        std::string::npos);
  CHECK(text.find("t=3.000 s") == std::string::npos);  // one warning per instance and flight
  w.disarm();
  CHECK(emergency.wait_for(0ms) == std::future_status::timeout);
}
