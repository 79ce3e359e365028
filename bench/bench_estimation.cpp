// bench_estimation: the estimator accuracy benchmark. Flies each mission (default: the hourglass
// of the default mission and configs/missions/aggressive.yaml) under each simulator sensor
// profile (default: realistic, then rosflight) over several seeds, in-process with sim_aero and
// estimator_ekf in the loop, and prints one table per mission and profile: tern's RMSE (median
// and worst seed), the raw GNSS fixes' RMSE computed the same way (median and worst seed), and
// ROSplane 2.0's published row, with divergences, filter resets and crashes counted. Writes
// bench/results/bench_estimation.json.
//
// Usage: bench_estimation [MISSION.yaml ...] [--seeds N] [--duration S] [--profiles a,b]
//                         [--set INSTANCE.PARAM=VALUE ...] [--per-seed]  (one line per seed after each table)
//                         [--gnss-outage START,END]  (no GNSS fix from START to END s: dead reckoning)
//                         [--paper]  (ROSplane 2.0's paper's world, below)
//
// --paper flies the world of ROSplane 2.0's paper's table (issue 61): the default mission (unless
// missions are named) under the rosflight profile, ROSflight's standalone simulator, with the
// estimator set up as a user of that world sets it up: its installation as measured (IMU and
// GNSS antenna at the CG, as the profile puts them: ekf.imu_position, ekf.gnss_antenna_position
// [0, 0, 0]) and its GNSS velocity noise as ROSplane's own estimator.yaml has it for that
// simulator (sigma_vn_gps, sigma_ve_gps 0.007 m/s, sigma_vd_gps 0.01 m/s: ekf.gnss_vel_noise_h/v,
// the floor under the receiver's reported speed accuracy, so that the receiver's own report,
// s_acc 0.01 m/s, is the noise fused; the default 0.3 m/s is PX4's EKF2_GPS_V_NOISE for a real
// receiver's correlated velocity). Settings given with --set come after these and override them.
// Its error window starts at 60 s, as the paper's table's does (kT0Paper; 30 s otherwise).
// It writes bench_estimation_paper.json (bench_estimation.json keeps the default campaign).
//
// How each figure is made (the same for tern and for raw GNSS): every new estimate (state topic)
// from t0 = 30 s on (after takeoff and climb; --paper: 60 s) is compared with the truth of the same tick, both
// in the simulator's frame (common_frame.hpp: the estimator's origin, its first GNSS fix, mapped
// to the simulator's origin); the raw-GNSS row compares the latest fix at that tick with the
// same truth (so a late fix counts as late). Wind from 60 s; course where the true ground speed
// is at least 5 m/s (the raw-GNSS course: the latest fix's velocity direction, atan2(v_e, v_n),
// as the estimate's and the truth's). Angles wrapped to [-pi, pi).
// Altitude is the estimate's height in the common frame (so it carries the estimator's origin,
// its first fix, off by the receiver's vertical error); "height above home" compares the change
// of height since the first valid estimate on the ground (estimate, truth and raw fix alike):
// the height a mission's altitudes are flown by.
// u, v, w compare the estimate's body velocity (its velocity in its own attitude) with the
// truth's, so they carry the attitude error too (Va 25 m/s x 1 deg of yaw = 0.44 m/s of v);
// "vel. error body x/y/z" is the velocity error alone, the estimate's NED velocity minus the
// truth's, in the true body axes.
// With --gnss-outage the outage's errors count in the RMSE too; its own rows give the drift at
// its end and the largest error 5 to 20 s after the fixes return.
// The height above home has a second baseline from the same ticks: the barometer alone (ISA
// pressure altitude, its change since the same first valid estimate; thermal drift and
// static-port error included).
// A flight diverged when its horizontal position error exceeded 50 m or its attitude error
// 30 deg at any compared tick after initialisation. ROSplane 2.0's row comes from a different
// estimator and a hardware flight: a reference, not a comparison on the same data.
// Consistency: the normalised estimation error squared, NEES = e^T P^-1 e, of position (NED, in
// the common frame), velocity (NED) and attitude (the body-frame rotation error, the EKF's
// error-state coordinates), each over its 3 dimensions, from the published covariance diagonal
// (State.P_diag: correlations between the axes of a block are left out). A consistent filter
// averages 1 per dimension; the target band is [0.5, 2].
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "config/cli_overrides.hpp"
#include "tern/common_frame.hpp"
#include "config/config.hpp"
#include "config/error.hpp"
#include "flight/host.hpp"
#include "tern/math.hpp"
#include "tern/msg/all.hpp"
#include "tern/port.hpp"
#include "tern/atmosphere.hpp"

