// bench_estimator_ekf: cost and accuracy of the estimator_ekf filter on a scripted flight.
// Prints a table and writes bench/results/bench_estimator_ekf.json.
//
// Cost: the sensor stream of a 120 s flight (truth_sim.hpp: IMU 400 Hz, GNSS 10 Hz, baro and
// pitot 100 Hz, magnetometer 50 Hz) is generated first, then fed to the estimator while each call
// is timed: ns per IMU sample (propagation), per GNSS solution (position + velocity update), per
// baro, per pitot (differential pressure + zero-sideslip update), per magnetometer sample, and
// per IMU tick (everything handled in one host step). Targets: IMU tick median < 5 us (issue 4).
// Accuracy (kinematic truth flight, not the closed-loop sim_aero benchmark of issue 4): RMSE
// after 20 s of convergence, attitude RMSE in 60-degree-bank turns, drift at the end of a 30 s
// GNSS outage. With sim_aero in the build its sensor models are used (Gauss-Markov GNSS and
// magnetometer errors, bias walks), else those of truth_sim.hpp.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fly.hpp"
#ifdef TERN_EKF_HAVE_SIM_AERO
#include "sim_aero_feed.hpp"
#endif

using namespace tern;
using namespace tern::ekf;
using namespace tern::ekf::test;
using clk = std::chrono::steady_clock;

namespace {

struct Tick {
  msg::Imu imu;
  bool has_gnss = false, has_baro = false, has_pitot = false, has_mag = false;
  msg::Gnss gnss;
  msg::Baro baro;
  msg::DiffPressure pitot;
  msg::Mag mag;
};

struct Stat {
  std::vector<double> ns;
  double median() {
    if (ns.empty()) return 0.0;
    std::nth_element(ns.begin(), ns.begin() + ns.size() / 2, ns.end());
    return ns[ns.size() / 2];
  }
  double p99() {
    if (ns.empty()) return 0.0;
    const std::size_t k = ns.size() * 99 / 100;
    std::nth_element(ns.begin(), ns.begin() + k, ns.end());
    return ns[k];
  }
  double mean() const {
    double s = 0;
    for (double x : ns) s += x;
    return ns.empty() ? 0.0 : s / ns.size();
  }
};

template <class F>
double timed(F&& f) {
  const auto t0 = clk::now();
  f();
  return std::chrono::duration<double, std::nano>(clk::now() - t0).count();
}

}  // namespace

