// bench_isolation: what one port hop costs when the instance is isolated (`isolate: true`: a
// child process in lockstep over shared memory, isolated_plugin.hpp), beside the in-process
// hop and the Fast DDS hop. Prints a table and writes bench/results/bench_isolation.json.
//   1. in-process: a flight of test_sensor (400 Hz) -> test_filter (on imu) -> test_controller,
//      60 s of flight; the filter's step time (reads imu, publishes state), median and p99
//   2. the same flight with the filter isolated: its step time is then the whole hop (imu copied
//      in, the command posted, the child's step, state copied out, the reply awaited)
//   3. the bare round trip: test_null (no ports) isolated vs in-process
//   4. the Fast DDS hop of State on loopback at 400 Hz, quoted from bench/results/bench_dds.json
//      (bench_dds) when that file exists
// Step times come from the host's own step clock (StepStats), so they include the scheduler's
// few ns per step in both columns, and are its histogram's bucket upper bounds (buckets 2^(1/4)
// apart: a median is good to about 19%).
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "config/config.hpp"
#include "flight/host.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kPlugins = TERN_TEST_PLUGIN_DIR;

std::string mission(bool isolate_filter, bool isolate_null) {
  const auto lib = [](const char* n) { return (kPlugins / (std::string("libtern_") + n + ".so")).string(); };
  return fmt::format(
      "name: bench_isolation\nseed: 1\nduration: 60\nlog: {{topics: [imu], max_rate: 1}}\nplugins:\n"
      "  - {{name: sensor, plugin: {}, rate: 400}}\n"
      "  - {{name: filter, plugin: {}, trigger: imu, isolate: {}}}\n"
      "  - {{name: ctl, plugin: {}, rate: 100}}\n"
      "  - {{name: idle, plugin: {}, rate: 400, isolate: {}}}\n",
      lib("test_sensor"), lib("test_filter"), isolate_filter, lib("test_controller"), lib("test_null"), isolate_null);
}

struct Times {
  double filter_median, filter_p99, null_median, null_p99;
};

Times fly(bool isolated, const fs::path& dir) {
  const fs::path cfg = dir / (isolated ? "isolated.yaml" : "in_process.yaml");
  std::ofstream(cfg) << mission(isolated, isolated);
  tern::core::HostOptions o;
  o.quiet = true;
  o.log_dir = dir / "runs";
  tern::core::Host h(tern::core::load_config(cfg), o);
  h.build();
  const auto r = h.fly();
  if (!r.ok) throw std::runtime_error("bench flight failed: " + r.end_reason);
  const auto& f = h.instances()[1]->stats;
  const auto& n = h.instances()[3]->stats;
  return {static_cast<double>(f.percentile(0.5)), static_cast<double>(f.percentile(0.99)), static_cast<double>(n.percentile(0.5)),
          static_cast<double>(n.percentile(0.99))};
}

}  // namespace

int run() {
  const fs::path dir = fs::temp_directory_path() / fmt::format("tern_bench_isolation_{}", ::getpid());
  fs::create_directories(dir);
  const Times in = fly(false, dir);
  const Times iso = fly(true, dir);
  fs::remove_all(dir);

  nlohmann::ordered_json out;
  out["in_process_filter_step"] = {{"median_ns", in.filter_median}, {"p99_ns", in.filter_p99}};
  out["isolated_filter_step"] = {{"median_ns", iso.filter_median}, {"p99_ns", iso.filter_p99}};
  out["isolated_hop_cost"] = {{"median_ns", iso.filter_median - in.filter_median}};
  out["in_process_null_step"] = {{"median_ns", in.null_median}, {"p99_ns", in.null_p99}};
  out["isolated_null_step"] = {{"median_ns", iso.null_median}, {"p99_ns", iso.null_p99}};
  const fs::path results = fs::path(TERN_SOURCE_DIR) / "bench" / "results";
  std::ifstream dds_file(results / "bench_dds.json");
  nlohmann::json dds;
  if (dds_file) dds = nlohmann::json::parse(dds_file, nullptr, false);
  const bool have_dds = dds.is_object() && dds.contains("dds_hop_400hz");
  if (have_dds) {
    out["dds_hop_400hz"] = dds["dds_hop_400hz"];
    out["port_hop"] = dds["port_hop"];
  }

  fmt::print("bench_isolation: one hop (step times from the host's step clock, 60 s of flight, 400 Hz)\n");
  fmt::print("{:<52} {:>12} {:>12}\n", "", "median", "p99");
  const auto row = [](const std::string& what, double med, double p99) {
    fmt::print("{:<52} {:>9.2f} us {:>9.2f} us\n", what, med * 1e-3, p99 * 1e-3);
  };
  if (have_dds) row("in-process port hop (bench_dds: publish + get + copy)", dds["port_hop"]["median_ns"], dds["port_hop"]["p99_ns"]);
  row("test_filter step, in-process (imu in, state out)", in.filter_median, in.filter_p99);
  row("test_filter step, isolated (the whole hop)", iso.filter_median, iso.filter_p99);
  row("test_null step, in-process", in.null_median, in.null_p99);
  row("test_null step, isolated (bare round trip)", iso.null_median, iso.null_p99);
  if (have_dds)
    row("Fast DDS UDP loopback at 400 Hz (bench_dds)", dds["dds_hop_400hz"]["median_ns"], dds["dds_hop_400hz"]["p99_ns"]);
  else
    fmt::print("(no bench/results/bench_dds.json: run bench_dds for the Fast DDS hop)\n");
  fmt::print("isolation costs {:.2f} us per hop (median, filter isolated minus in-process)\n",
             (iso.filter_median - in.filter_median) * 1e-3);
  fs::create_directories(results);
  std::ofstream(results / "bench_isolation.json") << out.dump(2) << "\n";
  return 0;
}

int main() {
  try {
    return run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_isolation: %s\n", e.what());
    return 1;
  }
}