namespace fs = std::filesystem;

namespace {
constexpr double kT0 = 30.0, kT0Wind = 60.0;  // s: the error window's start (--paper: kT0Paper), the wind's
constexpr double kT0Paper = 60.0;             // s: the paper's table counts its error from 60 s (issue 61)
// Course only while the aircraft moves: at rest it is undefined, and waiting for its takeoff at
// 3 m/s (an aggressive seed rolled until 45 s in a 6-m/s wind) 0.1 m/s of velocity error across
// the track is 2 deg.
constexpr double kCourseMinGroundSpeed = 5.0;  // m/s, true ground speed
constexpr double kDivergedPosition = 50.0, kDivergedAttitude = 30.0 / tern::kDegPerRad;
using tern::wrap_pi;

struct Rms {
  double sum = 0;
  std::size_t n = 0;
  void add(double e) {
    if (std::isfinite(e)) {
      sum += e * e;
      ++n;
    }
  }
  double value() const { return n == 0 ? std::nan("") : std::sqrt(sum / static_cast<double>(n)); }
};

// The quantities of the table; the first kGnssRows also have a raw-GNSS figure.
enum Q { N, E, HORIZ, ALT, HOME, U, V, W, ROLL, PITCH, YAW, COURSE, WIND, VEL_X, VEL_Y, VEL_Z, kQ };
constexpr int kGnssRows = 5;
struct QInfo {
  const char* name;
  double scale;     // to the printed unit
  double rosplane;  // ROSplane 2.0 paper (NaN: not given)
};
const QInfo kInfo[kQ] = {
    {"north m", 1, 0.325},
    {"east m", 1, 0.258},
    {"horizontal m", 1, std::nan("")},
    {"altitude m", 1, 0.894},
    {"height above home m", 1, std::nan("")},
    {"u m/s", 1, 0.045},
    {"v m/s", 1, 0.089},
    {"w m/s", 1, 0.105},
    {"roll deg", tern::kDegPerRad, 0.189},
    {"pitch deg", tern::kDegPerRad, 0.074},
    {"yaw deg", tern::kDegPerRad, std::nan("")},
    {"course deg", tern::kDegPerRad, 0.112},
    {"wind (from 60 s) m/s", 1, std::nan("")},
    {"vel. error body x m/s", 1, std::nan("")},
    {"vel. error body y m/s", 1, std::nan("")},
    {"vel. error body z m/s", 1, std::nan("")},
};

// NEES blocks: position, velocity, attitude (3 dimensions each).
enum Block { NEES_P, NEES_V, NEES_ATT, kBlocks };
const char* const kBlockName[kBlocks] = {"position", "velocity", "attitude"};
struct Mean {
  double sum = 0;
  std::size_t n = 0;
  void add(double e) {
    if (std::isfinite(e)) {
      sum += e;
      ++n;
    }
  }
  double value() const { return n == 0 ? std::nan("") : sum / static_cast<double>(n); }
};

// Where the aircraft stood at the first valid estimate (on the ground, before takeoff): the
// truth's and the estimate's down position and the raw GNSS fix's (m, NED down), and the
// barometer's ISA pressure altitude (m, up), for the height above home.
struct Home {
  bool set = false;
  double truth_d = 0, estimate_d = 0, fix_d = std::nan(""), baro_h = std::nan("");
};

// A GNSS outage flown on purpose (--gnss-outage A,B: the simulator's gnss_nan window): the
// horizontal error (common frame) at the last estimate before the first fix after it (the
// drift), and the largest error from 5 to 20 s after it (has the estimate come back and stayed?).
struct Outage {
  double start = std::nan(""), end = std::nan("");
  bool on() const { return std::isfinite(start); }
};
struct OutageResult {
  double drift = std::nan(""), after_max = 0.0;
};

struct Flight {
  std::uint64_t seed = 0;
  Home home;
  OutageResult outage;
  Rms est[kQ], gnss[kGnssRows];
  Rms baro_home;       // the barometer alone's height above home, m
  Rms gnss_course;     // the latest fix's course (its NED velocity) against the true one, rad
  Mean nees[kBlocks];  // per dimension
  bool diverged = false, crashed = false, failed = false;
  double diverged_at = std::nan("");  // s: first tick beyond the divergence limits
  double filter_resets = 0, gnss_resets = 0, mag_resets = 0, inflations = 0;
  std::string end_reason;
};

// e^T diag(P)^-1 e / 3 for the block of P_diag starting at `first`.
double nees_per_dim(const Eigen::Vector3d& e, const std::array<double, 21>& P_diag, std::size_t first) {
  double s = 0;
  for (std::size_t i = 0; i < 3; ++i) s += e[static_cast<int>(i)] * e[static_cast<int>(i)] / P_diag[first + i];
  return s / 3.0;
}

template <class T>
const T* latest(const tern::OutputBase* src) {
  if (src == nullptr || src->sequence() == 0 || src->type().fingerprint != tern::reflect::fingerprint<T>()) return nullptr;
  return static_cast<const T*>(src->data());
}

// The config with every sim_aero instance's sensor_profile set, and the --set overrides.
tern::core::MissionConfig with_profile(const std::string& mission, const std::string& profile, const tern::core::CliOverrides& sets,
                                       const Outage& outage) {
  tern::core::MissionConfig mc = tern::core::load_config(mission);
  for (auto& inst : mc.plugins) {
    if (inst.plugin == "sim_aero") {
      tern::core::ParamSetting s;
      s.node = YAML::Node(profile);
      s.file = mission;
      s.field = "bench_estimation --profiles";
      inst.params["sensor_profile"] = s;
      if (outage.on()) {  // a new setting: YAML nodes are references, s.node is now in params
        tern::core::ParamSetting o;
        o.node = YAML::Load(fmt::format("[{}, {}]", outage.start, outage.end));
        o.file = mission;
        o.field = "bench_estimation --gnss-outage";
        inst.params["gnss_nan"] = o;
      }
    }
  }
  tern::core::apply_overrides(mc, sets);  // as `tern fly --set`
  return mc;
}

// The outage figures of one tick at flight time s with horizontal error e.
void add_outage_tick(OutageResult& r, const Outage& o, double s, double e) {
  if (!o.on() || s < o.start) return;
  if (s < o.end)
    r.drift = e;
  else if (s >= o.end + 5.0 && s < o.end + 20.0)
    r.after_max = std::max(r.after_max, e);
}

// Estimate and raw-sensor errors of one tick (all against the truth of the tick, in its frame).
void add_tick(Flight& f, const tern::msg::State& x, const tern::msg::State& t, const tern::msg::Gnss* g, const tern::msg::Baro* b, double s,
              const Outage& outage) {
  const Eigen::Vector3d p = tern::estimate_in_truth_frame(x, t);
  const double dn = p.x() - t.p_n, de = p.y() - t.p_e;
  add_outage_tick(f.outage, outage, s, std::hypot(dn, de));
  f.est[N].add(dn);
  f.est[E].add(de);
  f.est[HORIZ].add(std::hypot(dn, de));
  f.est[ALT].add(t.p_d - p.z());
  f.est[HOME].add((t.p_d - f.home.truth_d) - (x.p_d - f.home.estimate_d));
  f.est[U].add(x.u - t.u);
  f.est[V].add(x.v - t.v);
  f.est[W].add(x.w - t.w);
  f.est[ROLL].add(wrap_pi(x.phi - t.phi));
  f.est[PITCH].add(wrap_pi(x.theta - t.theta));
  f.est[YAW].add(wrap_pi(x.psi - t.psi));
  if (t.Vg >= kCourseMinGroundSpeed) f.est[COURSE].add(wrap_pi(x.chi - t.chi));
  if (s >= kT0Wind) f.est[WIND].add(std::hypot(x.w_n - t.w_n, x.w_e - t.w_e));
  const Eigen::Vector3d dv_body = t.quat.conjugate() * Eigen::Vector3d(x.v_n - t.v_n, x.v_e - t.v_e, x.v_d - t.v_d);
  f.est[VEL_X].add(dv_body.x());
  f.est[VEL_Y].add(dv_body.y());
  f.est[VEL_Z].add(dv_body.z());
  const double att =
      std::max({std::fabs(wrap_pi(x.phi - t.phi)), std::fabs(wrap_pi(x.theta - t.theta)), std::fabs(wrap_pi(x.psi - t.psi))});
  if ((!(std::hypot(dn, de) <= kDivergedPosition) || !(att <= kDivergedAttitude)) && !f.diverged) {
    f.diverged = true;
    f.diverged_at = s;
  }
  if (x.P_diag[0] > 0.0) {
    f.nees[NEES_P].add(nees_per_dim(p - Eigen::Vector3d(t.p_n, t.p_e, t.p_d), x.P_diag, tern::msg::State::P_position));
    f.nees[NEES_V].add(nees_per_dim(Eigen::Vector3d(x.v_n - t.v_n, x.v_e - t.v_e, x.v_d - t.v_d), x.P_diag, tern::msg::State::P_velocity));
    const Eigen::AngleAxisd d(x.quat.conjugate() * t.quat);  // q_true = q (x) exp(dtheta)
    f.nees[NEES_ATT].add(nees_per_dim(d.angle() * d.axis(), x.P_diag, tern::msg::State::P_attitude));
  }
  if (g != nullptr) {
    const Eigen::Vector3d q = tern::fix_in_truth_frame(*g, t);
    f.gnss[N].add(q.x() - t.p_n);
    f.gnss[E].add(q.y() - t.p_e);
    f.gnss[HORIZ].add(std::hypot(q.x() - t.p_n, q.y() - t.p_e));
    f.gnss[ALT].add(t.p_d - q.z());
    f.gnss[HOME].add((t.p_d - f.home.truth_d) - (q.z() - f.home.fix_d));
    if (t.Vg >= kCourseMinGroundSpeed) f.gnss_course.add(wrap_pi(std::atan2(g->vel.y(), g->vel.x()) - t.chi));
  }
  if (b != nullptr) f.baro_home.add((t.p_d - f.home.truth_d) + (tern::isa_pressure_altitude(b->pressure) - f.home.baro_h));
}

double summary_number(const nlohmann::json& j, const char* instance, const char* key) {
  const auto& i = j["instances"];
  if (!i.contains(instance) || !i[instance].contains(key) || !i[instance][key].is_number()) return 0.0;
  return i[instance][key].get<double>();
}

Flight fly(const std::string& mission, const std::string& profile, const tern::core::CliOverrides& sets, std::uint64_t seed,
           double duration, double t0, const Outage& outage, const fs::path& logs) {
  tern::core::HostOptions o;
  o.quiet = true;
  o.seed = seed;
  if (duration > 0) o.duration = duration;
  o.log_dir = logs;
  tern::core::Host host(with_profile(mission, profile, sets, outage), o);
  host.build();
  Flight f;
  f.seed = seed;
  std::uint64_t last_seq = 0;
  const tern::OutputBase *state_src = nullptr, *truth_src = nullptr, *gnss_src = nullptr, *baro_src = nullptr;
  const int observer = host.add_tick_observer([&](tern::Nanos now) {
    if (state_src == nullptr) {
      state_src = host.topic_source("state");
      truth_src = host.topic_source("truth");
      gnss_src = host.topic_source("gnss");
      baro_src = host.topic_source("baro");
    }
    const auto* x = latest<tern::msg::State>(state_src);
    const auto* t = latest<tern::msg::State>(truth_src);
    const double s = tern::to_seconds(now);
    if (x == nullptr || t == nullptr || !x->valid) return;
    if (!f.home.set) {
      const auto* g = latest<tern::msg::Gnss>(gnss_src);
      const auto* b = latest<tern::msg::Baro>(baro_src);
      f.home = {true, t->p_d, x->p_d, g ? tern::fix_in_truth_frame(*g, *t).z() : std::nan(""),
                b ? tern::isa_pressure_altitude(b->pressure) : std::nan("")};
    }
    if (s < t0 || state_src->sequence() == last_seq) return;
    last_seq = state_src->sequence();
    add_tick(f, *x, *t, latest<tern::msg::Gnss>(gnss_src), latest<tern::msg::Baro>(baro_src), s, outage);
  });
  const auto r = host.fly();
  host.remove_tick_observer(observer);
  f.failed = !r.ok;
  f.end_reason = r.end_reason;
  std::ifstream in(r.run_dir / "summary.json");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (!j.is_discarded()) {
    f.crashed = summary_number(j, "sim", "sim_crashed") > 0;
    f.filter_resets = summary_number(j, "ekf", "filter_resets");
    f.gnss_resets = summary_number(j, "ekf", "gnss_resets");
    f.mag_resets = summary_number(j, "ekf", "mag_resets");
    f.inflations = summary_number(j, "ekf", "inflations");
  }
  return f;
}

struct Spread {
  double median = std::nan(""), worst = std::nan("");
};
Spread spread(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return {};
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return {n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]), v.back()};
}

