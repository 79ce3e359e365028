// bench_sim_aero: cost of the simulator. Prints a table and writes
// bench/results/bench_sim_aero.json: nanoseconds per model evaluation, per RK4 step
// (servo + wind + RK4, moderate turbulence), per plugin step at 400 Hz (RK4 + aero + all
// sensors + truth, through the SDK harness), and the real-time factor of the sim alone.
// Times are thread CPU time (best of 3), so that a busy shared machine does not inflate them.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sim_aero_plugin.hpp"
#include "tern/testing/harness.hpp"
#include "tern_sim_aero/simulator.hpp"
#include "tern/aero/trim.hpp"

namespace {
volatile double g_sink = 0;

struct Row {
  std::string name;
  double ns;
  long n;
};

// CPU time of this thread, ns: on a shared machine it counts only the time spent computing.
double cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e9 + static_cast<double>(ts.tv_nsec);
}

// Best of three runs of n operations, after a warm-up; thread CPU time per operation.
template <class F>
Row measure(const std::string& name, long n, F&& f) {
  for (long i = 0; i < n / 10; ++i) f(i);
  double best = 1e300;
  for (int rep = 0; rep < 3; ++rep) {
    const double t0 = cpu_ns();
    for (long i = 0; i < n; ++i) f(i);
    best = std::min(best, (cpu_ns() - t0) / static_cast<double>(n));
  }
  return {name, best, n};
}
}  // namespace

int main() {
  const std::string aircraft = std::string(TERN_AIRCRAFT_DIR) + "/anaconda.yaml";
  const tern::Aircraft ac = tern::load_aircraft(aircraft);
  const tern::sim::TrimResult tr = tern::sim::compute_trim(ac, tern::sim::TrimRequest{});
  std::vector<Row> rows;

  rows.push_back(measure("derivative (forces, moments, 13-state)", 1'000'000, [&](long i) {
    tern::sim::StateVector x = tr.x;
    x[tern::sim::U] += 1e-9 * static_cast<double>(i & 7);
    g_sink = g_sink + tern::sim::derivative(ac, x, tr.delta, tern::sim::Wind{})[tern::sim::U];
  }));

  tern::sim::Simulator sim(ac, 1);
  sim.set_state(tr.x, tr.delta);
  sim.set_command(tr.delta);
  sim.set_turbulence(tern::sim::dryden_preset("moderate"));
  // Open loop in turbulence the aircraft would eventually crash (and stop integrating):
  // restart it at trim every 10 s of flight.
  rows.push_back(measure("RK4 step (servo + wind + 4 derivatives)", 400'000, [&](long i) {
    if (i % 4000 == 0) sim.set_state(tr.x, tr.delta);
    sim.step(0.0025);
    g_sink = g_sink + sim.state()[tern::sim::PN];
  }));

  tern::testing::HarnessOptions o;
  o.aircraft_file = aircraft;
  tern::testing::Harness h(std::make_unique<tern::sim_aero::SimAero>(),
                           {{"init_mode", std::string("trim")}, {"turbulence", std::string("moderate")}}, o);
  tern::Nanos t = 0;
  h.step(t);
  const Row plugin = measure("plugin step at 400 Hz (RK4 + sensors + truth)", 200'000, [&](long i) {
    if (i % 4000 == 0) {  // a new flight every 10 s (see above)
      h.reset();
      t = 0;
    } else {
      t += 2'500'000;
    }
    h.step(t);
  });
  rows.push_back(plugin);
  const double rtf = 2.5e6 / plugin.ns;

  std::printf("%-56s %12s %10s\n", "benchmark (Anaconda, trim 17 m/s; CPU time, best of 3)", "ns/op", "ops");
  for (const auto& r : rows) std::printf("%-56s %12.1f %10ld\n", r.name.c_str(), r.ns, r.n);
  std::printf("%-56s %12.0f\n", "real-time factor of the sim alone (400 Hz)", rtf);
  if (sim.crashed()) std::printf("warning: the RK4 benchmark ended crashed\n");

  const std::filesystem::path out = std::filesystem::path(TERN_BENCH_RESULTS_DIR) / "bench_sim_aero.json";
  std::filesystem::create_directories(out.parent_path());
  std::ofstream f(out);
  f << "{\n  \"benchmark\": \"bench_sim_aero\",\n  \"aircraft\": \"anaconda\",\n  \"results\": [\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    f << "    {\"name\": \"" << rows[i].name << "\", \"ns_per_op\": " << rows[i].ns << ", \"ops\": " << rows[i].n << "}"
      << (i + 1 < rows.size() ? "," : "") << "\n";
  }
  f << "  ],\n  \"ns_per_sim_step\": " << plugin.ns << ",\n  \"real_time_factor\": " << rtf << "\n}\n";
  std::printf("wrote %s\n", out.string().c_str());
  return g_sink == 12345.0 ? 1 : 0;
}
