// bench_estimation: the estimator accuracy benchmark of the EKF issue. Flies the first five
// minutes of the default mission (Anaconda from the ground, ROSplane's hourglass, 5 m/s of wind
// from the south-east plus light Dryden turbulence, default sensor models, seed 1) in-process with
// sim_aero and estimator_ekf in the loop, compares the estimate with the simulator's truth at
// every IMU tick, and prints the RMSE beside ROSplane 2.0's published figures and beside the raw
// GNSS error of the same run. Writes bench/results/bench_estimation.json.
//
// Usage: bench_estimation [MISSION.yaml] [--duration S] [--seed N]
// Window: errors count from t0 = 30 s (after takeoff and climb: cruise starts near 11 s) to the
// end; wind from 60 s (after its convergence). Course and yaw errors are wrapped to [-pi, pi).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <GeographicLib/LocalCartesian.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "config.hpp"
#include "host.hpp"
#include "tern/math.hpp"
#include "tern/msg/all.hpp"
#include "tern/port.hpp"

namespace fs = std::filesystem;

namespace {
constexpr double kDeg = 180.0 / tern::kPi;
using tern::wrap_pi;

struct Rms {
  double sum = 0;
  std::size_t n = 0;
  void add(double e) { sum += e * e; ++n; }
  double value() const { return n == 0 ? std::nan("") : std::sqrt(sum / static_cast<double>(n)); }
};

template <class T>
const T* latest(const tern::OutputBase* src) {
  if (src == nullptr || src->sequence() == 0 || src->type().fingerprint != tern::reflect::fingerprint<T>()) return nullptr;
  return static_cast<const T*>(src->data());
}
}  // namespace

