// bench_path: cost of the path library's steps (ns per call): path manager update while flying
// the ROSplane hourglass (fillets and Dubins), vector-field follower (line, orbit), Dubins path
// computation, fillet computation. Prints a table, writes bench/results/bench_path.json.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "tern/path/follower.hpp"
#include "tern/path/geometry.hpp"
#include "tern/path/manager.hpp"
#include "tern/math.hpp"

using namespace tern::path;
using Clock = std::chrono::steady_clock;

namespace {
volatile double g_sink = 0.0;

struct Row {
  std::string key;   ///< JSON key
  std::string name;  ///< table label
  double median_ns;  ///< median over batches of the mean ns per call in a batch
  double min_ns;     ///< fastest batch
  long calls;        ///< calls per batch
};

/// Times `calls` calls of f(i) in each of 15 batches; the median batch is robust against other
/// work on a shared machine.
template <class F>
Row measure(const std::string& key, const std::string& name, long calls, F&& f) {
  f(0);  // warm-up
  std::vector<double> per_call;
  for (int b = 0; b < 15; ++b) {
    const auto t0 = Clock::now();
    for (long i = 0; i < calls; ++i) f(i);
    const auto t1 = Clock::now();
    per_call.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(calls));
  }
  std::sort(per_call.begin(), per_call.end());
  return {key, name, per_call[per_call.size() / 2], per_call.front(), calls};
}

std::vector<MissionPoint> hourglass(bool use_chi) {
  std::vector<MissionPoint> w;
  for (auto p : {Vec3(400, -250, -70), Vec3(-400, -50, -70), Vec3(-400, -250, -70), Vec3(400, -50, -70)})
    w.push_back({p, 1.1518, use_chi, 17.0});
  return w;
}

/// Positions along a recorded kinematic flight (so the manager switches as in flight).
std::vector<std::pair<Vec3, double>> flight(bool use_chi, int steps) {
  PathManager m;
  m.set_waypoints(hourglass(use_chi), true);
  double n = 0, e = 0, chi = 0, phi = 0;
  const double Va = 17, dt = 0.01;
  std::vector<std::pair<Vec3, double>> out;
  FollowerCommand c;
  for (int k = 0; k < steps; ++k) {
    const Vec3 p(n, e, -70);
    out.emplace_back(p, chi);
    const PathSegment s = m.update(p, chi, k * dt);
    if (k % 10 == 0) c = follow(s, FollowerInput{p, chi, chi, Va, Va}, FollowerGains{});
    const double err = tern::wrap_pi(c.chi_c - chi);
    const double phi_c = std::clamp(2.0 * err + c.phi_ff, -0.785, 0.785);
    phi += (phi_c - phi) * dt / 0.3;
    chi = tern::wrap_pi(chi + tern::kGravity / Va * std::tan(phi) * dt);
    n += Va * std::cos(chi) * dt;
    e += Va * std::sin(chi) * dt;
  }
  return out;
}
}  // namespace

int main() {
  std::vector<Row> rows;
  const int steps = 60000;  // 600 s at 100 Hz
  for (bool use_chi : {false, true}) {
    const auto track = flight(use_chi, steps);
    rows.push_back(measure(use_chi ? "manager_update_dubins_ns" : "manager_update_fillets_ns",
                           use_chi ? "manager update (hourglass, Dubins)" : "manager update (hourglass, fillets)", steps,
                           [&, m = PathManager()](long i) mutable {
                             if (i == 0) {  // replay the flight from the start with a fresh manager
                               m = PathManager();
                               m.set_waypoints(hourglass(use_chi), true);
                             }
                             const auto& [p, chi] = track[static_cast<std::size_t>(i)];
                             g_sink = g_sink + m.update(p, chi, static_cast<double>(i) * 0.01).rho;
                           }));
  }
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> pos(-500, 500), ang(-3.14, 3.14);
  std::vector<Vec3> pts(4096);
  std::vector<double> angs(4096);
  for (auto& p : pts) p = Vec3(pos(rng), pos(rng), -70);
  for (auto& a : angs) a = ang(rng);
  PathSegment line;
  line.type = PathSegment::Type::line;
  line.r = Vec3(0, 0, -70);
  line.q = Vec3(1, 1, 0).normalized();
  line.Va_d = 17;
  PathSegment orbit;
  orbit.c = Vec3(0, 0, -70);
  orbit.rho = 50;
  orbit.Va_d = 17;
  const FollowerGains g;
  rows.push_back(measure("follower_line_ns", "follower step (line)", 200'000, [&](long i) {
    g_sink = g_sink + follow(line, FollowerInput{pts[i & 4095], angs[i & 4095], angs[i & 4095], 17, 17}, g).chi_c;
  }));
  rows.push_back(measure("follower_orbit_ns", "follower step (orbit)", 200'000, [&](long i) {
    g_sink = g_sink + follow(orbit, FollowerInput{pts[i & 4095], angs[i & 4095], angs[i & 4095], 17, 17}, g).chi_c;
  }));
  rows.push_back(measure("dubins_path_ns", "Dubins path (4 candidates)", 100'000, [&](long i) {
    const long j = i & 4095, k = (i + 1) & 4095;
    g_sink = g_sink + dubins_path(pts[j], angs[j], pts[k], angs[k], 50.0).length;
  }));
  rows.push_back(measure("fillet_ns", "fillet", 200'000, [&](long i) {
    const long j = i & 4095;
    g_sink = g_sink + compute_fillet(pts[j], pts[(j + 1) & 4095], pts[(j + 2) & 4095], 5.0).offset;
  }));

  // Targets: a step must be negligible against the 100 Hz manager / 10 Hz follower periods and
  // a Dubins path (computed once per waypoint) cheap enough for replanning every step.
  const std::vector<std::pair<std::string, double>> targets = {
      {"manager_update_fillets_ns", 1000}, {"manager_update_dubins_ns", 1000}, {"follower_line_ns", 1000},
      {"follower_orbit_ns", 1000},         {"dubins_path_ns", 5000},           {"fillet_ns", 1000}};
  std::printf("%-40s %12s %12s %12s %10s\n", "bench_path", "median ns", "min ns", "target ns", "calls");
  for (const auto& r : rows) {
    double target = 0;
    for (const auto& [k, v] : targets)
      if (k == r.key) target = v;
    std::printf("%-40s %12.1f %12.1f %12.0f %10ld\n", r.name.c_str(), r.median_ns, r.min_ns, target, r.calls);
  }

  const std::filesystem::path dir = TERN_BENCH_RESULTS_DIR;
  std::filesystem::create_directories(dir);
  std::ofstream js(dir / "bench_path.json");
  js << "{\n";
  for (const auto& r : rows) js << "  \"" << r.key << "\": " << r.median_ns << ",\n";
  for (const auto& r : rows) js << "  \"" << r.key.substr(0, r.key.size() - 3) << "_min_ns\": " << r.min_ns << ",\n";
  js << "  \"targets\": {";
  for (std::size_t i = 0; i < targets.size(); ++i) js << (i ? ", " : "") << "\"" << targets[i].first << "\": " << targets[i].second;
  js << "}\n}\n";
  std::printf("wrote %s\n", (dir / "bench_path.json").string().c_str());
  bool ok = true;
  for (const auto& r : rows)
    for (const auto& [k, v] : targets)
      if (k == r.key && r.median_ns > v) ok = false;
  if (!ok) std::printf("some medians exceed their targets\n");
  return 0;
}