std::string cell(double v) { return std::isfinite(v) ? fmt::format("{:.3f}", v) : std::string("-"); }

// One line per seed: where the median hides a bad flight ("outage m": the drift at the end of the
// GNSS outage, with --gnss-outage; "baro m": the barometer alone's height above home).
void print_seeds(const std::vector<Flight>& flights) {
  std::printf("  %4s %9s %8s %8s %8s %8s %9s %8s %10s %8s %8s %8s %7s %7s %7s %s\n", "seed", "horiz m", "alt m", "home m", "baro m",
              "roll deg", "pitch deg", "yaw deg", "course deg", "wind m/s", "outage m", "NEES att", "resets", "inflat", "diverge", "end");
  for (const auto& f : flights) {
    std::printf("  %4llu %9.3f %8.3f %8.3f %8.3f %8.3f %9.3f %8.3f %10.3f %8.3f %8s %8.1f %7.0f %7.0f %7s %s%s\n",
                static_cast<unsigned long long>(f.seed), f.est[HORIZ].value(), f.est[ALT].value(), f.est[HOME].value(), f.baro_home.value(),
                f.est[ROLL].value() * tern::kDegPerRad, f.est[PITCH].value() * tern::kDegPerRad, f.est[YAW].value() * tern::kDegPerRad,
                f.est[COURSE].value() * tern::kDegPerRad, f.est[WIND].value(), cell(f.outage.drift).c_str(), f.nees[NEES_ATT].value(),
                f.filter_resets + f.gnss_resets + f.mag_resets, f.inflations,
                f.diverged ? fmt::format("{:.1f}s", f.diverged_at).c_str() : "-", f.end_reason.c_str(), f.crashed ? " (crashed)" : "");
  }
}