int main(int argc, char** argv) {
  std::string mission = std::string(TERN_SOURCE_DIR) + "/configs/missions/default.yaml";
  double duration = 300.0;
  std::uint64_t seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--duration" && i + 1 < argc) duration = std::atof(argv[++i]);
    else if (a == "--seed" && i + 1 < argc) seed = std::strtoull(argv[++i], nullptr, 10);
    else if (a.rfind("--", 0) == 0) {
      std::fprintf(stderr, "bench_estimation: unknown option '%s' (usage: bench_estimation [MISSION.yaml] [--duration S] [--seed N])\n", a.c_str());
      return 2;
    } else mission = a;
  }
  constexpr double t0 = 30.0, t0_wind = 60.0;

  std::string tmpl = (fs::temp_directory_path() / "tern_bench_estimation_XXXXXX").string();
  if (::mkdtemp(tmpl.data()) == nullptr) {
    std::fprintf(stderr, "bench_estimation: mkdtemp failed in %s\n", fs::temp_directory_path().c_str());
    return 1;
  }
  const fs::path logs = tmpl;

  tern::core::HostOptions o;
  o.quiet = true;
  o.seed = seed;
  o.duration = duration;
  o.log_dir = logs;
  tern::core::Host host(tern::core::load_config(mission), o);
  host.build();

  enum { N, E, ALT, U, V, W, ROLL, PITCH, YAW, COURSE, VA, WIND_N, WIND_E, COUNT };
  Rms est[COUNT];
  Rms gnss_n, gnss_e, gnss_alt, gnss_vn, gnss_ve, gnss_vd;
  std::uint64_t last_state_seq = 0, last_gnss_seq = 0;
  const tern::OutputBase *state_src = nullptr, *truth_src = nullptr, *gnss_src = nullptr;
  std::unique_ptr<GeographicLib::LocalCartesian> geo;
  host.set_tick_observer([&](tern::Nanos now) {
    if (state_src == nullptr) {
      state_src = host.topic_source("state");
      truth_src = host.topic_source("truth");
      gnss_src = host.topic_source("gnss");
    }
    const auto* x = latest<tern::msg::State>(state_src);
    const auto* t = latest<tern::msg::State>(truth_src);
    if (t == nullptr) return;
    const double s = static_cast<double>(now) * 1e-9;
    if (geo == nullptr) geo = std::make_unique<GeographicLib::LocalCartesian>(t->origin_lat, t->origin_lon, t->origin_alt);
    if (s < t0) return;
    // the raw GNSS error of this run: each new fix against the truth of the same tick
    if (const auto* g = latest<tern::msg::Gnss>(gnss_src); g != nullptr && gnss_src->sequence() != last_gnss_seq) {
      last_gnss_seq = gnss_src->sequence();
      double east = 0, north = 0, up = 0;
      geo->Forward(g->lat, g->lon, g->alt, east, north, up);
      gnss_n.add(north - t->p_n);
      gnss_e.add(east - t->p_e);
      gnss_alt.add(up + t->p_d);
      gnss_vn.add(g->vel.x() - t->v_n);
      gnss_ve.add(g->vel.y() - t->v_e);
      gnss_vd.add(g->vel.z() - t->v_d);
    }
    if (x == nullptr || !x->valid || state_src->sequence() == last_state_seq) return;
    last_state_seq = state_src->sequence();
    est[N].add(x->p_n - t->p_n);
    est[E].add(x->p_e - t->p_e);
    est[ALT].add(x->p_d - t->p_d);
    est[U].add(x->u - t->u);
    est[V].add(x->v - t->v);
    est[W].add(x->w - t->w);
    est[ROLL].add(wrap_pi(x->phi - t->phi));
    est[PITCH].add(wrap_pi(x->theta - t->theta));
    est[YAW].add(wrap_pi(x->psi - t->psi));
    est[COURSE].add(wrap_pi(x->chi - t->chi));
    est[VA].add(x->Va - t->Va);
    if (s >= t0_wind) {
      est[WIND_N].add(x->w_n - t->w_n);
      est[WIND_E].add(x->w_e - t->w_e);
    }
  });
  const auto r = host.fly();
  host.set_tick_observer({});
  std::error_code ec;
  fs::remove_all(logs, ec);
  if (!r.ok) {
    std::fprintf(stderr, "bench_estimation: the flight failed: %s\n", r.end_reason.c_str());
    return 1;
  }

  const double wind = std::hypot(est[WIND_N].value(), est[WIND_E].value());
  struct Row {
    const char* name;
    double rmse, rosplane, target, gnss;
    const char* target_text;
  };
  const double nan = std::nan("");
  const Row rows[] = {
      {"north m", est[N].value(), 0.325, gnss_n.value(), gnss_n.value(), "<= raw GNSS"},
      {"east m", est[E].value(), 0.258, gnss_e.value(), gnss_e.value(), "<= raw GNSS"},
      {"altitude m", est[ALT].value(), 0.894, 0.894, gnss_alt.value(), "< 0.894"},
      {"Vel-X (u) m/s", est[U].value(), 0.045, 0.045, nan, "< 0.045"},
      {"Vel-Y (v) m/s", est[V].value(), 0.089, 0.089, nan, "< 0.089"},
      {"Vel-Z (w) m/s", est[W].value(), 0.105, 0.105, nan, "< 0.105"},
      {"roll deg", est[ROLL].value() * kDeg, 0.189, 0.189, nan, "< 0.189"},
      {"pitch deg", est[PITCH].value() * kDeg, 0.074, 0.074, nan, "< 0.074"},
      {"course deg", est[COURSE].value() * kDeg, 0.112, 0.112, nan, "< 0.112"},
      {"wind (after 60 s) m/s", wind, nan, 0.5, nan, "< 0.5"},
      {"yaw deg", est[YAW].value() * kDeg, nan, nan, nan, ""},
      {"airspeed m/s", est[VA].value(), nan, nan, nan, ""},
  };
  std::printf("bench_estimation: %s, %.0f s, seed %llu, RMSE from t = %.0f s over %zu estimates\n", mission.c_str(), duration,
              static_cast<unsigned long long>(seed), t0, est[N].n);
  std::printf("%-24s %10s %10s %12s %10s %6s\n", "quantity", "tern", "ROSplane", "target", "raw GNSS", "met");
  nlohmann::ordered_json j;
  j["mission"] = mission;
  j["duration_s"] = duration;
  j["seed"] = seed;
  j["window_start_s"] = t0;
  j["wind_window_start_s"] = t0_wind;
  int missed = 0;
  for (const auto& row : rows) {
    const bool has_target = !std::isnan(row.target);
    const bool met = has_target && row.rmse <= row.target;
    if (has_target && !met) ++missed;
    auto cell = [](double v) { return std::isnan(v) ? std::string("-") : fmt::format("{:.3f}", v); };
    std::printf("%-24s %10s %10s %12s %10s %6s\n", row.name, cell(row.rmse).c_str(), cell(row.rosplane).c_str(), row.target_text,
                cell(row.gnss).c_str(), has_target ? (met ? "yes" : "NO") : "");
    auto& e = j["rmse"][row.name];
    e["tern"] = row.rmse;
    if (!std::isnan(row.rosplane)) e["rosplane_2_0"] = row.rosplane;
    if (has_target) {
      e["target"] = row.target;
      e["met"] = met;
    }
    if (!std::isnan(row.gnss)) e["raw_gnss"] = row.gnss;
  }
  j["raw_gnss_velocity_rmse_mps"] = {gnss_vn.value(), gnss_ve.value(), gnss_vd.value()};
  j["targets_missed"] = missed;
  std::printf("raw GNSS velocity error (n, e, d) m/s: %.3f %.3f %.3f; targets missed: %d\n", gnss_vn.value(), gnss_ve.value(),
              gnss_vd.value(), missed);
  fs::create_directories(TERN_BENCH_RESULTS_DIR);
  std::ofstream(fs::path(TERN_BENCH_RESULTS_DIR) / "bench_estimation.json") << j.dump(2) << "\n";
  std::printf("wrote %s/bench_estimation.json\n", TERN_BENCH_RESULTS_DIR);
  return 0;
}
