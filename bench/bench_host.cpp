// bench_host: the host's own costs. Prints a table and writes bench/results/bench_host.json.
//   1. port publish-to-read, per subscriber (target < 50 ns)
//   2. scheduler overhead per plugin step (target < 100 ns)
//   3. host start (config load, 7 plugins loaded and configured, log opened) to first tick
//      (target < 100 ms)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "config/config.hpp"
#include "flight/host.hpp"
#include "tern/port.hpp"

namespace fs = std::filesystem;
using clk = std::chrono::steady_clock;

namespace {
double ns_since(clk::time_point t0) { return std::chrono::duration<double, std::nano>(clk::now() - t0).count(); }

double publish_read_ns(std::size_t subscribers, std::size_t iterations) {
  tern::Output<tern::msg::Imu> out;
  std::vector<std::unique_ptr<tern::Input<tern::msg::Imu>>> ins;
  for (std::size_t i = 0; i < subscribers; ++i) {
    ins.push_back(std::make_unique<tern::Input<tern::msg::Imu>>());
    ins.back()->bind(&out);
  }
  tern::msg::Imu m;
  double sink = 0;
  const auto t0 = clk::now();
  for (std::size_t k = 0; k < iterations; ++k) {
    m.stamp = static_cast<tern::Nanos>(k);
    m.accel.x() = static_cast<double>(k);
    out.publish(m);
    for (auto& in : ins) {
      if (in->updated()) sink += in->get().accel.x();
      in->mark_seen();
    }
  }
  const double ns = ns_since(t0);
  if (sink == -1) std::puts("");
  return ns / static_cast<double>(iterations);
}

fs::path write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p;
}
}  // namespace

int main() {
  const fs::path dir = fs::temp_directory_path() / "tern_bench_host";
  fs::create_directories(dir);
  setenv("TERN_PLUGIN_PATH", TERN_TEST_PLUGIN_DIR, 1);
  nlohmann::ordered_json j;

  // 1. ports
  const std::size_t iters = 2'000'000;
  const double p0 = publish_read_ns(0, iters);
  std::vector<std::pair<std::size_t, double>> per_sub;
  for (std::size_t n : {1, 4, 16}) per_sub.emplace_back(n, (publish_read_ns(n, iters) - p0) / static_cast<double>(n));

  // 2. scheduler overhead: 7 instances of a plugin whose step does nothing, 400 Hz, no logging
  std::string cfg = "name: bench_sched\nduration: 250\nlog: {topics: []}\nplugins:\n";
  for (int i = 0; i < 7; ++i) cfg += fmt::format("  - {{name: n{}, plugin: test_null, rate: 400}}\n", i);
  double sched_ns = 0;
  {
    tern::core::HostOptions o;
    o.quiet = true;
    o.log_dir = dir / "runs";
    tern::core::Host h(tern::core::load_config(write(dir / "sched.yaml", cfg)), o);
    h.build();
    const auto r = h.fly();
    std::uint64_t steps = 0;
    for (const auto& inst : h.instances()) steps += inst->stats.steps;
    sched_ns = r.wall_s * 1e9 / static_cast<double>(steps);
  }

  // 3. start to first tick, seven plugins (sensor, filter, controller, four others), logging on
  std::string cfg7 =
      "name: bench_start\nduration: 0.01\nplugins:\n"
      "  - {name: sensor, plugin: test_sensor, rate: 400}\n"
      "  - {name: filter, plugin: test_filter, trigger: imu}\n"
      "  - {name: ctl, plugin: test_controller, rate: 100}\n";
  for (int i = 0; i < 4; ++i) cfg7 += fmt::format("  - {{name: n{}, plugin: test_null, rate: 100}}\n", i);
  const fs::path cfg7_path = write(dir / "start.yaml", cfg7);
  std::vector<double> starts;
  for (int rep = 0; rep < 5; ++rep) {
    // from reading the config to the first tick (the Host records constructor -> first tick)
    const auto t0 = clk::now();
    tern::core::HostOptions o;
    o.quiet = true;
    o.log_dir = dir / "runs";
    tern::core::MissionConfig mc = tern::core::load_config(cfg7_path);
    const double load_ms = ns_since(t0) * 1e-6;
    tern::core::Host h(std::move(mc), o);
    h.build();
    (void)h.fly();
    starts.push_back(load_ms + h.start_to_first_tick_ms());
  }
  std::sort(starts.begin(), starts.end());
  const double start_ms = starts[starts.size() / 2];

  // 4. hot-swap between flights: swap one plugin (v1 <-> v2 of test_controller), then the next
  //    flight's start (log directory, resets, start()) to its first tick
  std::vector<double> swaps, next_starts;
  {
    tern::core::HostOptions o;
    o.quiet = true;
    o.log_dir = dir / "runs";
    tern::core::Host h(tern::core::load_config(cfg7_path), o);
    h.build();
    (void)h.fly();
    const fs::path v[2] = {fs::path(TERN_TEST_PLUGIN_DIR) / "v2" / "libtern_test_controller.so",
                           fs::path(TERN_TEST_PLUGIN_DIR) / "libtern_test_controller.so"};
    for (int rep = 0; rep < 20; ++rep) {
      const auto t0 = clk::now();
      h.swap("ctl", v[rep % 2]);
      swaps.push_back(ns_since(t0) * 1e-6);
      (void)h.fly();
      next_starts.push_back(h.flight_start_ms());
    }
  }
  std::sort(swaps.begin(), swaps.end());
  std::sort(next_starts.begin(), next_starts.end());
  const double swap_ms = swaps[swaps.size() / 2], next_start_ms = next_starts[next_starts.size() / 2];
  fs::remove_all(dir);

  std::printf("%-52s %12s %12s\n", "benchmark", "measured", "target");
  for (auto& [n, ns] : per_sub)
    std::printf("%-52s %9.1f ns %9s\n", fmt::format("port publish-to-read per subscriber ({} subs)", n).c_str(), ns, "< 50 ns");
  std::printf("%-52s %9.1f ns %9s\n", "port publish alone", p0, "");
  std::printf("%-52s %9.1f ns %9s\n", "scheduler overhead per plugin step (7 x 400 Hz)", sched_ns, "< 100 ns");
  std::printf("%-52s %9.2f ms %9s\n", "host start to first tick, 7 plugins (median of 5)", start_ms, "< 100 ms");
  std::printf("%-52s %9.2f ms %9s\n", "hot-swap of one plugin between flights (median of 20)", swap_ms, "< 50 ms");
  std::printf("%-52s %9.2f ms %9s\n", "next flight: fly() to its first tick (median of 20)", next_start_ms, "");

  for (auto& [n, ns] : per_sub) j["port_publish_to_read_ns_per_subscriber"][std::to_string(n)] = ns;
  j["port_publish_ns"] = p0;
  j["scheduler_overhead_ns_per_step"] = sched_ns;
  j["start_to_first_tick_ms"] = start_ms;
  j["swap_ms"] = swap_ms;
  j["next_flight_start_ms"] = next_start_ms;
  j["targets"] = {{"port_publish_to_read_ns_per_subscriber", 50},
                  {"scheduler_overhead_ns_per_step", 100},
                  {"start_to_first_tick_ms", 100},
                  {"swap_ms", 50}};
  write(fs::path(TERN_SOURCE_DIR) / "bench" / "results" / "bench_host.json", j.dump(2) + "\n");
  return 0;
}
