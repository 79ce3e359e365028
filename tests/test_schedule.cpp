// Schedule order, rates, library unloading.
#include <doctest/doctest.h>

#include <dlfcn.h>

#include "loader.hpp"
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