// The outage rows: drift at the end of the outage and the largest error 5-20 s after it.
void report_outage(nlohmann::ordered_json& j, const Outage& outage, const std::vector<Flight>& flights) {
  std::vector<double> drift, after;
  for (const auto& f : flights) {
    drift.push_back(f.outage.drift);
    after.push_back(f.outage.after_max);
  }
  const Spread d = spread(drift), a = spread(after);
  std::printf(
      "  GNSS outage %.0f-%.0f s: drift at its end %s m median, %s m worst; largest error 5-20 s after: "
      "%s m median, %s m worst\n",
      outage.start, outage.end, cell(d.median).c_str(), cell(d.worst).c_str(), cell(a.median).c_str(), cell(a.worst).c_str());
  auto& r = j["gnss_outage"];
  r["window_s"] = {outage.start, outage.end};
  r["drift_median_m"] = d.median;
  r["drift_worst_m"] = d.worst;
  r["after_max_median_m"] = a.median;
  r["after_max_worst_m"] = a.worst;
}

nlohmann::ordered_json report(const std::string& mission, const std::string& profile, const std::vector<Flight>& flights, double t0,
                              const Outage& outage) {
  int diverged = 0, crashed = 0, failed = 0;
  double filter_resets = 0, gnss_resets = 0, mag_resets = 0, inflations = 0;
  for (const auto& f : flights) {
    inflations += f.inflations;
    diverged += f.diverged;
    crashed += f.crashed;
    failed += f.failed;
    filter_resets += f.filter_resets;
    gnss_resets += f.gnss_resets;
    mag_resets += f.mag_resets;
  }
  std::printf("\n%s, sensor profile %s, %zu seeds (RMSE from %.0f s; worst = the worst seed)\n", mission.c_str(), profile.c_str(),
              flights.size(), t0);
  std::printf("  %-22s %10s %10s %11s %11s %10s\n", "quantity", "tern med", "tern worst", "GNSS med", "GNSS worst", "ROSplane*");
  nlohmann::ordered_json j;
  j["mission"] = mission;
  j["sensor_profile"] = profile;
  j["seeds"] = flights.size();
  for (int q = 0; q < kQ; ++q) {
    std::vector<double> tv, gv;
    for (const auto& f : flights) {
      tv.push_back(f.est[q].value() * kInfo[q].scale);
      if (q < kGnssRows) gv.push_back(f.gnss[q].value() * kInfo[q].scale);
      if (q == COURSE) gv.push_back(f.gnss_course.value() * kInfo[q].scale);
    }
    const Spread t = spread(tv), g = spread(gv);
    std::printf("  %-22s %10s %10s %11s %11s %10s\n", kInfo[q].name, cell(t.median).c_str(), cell(t.worst).c_str(), cell(g.median).c_str(),
                cell(g.worst).c_str(), cell(kInfo[q].rosplane).c_str());
    auto& r = j["rmse"][kInfo[q].name];
    r["tern_median"] = t.median;
    r["tern_worst"] = t.worst;
    if (q < kGnssRows || q == COURSE) {
      r["raw_gnss_median"] = g.median;
      r["raw_gnss_worst"] = g.worst;
    }
    if (std::isfinite(kInfo[q].rosplane)) r["rosplane_2_0_paper"] = kInfo[q].rosplane;
  }
  for (int b = 0; b < kBlocks; ++b) {
    std::vector<double> v;
    for (const auto& f : flights) v.push_back(f.nees[b].value());
    const Spread sp = spread(v);
    double best = std::nan(""), sum = 0.0;
    int n = 0;
    for (double x : v) {
      if (!std::isfinite(x)) continue;
      if (!(x >= best)) best = x;
      sum += x;
      ++n;
    }
    const double mean = n > 0 ? sum / n : std::nan("");  // the "averages over the flights"
    std::printf("  NEES per dim %-9s %10s %10s (lowest %s, mean %s; target 0.5..2)\n", kBlockName[b], cell(sp.median).c_str(),
                cell(sp.worst).c_str(), cell(best).c_str(), cell(mean).c_str());
    auto& r = j["nees_per_dimension"][kBlockName[b]];
    r["mean"] = mean;
    r["median"] = sp.median;
    r["highest"] = sp.worst;
    r["lowest"] = best;
  }
  std::vector<double> baro;
  for (const auto& f : flights) baro.push_back(f.baro_home.value());
  const Spread b = spread(baro);
  std::printf("  baseline: the barometer alone (ISA) gives the height above home to %s m median, %s m worst\n", cell(b.median).c_str(),
              cell(b.worst).c_str());
  j["rmse"][kInfo[HOME].name]["baro_alone_median"] = b.median;
  j["rmse"][kInfo[HOME].name]["baro_alone_worst"] = b.worst;
  if (outage.on()) report_outage(j, outage, flights);
  std::printf(
      "  divergences %d, crashes %d, failed flights %d; filter resets %.0f, GNSS resets %.0f, mag resets %.0f, "
      "covariance inflations %.0f (all seeds)\n",
      diverged, crashed, failed, filter_resets, gnss_resets, mag_resets, inflations);
  j["divergences"] = diverged;
  j["crashes"] = crashed;
  j["failed_flights"] = failed;
  j["filter_resets"] = filter_resets;
  j["gnss_resets"] = gnss_resets;
  j["mag_resets"] = mag_resets;
  j["covariance_inflations"] = inflations;
  return j;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string x; std::getline(ss, x, ',');) {
    if (!x.empty()) out.push_back(x);
  }
  return out;
}
}  // namespace

