// Schedule order, rates, library unloading; the Scheduler and rates alone, without plugins.
#include <doctest/doctest.h>

#include <dlfcn.h>

#include <csignal>
#include <stdexcept>

#include "graph/loader.hpp"
#include "graph/scheduler.hpp"
#include "test_util.hpp"

using namespace tern::core;

namespace {
std::unique_ptr<Host> built(const std::string& yaml, const std::string& file = "sched.yaml") {
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / "runs";
  auto h = std::make_unique<Host>(load_config(write_file(file, yaml)), o);
  h->build();
  return h;
}
}  // namespace

TEST_CASE("I/O first, then producers before consumers, whatever the config order") {
  const std::string cfg =
      "name: order\nduration: 1\nplugins:\n"
      "  - {name: ctl, plugin: test_controller, rate: 100}\n"
      "  - {name: filter, plugin: test_filter, trigger: imu}\n"
      "  - {name: sensor, plugin: test_sensor, rate: 400}\n";
  auto h = built(cfg);
  CHECK(h->schedule() == std::vector<std::string>{"sensor", "filter", "ctl", "metrics"});  // metrics: built in
  CHECK(h->base_period() == 2'500'000);
  // the sensor reads actuators from the controller scheduled after it: a feedback edge
  CHECK(h->graph_text().find("sensor.actuators (feedback: previous tick)") != std::string::npos);
  CHECK(h->graph_dot().find("\"ctl\" -> \"sensor\" [label=\"actuators\", style=dashed]") != std::string::npos);
}

