// bench_control: cost of one controller step. Prints a table and writes
// bench/results/bench_control.json: nanoseconds per autopilot update (the plain algorithm) and
// per plugin step through the SDK harness (ports and parameters included), for the successive
// loop closure (control_slc) and total energy (control_tecs) laws. States are replayed from a
// closed-loop flight of the linear Anaconda model with altitude, course and airspeed steps.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "control_common/testing/closed_loop.hpp"
#include "control_slc.hpp"
#include "control_tecs.hpp"

namespace {
using Clock = std::chrono::steady_clock;
using namespace tern;
using namespace tern::control;
volatile double g_sink = 0;

struct Row {
  std::string name;
  double ns;
  long n;
};

template <class F>
Row measure(const std::string& name, long n, F&& f) {
  for (long i = 0; i < n / 10; ++i) f(i);  // warm-up
  const auto t0 = Clock::now();
  for (long i = 0; i < n; ++i) f(i);
  const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / static_cast<double>(n);
  return {name, ns, n};
}

// 60 s of closed-loop flight (6000 states at 100 Hz) with steps in every command.
std::vector<VehicleState> record() {
  std::vector<VehicleState> xs;
  SlcLongitudinal law;
  Autopilot ap(law);
  testmodel::LinearAircraft plant(testmodel::anaconda());
  Command c{17.0, 100.0, 0.0, 0.0, 0.0, 0.0, false, false};
  for (int i = 0; i < 6000; ++i) {
    if (i == 1000) c.h_c = 120.0;
    if (i == 2500) c.chi_c = 1.5;
    if (i == 4000) c.Va_c = 20.0;
    const auto x = plant.state();
    xs.push_back(x);
    plant.step(ap.update(Mode::cruise, x, c, {}, 0.01).surfaces, 0.01);
  }
  return xs;
}

msg::State to_msg(const VehicleState& x) {
  msg::State s;
  s.phi = x.phi;
  s.theta = x.theta;
  s.chi = x.chi;
  s.psi = x.chi;
  s.p = x.p;
  s.q = x.q;
  s.r = x.r;
  s.p_d = -x.h;
  s.v_d = -x.h_dot;
  s.Va = x.Va;
  s.valid = true;
  return s;
}
}  // namespace

int main() {
  const auto xs = record();
  const long N = 1'000'000;
  const Command c{17.0, 110.0, 0.8, 0.0, 0.0, 0.0, false, false};
  std::vector<Row> rows;

  SlcLongitudinal slc;
  Autopilot ap_slc(slc);
  rows.push_back(measure("SLC autopilot update (algorithm)", N,
                         [&](long i) { g_sink = g_sink + ap_slc.update(Mode::cruise, xs[i % xs.size()], c, {}, 0.01).surfaces.delta_e; }));
  Tecs tecs;
  Autopilot ap_tecs(tecs);
  rows.push_back(measure("TECS autopilot update (algorithm)", N,
                         [&](long i) { g_sink = g_sink + ap_tecs.update(Mode::cruise, xs[i % xs.size()], c, {}, 0.01).surfaces.delta_e; }));

  std::vector<msg::State> ms;
  for (const auto& x : xs) ms.push_back(to_msg(x));
  msg::ControllerCommand cmd;
  cmd.Va_c = c.Va_c;
  cmd.h_c = c.h_c;
  cmd.chi_c = c.chi_c;
  auto plugin_row = [&](const std::string& name, std::unique_ptr<Plugin> p) {
    testing::Harness h(std::move(p));
    h.set_input("controller_command", cmd);
    Nanos t = 0;
    return measure(name, N / 2, [&](long i) {
      h.set_input("state", ms[static_cast<std::size_t>(i) % ms.size()]);
      h.step(t += 10'000'000);
      g_sink = g_sink + h.output<msg::Actuators>("actuators").delta_e;
    });
  };
  rows.push_back(plugin_row("control_slc plugin step (harness, ports)", std::make_unique<ControlSlc>()));
  rows.push_back(plugin_row("control_tecs plugin step (harness, ports)", std::make_unique<ControlTecs>()));

  std::printf("%-48s %12s %10s\n", "benchmark (linear Anaconda replay, 100 Hz)", "ns/step", "steps");
  for (const auto& r : rows) std::printf("%-48s %12.1f %10ld\n", r.name.c_str(), r.ns, r.n);

  const std::filesystem::path dir = std::filesystem::path(TERN_BENCH_RESULTS_DIR).lexically_normal();
  std::filesystem::create_directories(dir);
  std::ofstream f(dir / "bench_control.json");
  f << "{\n  \"benchmark\": \"bench_control\",\n  \"unit\": \"ns per step\",\n  \"results\": [\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    f << "    {\"name\": \"" << rows[i].name << "\", \"ns\": " << rows[i].ns << ", \"n\": " << rows[i].n << "}"
      << (i + 1 < rows.size() ? ",\n" : "\n");
  }
  f << "  ]\n}\n";
  std::printf("wrote %s\n", (dir / "bench_control.json").c_str());
  return 0;
}