int main(int argc, char** argv) {
  const std::string dir = std::string(TERN_SOURCE_DIR) + "/configs/missions/";
  std::vector<std::string> missions, profiles = {"realistic", "rosflight"};
  int seeds = 10;
  double duration = 300.0;
  tern::core::CliOverrides sets;
  const char* usage =
      "usage: bench_estimation [MISSION.yaml ...] [--seeds N] [--duration S] [--profiles a,b] [--set INSTANCE.PARAM=VALUE ...] "
      "[--per-seed] [--gnss-outage START,END] [--paper]";
  bool per_seed = false, paper = false;
  Outage outage;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seeds" && i + 1 < argc)
      seeds = std::atoi(argv[++i]);
    else if (a == "--duration" && i + 1 < argc)
      duration = std::atof(argv[++i]);
    else if (a == "--profiles" && i + 1 < argc)
      profiles = split(argv[++i]);
    else if (a == "--per-seed")
      per_seed = true;
    else if (a == "--paper")
      paper = true;
    else if (a == "--gnss-outage" && i + 1 < argc) {
      const auto w = split(argv[++i]);
      if (w.size() == 2) outage = {std::atof(w[0].c_str()), std::atof(w[1].c_str())};
      if (w.size() != 2 || !(outage.start >= kT0) || !(outage.end > outage.start)) {
        std::fprintf(stderr, "bench_estimation: --gnss-outage wants START,END in s with %.0f <= START < END, got '%s'\n", kT0, argv[i]);
        return 2;
      }
    } else if (a == "--set" && i + 1 < argc)
      sets.sets.push_back(argv[++i]);
    else if (a.rfind("--", 0) == 0) {
      std::fprintf(stderr, "bench_estimation: unknown option '%s' (%s)\n", a.c_str(), usage);
      return 2;
    } else
      missions.push_back(a);
  }
  if (paper) {
    profiles = {"rosflight"};
    if (missions.empty()) missions = {dir + "default.yaml"};
    sets.sets.insert(sets.sets.begin(), {"ekf.imu_position=[0,0,0]", "ekf.gnss_antenna_position=[0,0,0]", "ekf.gnss_vel_noise_h=0.007",
                                         "ekf.gnss_vel_noise_v=0.01"});
  }
  if (missions.empty()) missions = {dir + "default.yaml", dir + "aggressive.yaml"};
  if (seeds < 1 || !(duration > kT0Wind) || profiles.empty()) {
    std::fprintf(stderr, "bench_estimation: need --seeds >= 1, --duration > %.0f s and a profile (%s)\n", kT0Wind, usage);
    return 2;
  }
  try {  // each mission with the settings configured once: one clear line now rather than a throw mid-campaign
    for (const auto& mission : missions) {
      tern::core::HostOptions describe;
      describe.describing = true;
      describe.quiet = true;
      tern::core::Host host(with_profile(mission, profiles.front(), sets, outage), describe);
      host.build();
    }
  } catch (const tern::core::ConfigError& e) {
    std::fprintf(stderr, "bench_estimation: %s\n", e.what());
    return 2;
  }
  std::string tmpl = (fs::temp_directory_path() / "tern_bench_estimation_XXXXXX").string();
  if (::mkdtemp(tmpl.data()) == nullptr) {
    std::fprintf(stderr, "bench_estimation: mkdtemp failed in %s\n", fs::temp_directory_path().c_str());
    return 1;
  }
  const fs::path logs = tmpl;
  std::printf("bench_estimation: %.0f s flights, seeds 1..%d; estimate and raw GNSS vs truth in the simulator's frame\n", duration, seeds);
  std::printf("(*) ROSplane 2.0 paper: its own estimator on a hardware flight; a reference, not a comparison on these data\n");
  nlohmann::ordered_json j;
  j["duration_s"] = duration;
  const double t0 = paper ? kT0Paper : kT0;
  j["window_start_s"] = t0;
  j["wind_window_start_s"] = kT0Wind;
  if (paper) j["paper_world"] = true;
  for (const auto& set : sets.sets) j["settings"].push_back(set);
  j["divergence"] =
      fmt::format("horizontal error > {} m or attitude error > {} deg", kDivergedPosition, kDivergedAttitude * tern::kDegPerRad);
  for (const auto& mission : missions) {
    for (const auto& profile : profiles) {
      std::vector<Flight> flights;
      for (int s = 1; s <= seeds; ++s)
        flights.push_back(fly(mission, profile, sets, static_cast<std::uint64_t>(s), duration, t0, outage, logs));
      j["runs"].push_back(report(fs::path(mission).stem().string(), profile, flights, t0, outage));
      if (per_seed) print_seeds(flights);
    }
  }
  std::error_code ec;
  fs::remove_all(logs, ec);
  fs::create_directories(TERN_BENCH_RESULTS_DIR);
  const char* out = paper ? "bench_estimation_paper.json" : "bench_estimation.json";
  std::ofstream(fs::path(TERN_BENCH_RESULTS_DIR) / out) << j.dump(2) << "\n";
  std::printf("\nwrote %s/%s\n", TERN_BENCH_RESULTS_DIR, out);
  return 0;
}