TEST_CASE("rates and triggers: step counts over one second of flight") {
  auto h = built(base_config().replace(base_config().find("duration: 2"), 11, "duration: 1"));
  const FlightResult r = h->fly();
  CHECK(r.ok);
  CHECK(r.end_reason == "duration");
  CHECK(r.flown == 1'000'000'000);
  std::map<std::string, std::uint64_t> steps;
  for (const auto& inst : h->instances()) steps[inst->cfg.name] = inst->stats.steps;
  CHECK(steps["sensor"] == 401);  // t = 0, 2.5 ms, ..., 1 s
  CHECK(steps["filter"] == 401);  // every imu sample, in the same tick
  CHECK(steps["ctl"] == 101);
  const std::string summary = read_file(r.run_dir / "summary.json");
  CHECK(summary.find("\"stale_imu_steps\": 0.0") != std::string::npos);
}

TEST_CASE("unloading a plugin leaves no library mapped") {
  const fs::path path = fs::path(TERN_TEST_PLUGIN_DIR) / "libtern_test_controller.so";
  REQUIRE(fs::exists(path));
  CHECK_FALSE(is_loaded(path));
  {
    auto lib = open_plugin(path);
    CHECK(is_loaded(path));
    auto p = lib->create();
    p.reset();
  }
  CHECK_FALSE(is_loaded(path));
  {  // a whole host: instances destroyed before their libraries
    auto h = built(base_config());
    CHECK(is_loaded(path));
    (void)h->fly();
  }
  CHECK_FALSE(is_loaded(path));
  CHECK_FALSE(is_loaded(fs::path(TERN_TEST_PLUGIN_DIR) / "libtern_test_sensor.so"));
}

// ---- the scheduler alone: no plugin library ------------------------------------------------------

namespace {

// A plugin compiled into the test: counts its steps, throws when told to.
class Counter final : public tern::Plugin {
 public:
  void configure() override { declare(in_, "imu"); }
  void step(tern::Nanos now) override {
    ++steps;
    last = now;
    if (fail) throw std::runtime_error("counter failed");
  }
  tern::Input<tern::msg::Imu> in_;
  int steps = 0;
  tern::Nanos last = -1;
  bool fail = false;
};

InstanceConfig rate_config(std::size_t index, const std::string& yaml) {
  InstanceConfig ic;
  ic.index = index;
  ic.node = YAML::Load(yaml);
  if (ic.node["rate"]) ic.rate = ic.node["rate"].as<double>();
  if (ic.node["budget_us"]) ic.budget_us = ic.node["budget_us"].as<double>();
  return ic;
}

}  // namespace

TEST_CASE("rates: the base period is the fastest rate's; divisors and budgets per instance") {
  const InstanceConfig sim = rate_config(0, "{rate: 400}"), ctl = rate_config(1, "{rate: 100, budget_us: 50}"),
                       ekf = rate_config(2, "{trigger: imu}"), planner = rate_config(3, "{rate: 10}");
  const Rates r = resolve_rates(std::nullopt, YAML::Node(), {&sim, &ctl, &ekf, &planner}, "/m.yaml");
  CHECK(r.base_period == 2'500'000);
  CHECK(r.divisors == std::vector<std::int64_t>{1, 4, 0, 40});
  CHECK(r.budgets == std::vector<tern::Nanos>{2'500'000, 50'000, 2'500'000, 100'000'000});
  // an explicit base rate: every rate must divide it
  const Rates b = resolve_rates(1000.0, YAML::Node(), {&ctl, &planner}, "/m.yaml");
  CHECK(b.base_period == 1'000'000);
  CHECK(b.divisors == std::vector<std::int64_t>{10, 100});
}

TEST_CASE("rates: a rate the base rate cannot serve, and no rate at all, are refused") {
  const InstanceConfig sim = rate_config(0, "{rate: 400}"), odd = rate_config(1, "{name: x, rate: 390}");
  CHECK_THROWS_WITH_AS(resolve_rates(std::nullopt, YAML::Node(), {&sim, &odd}, "/m.yaml"),
                       doctest::Contains("/m.yaml:1:17: plugins[1].rate: 390 Hz cannot be served by the base rate 400 Hz"), ConfigError);
  const InstanceConfig trig = rate_config(0, "{trigger: imu}");
  CHECK_THROWS_WITH_AS(resolve_rates(std::nullopt, YAML::Node(), {&trig}, "/m.yaml"),
                       "/m.yaml: base_rate: no instance has a rate and no base_rate is given", ConfigError);
}

TEST_CASE("scheduler: ticks from 0 to the end inclusive, in integer ns; a stop signal ends after the last tick flown") {
  Scheduler clock(2'500'000, 10'000'000, false);
  std::vector<tern::Nanos> times;
  while (clock.next(0)) times.push_back(clock.now());
  CHECK(times == std::vector<tern::Nanos>{0, 2'500'000, 5'000'000, 7'500'000, 10'000'000});
  CHECK(clock.end_reason() == "duration");
  CHECK(clock.now() == 10'000'000);
  Scheduler stopped(2'500'000, 10'000'000, false);
  REQUIRE(stopped.next(0));
  REQUIRE(stopped.next(0));
  CHECK_FALSE(stopped.next(SIGTERM));
  CHECK(stopped.end_reason() == "SIGTERM");
  CHECK(stopped.now() == 2'500'000);
  Scheduler at_once(2'500'000, 10'000'000, false);
  CHECK_FALSE(at_once.next(SIGINT));
  CHECK(at_once.end_reason() == "SIGINT");
  CHECK(at_once.now() == 0);
}

TEST_CASE("scheduler: rate instances are due every divisor-th tick, triggered ones when their input has news") {
  tern::Output<tern::msg::Imu> imu;
  imu.set_identity("imu", "");
  Counter c;
  c.configure();
  c.in_.bind(&imu);
  Scheduler clock(2'500'000, 20'000'000, false);
  std::vector<std::int64_t> rate_ticks, trigger_ticks;
  StepStats stats;
  while (clock.next(0)) {
    if (clock.due(4, nullptr)) rate_ticks.push_back(clock.tick());
    if (clock.tick() % 3 == 0) imu.publish(tern::msg::Imu{});
    clock.start_steps();
    if (clock.due(0, &c.in_)) {
      trigger_ticks.push_back(clock.tick());
      std::string error;
      stats.add(clock.step(c, error));  // marks the input seen
      CHECK(error.empty());
    }
  }
  CHECK(rate_ticks == std::vector<std::int64_t>{0, 4, 8});
  CHECK(trigger_ticks == std::vector<std::int64_t>{0, 3, 6});
  CHECK(c.steps == 3);
  CHECK(c.last == 15'000'000);
  CHECK(stats.steps == 3);
}

TEST_CASE("scheduler: a step that throws gives its error and is still timed") {
  Counter c;
  c.configure();
  c.fail = true;
  Scheduler clock(1'000'000, 0, false);
  REQUIRE(clock.next(0));
  StepStats stats;
  stats.budget_ns = 1;  // any step overruns 1 ns
  clock.start_steps();
  std::string error;
  stats.add(clock.step(c, error));  // the duration, for the caller to add once the watchdog let the step go
  CHECK(error == "counter failed");
  CHECK(c.steps == 1);
  CHECK(stats.steps == 1);
  CHECK(stats.overruns == 1);
  CHECK(stats.max_ns > 0);
}

TEST_CASE("step statistics: log-spaced histogram, percentiles as bucket upper bounds, overruns over the budget") {
  StepStats s;
  s.budget_ns = 1000;
  for (int i = 0; i < 99; ++i) s.add(100);
  s.add(5000);
  CHECK(s.steps == 100);
  CHECK(s.overruns == 1);
  CHECK(s.max_ns == 5000);
  CHECK(s.total_ns == 99 * 100 + 5000);
  // 100 ns lies in [96, 112): the median's upper bound is 112 ns, within 2^(1/4) of the value
  CHECK(s.percentile(0.5) == 112);
  CHECK(s.percentile(0.99) == 112);
  CHECK(s.percentile(1.0) >= 5000);
  CHECK(s.percentile(1.0) < 5000 * 1.19);
  CHECK(StepStats{}.percentile(0.5) == 0);
}