int main() {
  // ---- cost -----------------------------------------------------------------------------------
  TruthSim sim(mixed_flight());
  std::vector<Tick> ticks;
  const int n = 120 * 400;
  ticks.reserve(n);
  for (int i = 0; i < n; ++i) {
    sim.advance();
    Tick t;
    t.imu = sim.imu();
    if ((t.has_gnss = sim.gnss_due())) t.gnss = sim.gnss();
    if ((t.has_baro = sim.baro_due())) t.baro = sim.baro();
    if ((t.has_pitot = sim.pitot_due())) t.pitot = sim.pitot();
    if ((t.has_mag = sim.mag_due())) t.mag = sim.mag();
    ticks.push_back(t);
  }
  Stat imu, gnss, baro, pitot, mag, tick;
  Estimator est;
  for (int rep = 0; rep < 3; ++rep) {
    est.reset();
    for (const Tick& t : ticks) {
      const auto t0 = clk::now();
      const double a = timed([&] { est.add_imu(t.imu); });
      double b = 0, c = 0, d = 0, e = 0;
      if (t.has_gnss) b = timed([&] { est.add_gnss(t.gnss); });
      if (t.has_baro) c = timed([&] { est.add_baro(t.baro); });
      if (t.has_pitot) d = timed([&] { est.add_diff_pressure(t.pitot); });
      if (t.has_mag) e = timed([&] { est.add_mag(t.mag); });
      est.check_timeouts(t.imu.stamp);
      msg::State s;
      est.fill_state(s);
      const double all = std::chrono::duration<double, std::nano>(clk::now() - t0).count();
      if (rep == 0 || !est.initialized()) continue;  // first pass warms caches
      imu.ns.push_back(a);
      if (t.has_gnss) gnss.ns.push_back(b);
      if (t.has_baro) baro.ns.push_back(c);
      if (t.has_pitot) pitot.ns.push_back(d);
      if (t.has_mag) mag.ns.push_back(e);
      tick.ns.push_back(all);
    }
  }

  // ---- accuracy ---------------------------------------------------------------------------------
  Rms north, east, alt, u, v, w, roll, pitch, course, wind, att60;
  const char* sensors_used = "truth_sim.hpp";
  {
    TruthSim s2(mixed_flight());
    EstimatorConfig cfg;
#ifdef TERN_EKF_HAVE_SIM_AERO
    sensors_used = "sim_aero (tern::sim::Sensors defaults)";
    cfg.rho = 1.2682;
    SimAeroFeed feed(s2, 1, cfg.rho);
    const auto run = [&](Estimator& e, double seconds, auto on_step) { fly_sim_aero(s2, feed, e, seconds, {}, on_step); };
#else
    const auto run = [&](Estimator& e, double seconds, auto on_step) { fly(s2, e, seconds, {}, on_step); };
#endif
    Estimator e2(cfg);
    run(e2, 22.0, [](const Truth&, const Estimator&) {});
    run(e2, 108.0, [&](const Truth& t, const Estimator& x) {
      const NominalState& xs = x.filter().x();
      const Eigen::Vector3d p = truth_position(t, x, s2);
      north.add(xs.p.x() - p.x());
      east.add(xs.p.y() - p.y());
      alt.add(xs.p.z() - p.z());
      const Eigen::Vector3d vb = t.R.transpose() * t.v;
      const msg::State st = x.state();
      u.add(st.u - vb.x());
      v.add(st.v - vb.y());
      w.add(st.w - vb.z());
      roll.add(wrap_pi(st.phi - t.phi) * 180 / kPi);
      pitch.add((st.theta - t.theta) * 180 / kPi);
      course.add(wrap_pi(st.chi - std::atan2(t.v.y(), t.v.x())) * 180 / kPi);
      wind.add((xs.wind - s2.options().wind).norm());
      if (std::fabs(t.phi) > 55.0 * kPi / 180) att60.add(attitude_error(xs.q, t.q()) * 180 / kPi);
    });
  }
  double outage_drift = 0.0;
  {
    TruthSim s3(mixed_flight());
    Estimator e3;
    fly(s3, e3, 40.0);
    Hooks h;
    h.gnss = [](msg::Gnss&) { return false; };
    fly(s3, e3, 30.0, h);
    outage_drift = (e3.filter().x().p - truth_position(s3.truth(), e3, s3)).head<2>().norm();
  }

  std::printf("bench_estimator_ekf (kinematic truth flight, 120 s, %zu IMU ticks timed)\n", tick.ns.size());
  std::printf("%-40s %10s %10s %10s\n", "cost", "median ns", "p99 ns", "mean ns");
  const auto row = [](const char* name, Stat& s) { std::printf("%-40s %10.0f %10.0f %10.0f\n", name, s.median(), s.p99(), s.mean()); };
  row("imu sample (propagation)", imu);
  row("gnss (position + velocity update)", gnss);
  row("baro (altitude update)", baro);
  row("pitot (diff. pressure + sideslip)", pitot);
  row("mag (3-axis update in the air)", mag);
  row("imu tick (all of one step)  target 5000", tick);
  std::printf("\n%-40s %10s   (sensors: %s)\n", "accuracy (after 20 s)", "RMSE", sensors_used);
  std::printf("%-40s %10.3f\n%-40s %10.3f\n%-40s %10.3f\n", "north m", north.rms(), "east m", east.rms(), "altitude m", alt.rms());
  std::printf("%-40s %10.4f\n%-40s %10.4f\n%-40s %10.4f\n", "u m/s", u.rms(), "v m/s", v.rms(), "w m/s", w.rms());
  std::printf("%-40s %10.4f\n%-40s %10.4f\n%-40s %10.4f\n", "roll deg", roll.rms(), "pitch deg", pitch.rms(), "course deg", course.rms());
  std::printf("%-40s %10.4f\n%-40s %10.4f\n%-40s %10.3f\n", "wind m/s", wind.rms(), "attitude in 60-deg bank deg", att60.rms(),
              "drift after 30 s GNSS outage m", outage_drift);

  std::string j = "{\n";
  const auto add = [&j](const std::string& k, double v, bool last = false) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "  \"%s\": %.6g%s\n", k.c_str(), v, last ? "" : ",");
    j += buf;
  };
  add("imu_propagation_median_ns", imu.median());
  add("gnss_update_median_ns", gnss.median());
  add("baro_update_median_ns", baro.median());
  add("pitot_sideslip_update_median_ns", pitot.median());
  add("mag_update_median_ns", mag.median());
  add("imu_tick_median_ns", tick.median());
  add("imu_tick_p99_ns", tick.p99());
  add("imu_tick_mean_ns", tick.mean());
  add("rmse_north_m", north.rms());
  add("rmse_east_m", east.rms());
  add("rmse_altitude_m", alt.rms());
  add("rmse_u_mps", u.rms());
  add("rmse_v_mps", v.rms());
  add("rmse_w_mps", w.rms());
  add("rmse_roll_deg", roll.rms());
  add("rmse_pitch_deg", pitch.rms());
  add("rmse_course_deg", course.rms());
  add("rmse_wind_mps", wind.rms());
  add("rmse_attitude_60deg_bank_deg", att60.rms());
  add("gnss_outage_30s_drift_m", outage_drift);
  add("target_imu_tick_median_ns", 5000.0, true);
  j += "}\n";
  const std::filesystem::path dir(TERN_BENCH_RESULTS_DIR);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "bench_estimator_ekf.json") << j;
  std::printf("\nwrote %s\n", (dir / "bench_estimator_ekf.json").c_str());
  return 0;
}
