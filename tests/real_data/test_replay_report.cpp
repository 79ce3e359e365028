// The truth-free replay report (core/apps/replay/replay_report.hpp): on a synthetic run directory
// with known offsets (reference 1 deg off in roll, GNSS fixes 3 m east, NIS ratios with known
// percentiles, a valid -> invalid transition), with topics missing, with malformed files; its
// notes (a reference altitude on another datum, a rejected magnetometer, a NIS far below 1) on
// variants of it; and end to end on a short default-mission flight whose truth serves as the
// reference.
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "../test_process.hpp"
#include "../test_util.hpp"
#include "replay/replay_report.hpp"
#include "tern/atmosphere.hpp"
#include "tern/geodesy.hpp"
#include "tern/magnetic_model.hpp"
#include "tern/math.hpp"

using tern::core::make_replay_report;
using tern::core::ReplayReport;

namespace {

const tern::GeoPoint kOrigin{47.389, 8.034, 480.0};

void write_csv(const fs::path& p, const std::string& header, const std::vector<std::vector<double>>& rows) {
  fs::create_directories(p.parent_path());
  std::ofstream f(p);
  f << header << "\n";
  for (const auto& r : rows) {
    for (std::size_t i = 0; i < r.size(); ++i) f << (i ? "," : "") << fmt::format("{:.17g}", r[i]);
    f << "\n";
  }
}

/// The synthetic estimate: north at 10 m/s, 20 m up, roll 0.2 rad, yaw 179 deg (a reference 2 deg
/// more crosses +-180), wind (3, -4); valid from 1 s, invalid over [12, 12.5).
struct Truthy {
  static double p_n(double t) { return 10.0 * t; }
  static bool valid(double t) { return t >= 1.0 && !(t >= 12.0 && t < 12.5); }
};

fs::path synthetic_run(const std::string& name) {
  const fs::path run = test_dir() / name;
  fs::create_directories(run / "topics");
  std::vector<std::vector<double>> state, ref, innov, gnss;
  const double psi = 179.0 * tern::kRadPerDeg;
  for (int k = 0; k <= 200; ++k) {  // 10 Hz, 0 .. 20 s
    const double t = 0.1 * k;
    state.push_back({t, std::round(t * 1e9), Truthy::p_n(t), 0.0, -20.0, 10.0, 0.0, 0.0, 0.2, 0.05, psi, 3.0, -4.0, kOrigin.lat,
                     kOrigin.lon, kOrigin.alt, 1.0, Truthy::valid(t) ? 1.0 : 0.0, k == 50 ? NAN : 0.1});
  }
  write_csv(run / "topics/state.csv",
            "t [s],stamp [ns],p_n [m],p_e [m],p_d [m],v_n [m/s],v_e [m/s],v_d [m/s],phi [rad],theta [rad],psi [rad],w_n [m/s],w_e [m/s],"
            "origin_lat [deg],origin_lon [deg],origin_alt [m],origin_valid [bool],valid [bool],alpha [rad]",
            state);
  const tern::GeoOrigin frame(kOrigin);
  for (int k = 0; k <= 100; ++k) {  // 5 Hz: interpolated at the state's 10 Hz, each field between its own samples
    const double t = 0.2 * k;
    const tern::GeoPoint g = frame.to_geodetic(Eigen::Vector3d(Truthy::p_n(t), 0.0, -20.0 + 2.0));  // 2 m lower
    ref.push_back({t, std::round(t * 1e9), 0.2 - 1.0 * tern::kRadPerDeg, 0.05 + 0.5 * tern::kRadPerDeg,
                   std::remainder(psi + 2.0 * tern::kRadPerDeg, 2 * M_PI), g.lat, g.lon, g.alt, 10.0, 1.0, 0.0, 3.5, -4.0});
    if (k % 3 == 2) ref.back()[2] = ref.back()[3] = ref.back()[4] = NAN;  // merged sources: no attitude in this row
  }
  write_csv(
      run / "topics/reference.csv",
      "t [s],stamp [ns],phi [rad],theta [rad],psi [rad],lat [deg],lon [deg],alt [m],v_n [m/s],v_e [m/s],v_d [m/s],w_n [m/s],w_e [m/s]",
      ref);
  for (int k = 0; k <= 20; ++k) {  // 1 Hz fixes, 3 m east of the estimate at their time of validity k s
    const double tov = k, stamp = k + 0.2;
    const tern::GeoPoint g = frame.to_geodetic(Eigen::Vector3d(Truthy::p_n(tov), 3.0, -20.0));
    const double vn = k < 3 ? 2.0 : 10.0;  // the window opens at the first fix at >= 5 m/s: stamp 3.2 s
    gnss.push_back({stamp, std::round(stamp * 1e9), k % 2 ? tov * 1e9 : 0.0, k == 15 ? 1.0 : 3.0, 10, g.lat, g.lon, g.alt, vn, 0.5, 0.0,
                    1.0, 2.0, 0.3});
  }
  write_csv(run / "topics/gnss.csv",
            "t [s],stamp [ns],time_of_validity [ns],fix_type [enum],num_sats [],lat [deg],lon [deg],alt [m],vel_n [m/s],vel_e [m/s],"
            "vel_d [m/s],h_acc [m],v_acc [m],s_acc [m/s]",
            gnss);
  for (int k = 0; k <= 200; ++k) {  // gnss_pos ratios k/100 on the even ticks up to 200 (0 .. 1); baro: every other fused one at 2
    const double t = 0.1 * k;
    const double pos = k % 2 == 0 ? (k / 2) / 100.0 : -1.0;
    const double baro = k < 40 ? (k % 2 ? 2.0 : 0.5) : -1.0;
    innov.push_back({t, std::round(t * 1e9), pos, -1, baro, -1, k < 20 ? 0.25 : -1.0, -1, -1});
  }
  write_csv(run / "topics/innovations.csv",
            "t [s],stamp [ns],gnss_pos [],gnss_vel [],baro [],diff_pressure [],mag [],sideslip [],normal_force []", innov);
  std::ofstream(run / "params.csv") << "t [s],parameter,value,source\n0.000000000,ekf.gnss_pos_gate,16.266,default\n"
                                       "0.000000000,ekf.baro_gate,10.828,default\n0.000000000,ekf.gnss_delay,0.2,sensor_log.yaml\n"
                                       "0.000000000,ekf.imu_position,\"[0, 0, 0]\",default\n";
  std::ofstream(run / "summary.json") << R"({"instances": {"sim": {"plugin": "sim_aero", "steps": 3},
    "ekf": {"plugin": "estimator_ekf", "gnss_pos_accepted": 90.0, "gnss_pos_rejected": 10.0, "gnss_pos_mean_nis": 1.25,
            "gnss_vel_accepted": 100.0, "gnss_vel_rejected": 0.0, "mag_accepted": 5.0, "mag_rejected": 0.0,
            "mag_heading_accepted": 3.0, "mag_heading_rejected": 0.0, "gnss_resets": 2.0, "mag_resets": 0.0,
            "filter_resets": 1.0, "inflations": 4.0}}})";
  return run;
}

Eigen::Matrix3d body_to_ned(double phi, double theta, double psi) {
  return (Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

/// f - R(phi, theta, psi)^T f_ned for the yaw that leaves the smallest, found by search (a 0.1 deg
/// grid, then 1e-5 deg steps about its best): the check's closed form, reached another way.
Eigen::Vector3d best_yaw_residual(double phi, double theta, const Eigen::Vector3d& f_ned, const Eigen::Vector3d& f) {
  auto res = [&](double psi) { return Eigen::Vector3d(f - body_to_ned(phi, theta, psi).transpose() * f_ned); };
  double best = 0.0;
  for (int k = 0; k < 3600; ++k)
    if (res(k * 0.1 * tern::kRadPerDeg).norm() < res(best).norm()) best = k * 0.1 * tern::kRadPerDeg;
  const double coarse = best;
  for (int k = -10000; k <= 10000; ++k)
    if (res(coarse + k * 1e-5 * tern::kRadPerDeg).norm() < res(best).norm()) best = coarse + k * 1e-5 * tern::kRadPerDeg;
  return res(best);
}

const tern::core::MeasurementReport& measurement(const ReplayReport& r, const std::string& name) {
  for (const auto& m : r.measurements)
    if (m.name == name) return m;
  FAIL("no measurement " << name);
  throw;
}

}  // namespace

TEST_CASE("replay report: known offsets against the reference and the GNSS") {
  const ReplayReport r = make_replay_report(synthetic_run("known"));
  CHECK(r.window.start_s == doctest::Approx(3.2));
  CHECK(r.window.end_s == doctest::Approx(20.2).epsilon(1e-12));
  CHECK(r.window.rule.find("GNSS horizontal speed >= 5 m/s") != std::string::npos);
  // the reference: interpolated at every valid state sample of [3.2, 20]: 3.2 .. 20.0 less 12.0 .. 12.4
  CHECK(r.reference.absent.empty());
  CHECK(r.reference.roll.samples == 169 - 5);
  CHECK(r.reference.roll.rms == doctest::Approx(1.0).epsilon(1e-9));
  CHECK(r.reference.roll.max == doctest::Approx(1.0).epsilon(1e-9));
  CHECK(r.reference.pitch.rms == doctest::Approx(0.5).epsilon(1e-9));
  CHECK(r.reference.yaw.rms == doctest::Approx(2.0).epsilon(1e-9));  // across +-180 deg
  CHECK(r.reference.course.rms == doctest::Approx(std::atan2(1.0, 10.0) / tern::kRadPerDeg).epsilon(1e-9));
  CHECK(r.reference.position_h.rms < 1e-4);
  CHECK(r.reference.position_v.rms == doctest::Approx(2.0).epsilon(1e-6));
  CHECK(r.reference.position_v.mean == doctest::Approx(-2.0).epsilon(1e-6));  // the estimate 2 m higher: a bias
  CHECK(r.reference.roll.mean == doctest::Approx(1.0).epsilon(1e-9));
  CHECK(r.reference.velocity_h.rms == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(r.wind.vs_reference.rms == doctest::Approx(0.5).epsilon(1e-12));
  CHECK(r.wind.mean_speed == doctest::Approx(5.0));
  CHECK(r.wind.max_speed == doctest::Approx(5.0));
  // GNSS: fixes with tov 4 .. 20 s (3 is before the window), less fix_type 1 at 15 s and tov 12
  // where the state is invalid; odd ones carry their epoch, even ones stamp - gnss_delay
  CHECK(r.gnss.fixes == 21);
  CHECK(r.gnss.fixes_in_window == 16);
  CHECK(r.gnss.position_h.samples == 15);
  CHECK(r.gnss.position_h.rms == doctest::Approx(3.0).epsilon(1e-6));
  CHECK(r.gnss.position_h.max == doctest::Approx(3.0).epsilon(1e-6));
  CHECK(r.gnss.velocity_h.rms == doctest::Approx(0.5).epsilon(1e-12));
  CHECK(r.gnss.course.rms == doctest::Approx(std::atan2(0.5, 10.0) / tern::kRadPerDeg).epsilon(1e-9));
  CHECK(r.gnss.share_pos_accepted == doctest::Approx(0.9));
  CHECK(r.gnss.time_rule.find("(7 fixes), else stamp - ekf.gnss_delay 0.2 s (8 fixes)") != std::string::npos);
}

TEST_CASE("replay report: the attitude against the specific force, the estimate's and the reference's") {
  const fs::path run = synthetic_run("specific_force");
  // 10 Hz fixes accelerating at 2 m/s^2 north; an accelerometer at 100 Hz that agrees with the
  // estimate's attitude (roll 0.2 rad, pitch 0.05 rad, yaw 179 deg): f = R^T (a - g)
  std::vector<std::vector<double>> gnss, imu;
  for (int k = 0; k <= 200; ++k) {
    const double t = 0.1 * k;
    gnss.push_back({t, std::round(t * 1e9), std::round(t * 1e9), 3.0, 10, kOrigin.lat, kOrigin.lon, kOrigin.alt, 6.0 + 2.0 * t, 0.0, 0.0,
                    1.0, 2.0, 0.3});
  }
  const Eigen::Vector3d a_g(2.0, 0.0, -9.80665);  // a - g, NED
  const Eigen::Vector3d f = body_to_ned(0.2, 0.05, 179.0 * tern::kRadPerDeg).transpose() * a_g;
  for (int k = 0; k <= 2000; ++k) imu.push_back({0.01 * k, std::round(0.01 * k * 1e9), f.x(), f.y(), f.z(), 0.0, 0.0, 0.0, 288.15});
  write_csv(run / "topics/gnss.csv",
            "t [s],stamp [ns],time_of_validity [ns],fix_type [enum],num_sats [],lat [deg],lon [deg],alt [m],vel_n [m/s],vel_e [m/s],"
            "vel_d [m/s],h_acc [m],v_acc [m],s_acc [m/s]",
            gnss);
  write_csv(run / "topics/imu.csv",
            "t [s],stamp [ns],accel_x [m/s^2],accel_y [m/s^2],accel_z [m/s^2],gyro_x [rad/s],gyro_y [rad/s],gyro_z [rad/s],temperature [K]",
            imu);
  const ReplayReport r = make_replay_report(run);
  const auto& c = r.specific_force;
  REQUIRE(c.absent.empty());
  // the window opens at the first fix at 5 m/s or more (t = 0): epochs every 0.5 s from 0.6 s to
  // 19.4 s, less those whose bracket touches the invalid state at [12, 12.5); all accelerated
  CHECK(c.epochs == 36);
  CHECK(c.accelerated == 36);
  CHECK(c.pitch.samples == c.epochs);
  CHECK(c.pitch.rms < 1e-6);
  // the 2 m/s^2 lie along the heading (yaw 179 deg, a north): a yaw turned by about
  // g * roll error / 2 m/s^2 would explain any roll error, so roll is not judged
  CHECK(c.roll.samples == 0);
  // the reference: 1 deg less roll, 0.5 deg more pitch, 2 deg more yaw: what the best yaw leaves
  // (searched for here), whatever its own yaw: about its pitch error (the roll error, absorbed by
  // a yaw, lengthens the horizontal part a little: + 0.06 deg)
  const Eigen::Vector3d res = best_yaw_residual(0.2 - 1.0 * tern::kRadPerDeg, 0.05 + 0.5 * tern::kRadPerDeg, a_g, f);
  CHECK(c.reference_pitch.samples == c.epochs);
  CHECK(c.reference_pitch.mean == doctest::Approx(-res.x() / a_g.norm() / tern::kRadPerDeg).epsilon(1e-4));
  CHECK(c.reference_pitch.mean == doctest::Approx(0.5).epsilon(0.15));
  CHECK(c.reference_roll.samples == 0);
  CHECK(tern::core::format_replay_table(r).find("pitch, reference") != std::string::npos);
  CHECK(tern::core::to_json(r)["specific_force"]["reference_pitch"]["samples"] == c.epochs);
  CHECK(tern::core::to_json(r)["specific_force"]["accelerated_epochs"] == c.accelerated);
  // without an accelerometer: absent, said so
  fs::remove(run / "topics/imu.csv");
  CHECK(make_replay_report(run).specific_force.absent == "absent (no accelerometer in topics/imu.csv)");
}

TEST_CASE("replay report: the specific-force check does not inherit a wrong yaw (a coordinated turn)") {
  const fs::path run = synthetic_run("specific_force_turn");
  // a coordinated turn at 20 m/s, 0.2 rad/s (4 m/s^2 toward the centre, bank atan(4 / g)), level;
  // the estimate has the right roll and pitch and a yaw 40 deg off; the reference the right yaw
  // and 1 deg more roll. Fixes at 10 Hz, the accelerometer at 100 Hz
  constexpr double V = 20.0, w = 0.2, g = tern::kStandardGravity, yaw_error = 40.0 * tern::kRadPerDeg;
  const double bank = std::atan(V * w / g);
  auto f_ned = [&](double t) { return Eigen::Vector3d(-V * w * std::sin(w * t), V * w * std::cos(w * t), -g); };  // a - g
  std::vector<std::vector<double>> gnss, imu, state, ref;
  for (int k = 0; k <= 200; ++k) {
    const double t = 0.1 * k, chi = w * t;
    gnss.push_back({t, std::round(t * 1e9), std::round(t * 1e9), 3.0, 10, kOrigin.lat, kOrigin.lon, kOrigin.alt, V * std::cos(chi),
                    V * std::sin(chi), 0.0, 1.0, 2.0, 0.3});
    state.push_back({t, std::round(t * 1e9), 0.0, 0.0, -20.0, V * std::cos(chi), V * std::sin(chi), 0.0, bank, 0.0,
                     std::remainder(chi + yaw_error, 2 * M_PI), 0.0, 0.0, kOrigin.lat, kOrigin.lon, kOrigin.alt, 1.0, 1.0, 0.1});
    ref.push_back({t, std::round(t * 1e9), bank + 1.0 * tern::kRadPerDeg, 0.0, std::remainder(chi, 2 * M_PI), kOrigin.lat, kOrigin.lon,
                   kOrigin.alt, V * std::cos(chi), V * std::sin(chi), 0.0, 0.0, 0.0});
  }
  for (int k = 0; k <= 2000; ++k) {
    const double t = 0.01 * k;
    const Eigen::Vector3d f = body_to_ned(bank, 0.0, w * t).transpose() * f_ned(t);
    imu.push_back({t, std::round(t * 1e9), f.x(), f.y(), f.z(), 0.0, 0.0, w, 288.15});
  }
  write_csv(run / "topics/gnss.csv",
            "t [s],stamp [ns],time_of_validity [ns],fix_type [enum],num_sats [],lat [deg],lon [deg],alt [m],vel_n [m/s],vel_e [m/s],"
            "vel_d [m/s],h_acc [m],v_acc [m],s_acc [m/s]",
            gnss);
  write_csv(run / "topics/imu.csv",
            "t [s],stamp [ns],accel_x [m/s^2],accel_y [m/s^2],accel_z [m/s^2],gyro_x [rad/s],gyro_y [rad/s],gyro_z [rad/s],temperature [K]",
            imu);
  write_csv(run / "topics/state.csv",
            "t [s],stamp [ns],p_n [m],p_e [m],p_d [m],v_n [m/s],v_e [m/s],v_d [m/s],phi [rad],theta [rad],psi [rad],w_n [m/s],w_e [m/s],"
            "origin_lat [deg],origin_lon [deg],origin_alt [m],origin_valid [bool],valid [bool],alpha [rad]",
            state);
  write_csv(
      run / "topics/reference.csv",
      "t [s],stamp [ns],phi [rad],theta [rad],psi [rad],lat [deg],lon [deg],alt [m],v_n [m/s],v_e [m/s],v_d [m/s],w_n [m/s],w_e [m/s]",
      ref);
  // the check this replaces, R(phi, theta, psi)^T (a - g) with the estimate's own yaw, would put
  // the yaw error into roll and pitch: 4 m/s^2 turned by 40 deg is 15 deg of tilt
  const Eigen::Vector3d inherited =
      body_to_ned(bank, 0.0, 5.0 * w).transpose() * f_ned(5.0) - body_to_ned(bank, 0.0, 5.0 * w + yaw_error).transpose() * f_ned(5.0);
  REQUIRE(inherited.head<2>().norm() / g / tern::kRadPerDeg > 10.0);
  const auto& c = make_replay_report(run).specific_force;
  REQUIRE(c.absent.empty());
  CHECK(c.epochs == 38);  // every 0.5 s from 0.6 s to 19.1 s
  CHECK(c.accelerated == c.epochs);
  // the turn's 4 m/s^2 lie across the heading: roll judged at every epoch, pitch at none (a yaw
  // would explain it); the estimate's roll is right whatever its yaw (the velocity fit's
  // straight line through the circle's +-0.6 s shortens a by 0.14 %: 0.03 deg)
  CHECK(c.roll.samples == c.epochs);
  CHECK(c.roll.rms < 0.05);
  CHECK(c.pitch.samples == 0);
  // the reference's 1 deg of roll, as the best yaw (searched for) leaves it: 1 deg
  const Eigen::Vector3d f5 = body_to_ned(bank, 0.0, 5.0 * w).transpose() * f_ned(5.0);
  const Eigen::Vector3d res = best_yaw_residual(bank + 1.0 * tern::kRadPerDeg, 0.0, f_ned(5.0), f5);
  CHECK(res.y() / f_ned(5.0).norm() / tern::kRadPerDeg == doctest::Approx(1.0).epsilon(0.01));
  CHECK(c.reference_roll.samples == c.epochs);
  CHECK(c.reference_roll.mean == doctest::Approx(1.0).epsilon(0.05));
  CHECK(c.reference_roll.max == doctest::Approx(1.0).epsilon(0.05));
}

TEST_CASE("replay report: NIS percentiles, counters, validity, NaN") {
  const ReplayReport r = make_replay_report(synthetic_run("nis"));
  CHECK(r.measurements.size() == 7);  // the innovations columns, nothing else
  const auto& pos = measurement(r, "gnss_pos");
  CHECK(pos.gate == "ekf.gnss_pos_gate = 16.266");
  CHECK(pos.whole.count == 101);
  CHECK(pos.whole.rejected == 0);
  CHECK(pos.whole.p50_nis == doctest::Approx(0.50 * 16.266));
  CHECK(pos.whole.p95_nis == doctest::Approx(0.95 * 16.266));
  CHECK(pos.whole.p99_nis == doctest::Approx(0.99 * 16.266));
  CHECK(pos.whole.mean_nis == doctest::Approx(0.5 * 16.266));
  CHECK(pos.window.count == 85);  // even ticks 3.2 .. 20.0 s: ratios 0.16 .. 1.00
  CHECK(pos.window.p50_ratio == doctest::Approx(0.58));
  const auto& baro = measurement(r, "baro");
  CHECK(baro.whole.count == 40);
  CHECK(baro.whole.share_rejected == doctest::Approx(0.5));
  CHECK(baro.whole.mean_nis == doctest::Approx(1.25 * 10.828));
  CHECK(baro.window.count == 8);            // 3.2 .. 3.9 s
  const auto& mag = measurement(r, "mag");  // heading and 3-axis both fused: the gate is not known
  CHECK(std::isnan(mag.whole.mean_nis));
  CHECK(mag.whole.p50_ratio == doctest::Approx(0.25));
  CHECK(mag.gate.find("both mag (5 fused) and mag_heading (3 fused)") != std::string::npos);
  CHECK(measurement(r, "gnss_vel").whole.count == 0);
  CHECK(measurement(r, "normal_force").gate.find("fixed gate 10.828") != std::string::npos);
  CHECK(r.counters.instance == "ekf");
  CHECK(r.counters.models.size() == 4);
  CHECK(r.validity.first_valid_s == doctest::Approx(1.0));
  CHECK(r.validity.valid_to_invalid == 1);
  CHECK(r.validity.filter_resets == 1);
  CHECK(r.validity.divergences == 2);
  CHECK(r.validity.samples == 191);
  CHECK(r.validity.share_valid == doctest::Approx(186.0 / 191.0));
  CHECK(r.validity.nan_cells == 1);
  const std::string table = tern::core::format_replay_table(r);
  CHECK(table.find("!!! NaN in state.csv: 1 cells in 1 rows !!!") != std::string::npos);
  CHECK(table.find("roll [deg]") != std::string::npos);
  const auto j = tern::core::to_json(r);
  CHECK(j["reference"]["roll"]["samples"].get<int>() == 164);
  CHECK(j["reference"]["roll"]["window"].get<std::string>() == r.window.rule);
  CHECK(j["validity"]["nan_cells"].get<int>() == 1);
  CHECK(j["estimator"]["resets"]["gnss_resets"].get<double>() == 2.0);
  // the keys tern plot's index.html reads (core/apps/plot/tern_plot_html.py _replay_tables)
  for (const char* k : {"start_s", "end_s", "rule"}) CHECK(j["window"].contains(k));
  for (const char* k : {"share_valid", "first_valid_s", "divergences", "valid_to_invalid", "filter_resets", "nan_cells"})
    CHECK(j["validity"].contains(k));
  for (const char* k : {"count", "share_rejected", "mean_nis", "p50_nis", "p95_nis", "p99_nis"})
    CHECK(j["measurements"]["baro"]["window"].contains(k));
  CHECK(j["measurements"]["baro"]["gate"] == "ekf.baro_gate = 10.828");
  CHECK(j["measurements"].contains("rule"));
  for (const char* k : {"accepted", "rejected", "mean_nis"}) CHECK(j["estimator"]["models"]["gnss_pos"].contains(k));
  CHECK(j["reference"]["status"] == "compared");
  CHECK(j["gnss"]["status"] == "compared");
  CHECK(j["wind"]["status"] == "estimated");
  for (const char* k : {"rms", "max", "unit", "samples", "rule"}) CHECK(j["gnss"]["course"].contains(k));
  CHECK(j["gnss"]["share_pos_accepted"].get<double>() == doctest::Approx(0.9));
  CHECK(j["wind"]["mean_speed"].get<double>() == doctest::Approx(5.0));
  CHECK(j["wind"]["vs_reference"]["rms"].get<double>() == doctest::Approx(0.5));
  tern::core::write_replay_report(r);
  CHECK(fs::exists(r.run_dir / "replay_report.json"));
}

TEST_CASE("replay report: sensor_log.yaml's airborne window; bad input is one line") {
  const fs::path run = synthetic_run("airborne");
  std::ofstream(run / "sensor_log.yaml") << "tern_sensor_log: 1\nairborne: [5, 10]\n";
  ReplayReport r = make_replay_report(run);
  CHECK(r.window.start_s == 5.0);
  CHECK(r.window.end_s == 10.0);
  CHECK(r.window.rule == "sensor_log.yaml airborne: [5, 10] s");
  CHECK(r.reference.roll.samples == 51);
  std::ofstream(run / "sensor_log.yaml") << "tern_sensor_log: 1\nairborne: [10, 5]\n";
  CHECK_THROWS_WITH(make_replay_report(run), doctest::Contains("sensor_log.yaml:2:11: airborne: [10, 5]: start must be before end"));
  fs::remove(run / "sensor_log.yaml");
  std::ofstream(run / "topics/innovations.csv", std::ios::app) << "20.1,20100000000,0.5,-1\n";
  CHECK_THROWS_WITH(make_replay_report(run), doctest::Contains("innovations.csv:203: 4 values, the header has 9 columns"));
  std::ofstream(run / "topics/innovations.csv") << "t [s],stamp [ns],gnss_pos []\n0.1,100000000,0.5\n0.2,200000000,x1\n";
  CHECK_THROWS_WITH(make_replay_report(run), doctest::Contains("innovations.csv:3: column 3: 'x1' is not a number"));
}

namespace {

/// reference.csv as synthetic_run writes it, but `above` m higher than the estimate.
void reference_above(const fs::path& run, double above) {
  const tern::GeoOrigin frame(kOrigin);
  std::vector<std::vector<double>> ref;
  for (int k = 0; k <= 100; ++k) {
    const double t = 0.2 * k;
    const tern::GeoPoint g = frame.to_geodetic(Eigen::Vector3d(Truthy::p_n(t), 0.0, -20.0 - above));
    ref.push_back({t, std::round(t * 1e9), 0.2, 0.05, 179.0 * tern::kRadPerDeg, g.lat, g.lon, g.alt, 10.0, 0.0, 0.0, 3.0, -4.0});
  }
  write_csv(
      run / "topics/reference.csv",
      "t [s],stamp [ns],phi [rad],theta [rad],psi [rad],lat [deg],lon [deg],alt [m],v_n [m/s],v_e [m/s],v_d [m/s],w_n [m/s],w_e [m/s]",
      ref);
}

/// The ISA static pressure (Pa) at pressure altitude h (m) against 1013.25 hPa (docs/sensor-log.md).

std::string note_at(const ReplayReport& r, const std::string& where) {
  for (const auto& e : r.explanations)
    for (const auto& w : e.where)
      if (w == where) return e.text;
  return "";
}

}  // namespace

TEST_CASE("replay report notes: a reference altitude on another datum, said where it shows and from which data") {
  CHECK(make_replay_report(synthetic_run("no_notes")).explanations.empty());  // 2 m lower, 1 deg of roll: nothing to explain
  const fs::path run = synthetic_run("datum");
  reference_above(run, 56.0);
  ReplayReport r = make_replay_report(run);  // without a barometer: neither GNSS nor pressure altitude
  std::string note = note_at(r, "reference.position_vertical");
  CHECK(note.find("the reference's altitude is 56.0 m above the estimate's (median of 164 samples in the window") == 0);
  CHECK(note.find("it is not the GNSS altitude (+56.0 m); the estimate's altitude is +0.0 m from the GNSS's (median)") !=
        std::string::npos);
  // a barometer whose ISA pressure altitude is the reference's: a day 56 m of pressure below standard
  std::vector<std::vector<double>> baro;
  for (int k = 0; k <= 400; ++k)
    baro.push_back({0.05 * k, std::round(0.05 * k * 1e9), tern::isa_pressure(kOrigin.alt + 20.0 + 56.0), 288.15});
  write_csv(run / "topics/baro.csv", "t [s],stamp [ns],pressure [Pa],temperature [K]", baro);
  r = make_replay_report(run);
  note = note_at(r, "reference.position_vertical");
  const double qnh = tern::isa_pressure(kOrigin.alt + 20.0 + 56.0) /
                     std::pow(1.0 - tern::kIsaPressureLapse * (kOrigin.alt + 20.0), tern::kIsaPressureExponent) / 100.0;
  CHECK(note.find("it is the barometer's ISA pressure altitude against 1013.25 hPa (median difference +0.0 m), 56.0 m above the GNSS "
                  "altitude; the estimate's altitude is +0.0 m from the GNSS's (median)") != std::string::npos);
  CHECK(note.find(fmt::format("the pressure altitude is the GNSS altitude at a sea-level pressure (QNH) of {:.1f} hPa", qnh)) !=
        std::string::npos);
  // where it shows: under the printed row, as the figure's "note", and in "notes"
  const std::string table = tern::core::format_replay_table(r);
  CHECK(table.find("position vert. [m]") < table.find("    note: the reference's altitude is 56.0 m above"));
  CHECK(table.find("    note: the reference's altitude is 56.0 m above") < table.find("velocity horiz. [m/s]"));
  const auto j = tern::core::to_json(r);
  CHECK(j["reference"]["position_vertical"]["note"] == note);
  CHECK(j["notes"].back() == "reference.position_vertical: " + note);
}

TEST_CASE("replay report notes: a rejected 3-axis magnetometer (the field it read against the model's), a NIS far below 1") {
  const fs::path run = synthetic_run("mag");
  std::vector<std::vector<double>> mag, innov;
  for (int k = 0; k <= 200; ++k) {  // 30 uT until 10 s, 48 uT after; the magnetometer rejected until 10 s
    const double t = 0.1 * k, b = t < 10.0 ? 30e-6 : 48e-6;
    mag.push_back({t, std::round(t * 1e9), b * 0.6, 0.0, b * 0.8});
    innov.push_back({t, std::round(t * 1e9), -1, -1, -1, 0.05, t < 10.0 ? 3.0 : 0.5, -1, -1});
  }
  write_csv(run / "topics/mag.csv", "t [s],stamp [ns],field_x [T],field_y [T],field_z [T]", mag);
  write_csv(run / "topics/innovations.csv",
            "t [s],stamp [ns],gnss_pos [],gnss_vel [],baro [],diff_pressure [],mag [],sideslip [],normal_force []", innov);
  std::ofstream(run / "params.csv") << "t [s],parameter,value,source\n0,ekf.mag_model_date,2014.11,sensor_log.yaml\n"
                                       "0,ekf.airspeed_gust_sigma,1,default\n0,ekf.diff_pressure_noise,2,default\n";
  std::ofstream(run / "summary.json") << R"({"instances": {"ekf": {"plugin": "estimator_ekf", "mag_accepted": 0.0,
    "mag_rejected": 100.0, "mag_mean_nis": 33.0, "mag_heading_accepted": 2101.0, "mag_heading_rejected": 3.0,
    "mag_heading_mean_nis": 2.78, "diff_pressure_accepted": 200.0, "diff_pressure_rejected": 0.0,
    "diff_pressure_mean_nis": 0.085}}})";
  const ReplayReport r = make_replay_report(run);
  const std::string note = note_at(r, "estimator.models.mag");
  CHECK(note == note_at(r, "measurements.mag"));  // the NIS table's row, where "100.0 %" shows, and the counters' row
  CHECK(note.find("mag 100.0 % rejected: the 3-axis magnetometer's 100 of 100 samples (mean NIS 33.0); in the window where it was "
                  "rejected the field reads 30-30 uT (5-95 %, ") == 0);
  CHECK(note.find("(WMM-2015v2 on 2014.11 at the origin, extrapolated) and 48 uT (median) where it was accepted: -37 % is not the "
                  "Earth's field alone") != std::string::npos);
  CHECK(note.find("against the Earth's 47.") != std::string::npos);
  CHECK(note.find("; what was fused is the heading model (mag_heading): 2101 samples accepted at mean NIS 2.78") != std::string::npos);
  CHECK(note.find("no magnetometer sample is fused after") == std::string::npos);  // fused to the window's end
  const std::string pitot = note_at(r, "estimator.models.diff_pressure");
  CHECK(pitot.find("mean NIS 0.085, below 0.3: the innovations are smaller than the noise the estimator allows for them "
                   "(airspeed_gust_sigma = 1 m/s of gusts") == 0);
  CHECK(note_at(r, "estimator.models.mag_heading").empty());  // 2.78: within [0.3, 3]
  const std::string table = tern::core::format_replay_table(r);
  CHECK(table.find("    note: mag 100.0 % rejected") != std::string::npos);
  CHECK(table.find("    note: mag 100.0 % rejected") == table.rfind("    note: mag 100.0 % rejected"));  // printed once
  CHECK(tern::core::to_json(r)["estimator"]["models"]["mag"]["note"] == note);
}

TEST_CASE("replay report: the magnetometer's field against the model, the model's error or the calibration") {
  // level flight turning at 0.2 rad/s for 40 s (every heading flown); the magnetometer reads the
  // WMM's field at the origin on 2014.11 (WMM-2015v2 carried back 0.89 years) rotated into the
  // body, plus an offset in body axes
  const tern::MagneticField earth = tern::world_magnetic_field(kOrigin.lat, kOrigin.lon, kOrigin.alt, 2014.11);
  auto run_with = [&](const std::string& name, const Eigen::Vector3d& offset_uT) {
    const fs::path run = synthetic_run(name);
    std::vector<std::vector<double>> state, gnss, mag;
    for (int k = 0; k <= 400; ++k) {
      const double t = 0.1 * k, psi = std::remainder(0.2 * t, 2 * M_PI);
      state.push_back({t, std::round(t * 1e9), 0.0, 0.0, -20.0, 20.0 * std::cos(psi), 20.0 * std::sin(psi), 0.0, 0.0, 0.0, psi, 0.0, 0.0,
                       kOrigin.lat, kOrigin.lon, kOrigin.alt, 1.0, 1.0, 0.1});
      gnss.push_back({t, std::round(t * 1e9), std::round(t * 1e9), 3.0, 10, kOrigin.lat, kOrigin.lon, kOrigin.alt, 20.0 * std::cos(psi),
                      20.0 * std::sin(psi), 0.0, 1.0, 2.0, 0.3});
      const Eigen::Vector3d b = body_to_ned(0.0, 0.0, psi).transpose() * earth.ned + offset_uT * 1e-6;
      mag.push_back({t, std::round(t * 1e9), b.x(), b.y(), b.z()});
    }
    write_csv(run / "topics/state.csv",
              "t [s],stamp [ns],p_n [m],p_e [m],p_d [m],v_n [m/s],v_e [m/s],v_d [m/s],phi [rad],theta [rad],psi [rad],w_n [m/s],"
              "w_e [m/s],origin_lat [deg],origin_lon [deg],origin_alt [m],origin_valid [bool],valid [bool],alpha [rad]",
              state);
    write_csv(run / "topics/gnss.csv",
              "t [s],stamp [ns],time_of_validity [ns],fix_type [enum],num_sats [],lat [deg],lon [deg],alt [m],vel_n [m/s],vel_e [m/s],"
              "vel_d [m/s],h_acc [m],v_acc [m],s_acc [m/s]",
              gnss);
    write_csv(run / "topics/mag.csv", "t [s],stamp [ns],field_x [T],field_y [T],field_z [T]", mag);
    std::ofstream(run / "params.csv", std::ios::app) << "0,ekf.mag_model_date,2014.11,sensor_log.yaml\n";
    return make_replay_report(run);
  };
  // the model's own field: it fits; its expected error is the WMM's plus 0.89 years of drift
  ReplayReport r = run_with("mag_field_model", Eigen::Vector3d::Zero());
  const auto& c = r.mag_field;
  REQUIRE(c.absent.empty());
  CHECK(c.samples == 401);
  CHECK(c.intensity == doctest::Approx(earth.intensity * 1e6).epsilon(1e-9));
  CHECK(c.inclination == doctest::Approx(earth.inclination / tern::kRadPerDeg).epsilon(1e-9));
  CHECK(c.model.find("WMM-2015v2 on 2014.11") == 0);
  CHECK(c.years_outside == doctest::Approx(2015.0 - 2014.11));
  CHECK(c.drift_intensity > 0.0);
  CHECK(c.expected_intensity == doctest::Approx(0.138 + c.years_outside * c.drift_intensity));
  CHECK(c.sectors == 8);
  CHECK(c.heading_spread < 1e-9);
  CHECK(note_at(r, "mag_field").find(": the model fits") != std::string::npos);
  CHECK(tern::core::to_json(r)["mag_field"]["model"]["years_outside_span"] == doctest::Approx(0.89));
  // a hard iron of 3 uT along the body's x: the strength follows the heading; the calibration
  r = run_with("mag_field_hard_iron", Eigen::Vector3d(3.0, 0.0, 0.0));
  CHECK(r.mag_field.heading_spread > 2.0);
  CHECK(note_at(r, "mag_field").find("a hard- or soft-iron calibration the log did not undo is the cause") != std::string::npos);
  // 4 uT along the body's z (level flight never turns it): steady with heading, not the model
  r = run_with("mag_field_z_offset", Eigen::Vector3d(0.0, 0.0, 4.0));
  CHECK(r.mag_field.heading_spread < 1e-9);
  CHECK(r.mag_field.vertical - r.mag_field.model_vertical == doctest::Approx(4.0));
  const std::string note = note_at(r, "mag_field");
  CHECK(note.find("25 times that in strength and 10 in inclination, which the model (and its extrapolation) cannot make; the "
                  "strength is steady with heading") != std::string::npos);
  CHECK(note.find("(+4.0 uT vertical, +0.0 uT horizontal) is a calibration level flight does not turn") != std::string::npos);
  MESSAGE(note);
}

TEST_CASE("replay report: missing topics are absent sections, not errors") {
  const fs::path run = test_dir() / "bare";
  fs::create_directories(run / "topics");
  write_csv(run / "topics/state.csv", "t [s],valid [bool]", {{0.0, 0.0}, {0.1, 1.0}, {0.2, 1.0}});
  const ReplayReport r = make_replay_report(run);
  CHECK(r.reference.absent == "absent (no topics/reference.csv)");
  CHECK(r.gnss.absent == "absent (no topics/gnss.csv)");
  CHECK(r.measurements_absent == "absent (no topics/innovations.csv)");
  CHECK(r.window.rule.find("the whole replay") == 0);
  CHECK(r.validity.share_valid == 1.0);
  CHECK(tern::core::format_replay_table(r).find("absent (no topics/gnss.csv)") != std::string::npos);
  CHECK_THROWS_WITH(make_replay_report(test_dir() / "nothing"), doctest::Contains("no topics/state.csv"));
}

namespace {

/// A topic CSV as rows of cells with a column index by name (the report's reader is what is tested).
struct Table {
  std::map<std::string, std::size_t> col;
  std::vector<std::vector<std::string>> rows;
  double at(std::size_t r, const std::string& name) const { return std::stod(rows[r][col.at(name)]); }
};

Table read_table(const fs::path& p) {
  Table t;
  const auto ls = lines(read_file(p));
  const auto head = cells(ls.at(0));
  for (std::size_t i = 0; i < head.size(); ++i) t.col[head[i].substr(0, head[i].find(" ["))] = i;
  for (std::size_t k = 1; k < ls.size(); ++k) t.rows.push_back(cells(ls[k]));
  return t;
}

/// reference.csv from the simulator's truth: what another estimator would have said, if perfect.
void reference_from_truth(const fs::path& run) {
  const Table truth = read_table(run / "topics/truth.csv");
  const tern::GeoOrigin frame(truth.at(0, "origin_lat"), truth.at(0, "origin_lon"), truth.at(0, "origin_alt"));
  std::vector<std::vector<double>> rows;
  for (std::size_t r = 0; r < truth.rows.size(); ++r) {
    const tern::GeoPoint g = frame.to_geodetic(Eigen::Vector3d(truth.at(r, "p_n"), truth.at(r, "p_e"), truth.at(r, "p_d")));
    rows.push_back({truth.at(r, "t"), truth.at(r, "stamp"), truth.at(r, "phi"), truth.at(r, "theta"), truth.at(r, "psi"), g.lat, g.lon,
                    g.alt, truth.at(r, "v_n"), truth.at(r, "v_e"), truth.at(r, "v_d"), truth.at(r, "w_n"), truth.at(r, "w_e")});
  }
  write_csv(
      run / "topics/reference.csv",
      "t [s],stamp [ns],phi [rad],theta [rad],psi [rad],lat [deg],lon [deg],alt [m],v_n [m/s],v_e [m/s],v_d [m/s],w_n [m/s],w_e [m/s]",
      rows);
}

}  // namespace

TEST_CASE("replay report end to end: a default-mission flight, its truth as the reference") {
  const fs::path out = test_dir() / "fly.out";
  REQUIRE(run_tern({"fly", std::string(TERN_SOURCE_DIR) + "/configs/missions/default.yaml", "--duration", "60", "-q", "--log-dir",
                    (test_dir() / "runs").string()},
                   out) == 0);
  std::string run;
  for (const auto& l : lines(read_file(out)))
    if (l.rfind("log: ", 0) == 0) run = l.substr(5);
  REQUIRE(!run.empty());
  reference_from_truth(run);
  const ReplayReport r = make_replay_report(run);
  // the window and the roll and pitch errors, computed here from the tables alone
  const Table gnss = read_table(fs::path(run) / "topics/gnss.csv");
  double start = NAN, end = NAN;
  for (std::size_t k = 0; k < gnss.rows.size(); ++k)
    if (std::hypot(gnss.at(k, "vel_n"), gnss.at(k, "vel_e")) >= 5.0) {
      if (std::isnan(start)) start = gnss.at(k, "t");
      end = gnss.at(k, "t");
    }
  CHECK(r.window.start_s == start);
  CHECK(r.window.end_s == end);
  const Table state = read_table(fs::path(run) / "topics/state.csv");
  const Table truth = read_table(fs::path(run) / "topics/truth.csv");
  std::map<std::string, std::size_t> truth_row;
  for (std::size_t k = 0; k < truth.rows.size(); ++k) truth_row[truth.rows[k][0]] = k;
  double roll2 = 0.0, pitch2 = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < state.rows.size(); ++k) {
    const double t = state.at(k, "t");
    if (t < start || t > end || state.at(k, "valid") != 1.0) continue;
    const std::size_t j = truth_row.at(state.rows[k][0]);
    roll2 += std::pow(std::remainder(state.at(k, "phi") - truth.at(j, "phi"), 2 * M_PI) / tern::kRadPerDeg, 2);
    pitch2 += std::pow(std::remainder(state.at(k, "theta") - truth.at(j, "theta"), 2 * M_PI) / tern::kRadPerDeg, 2);
    ++n;
  }
  REQUIRE(n > 400);  // state.csv at the default log's 10 Hz (docs/logs.md, log level replay) over ~47 s of window
  CHECK(r.reference.roll.samples == n);
  CHECK(r.reference.roll.rms == doctest::Approx(std::sqrt(roll2 / n)).epsilon(1e-9));
  CHECK(r.reference.pitch.rms == doctest::Approx(std::sqrt(pitch2 / n)).epsilon(1e-9));
  // the rest against what the realistic sensors allow: metres, tenths of m/s, no NaN, no divergence
  CHECK(r.reference.roll.rms < 2.0);
  CHECK(r.reference.position_h.samples == n);
  CHECK(r.reference.position_h.rms < 5.0);
  CHECK(r.reference.velocity_h.rms < 1.0);
  CHECK(r.gnss.position_h.rms > 0.01);  // the fixes' noise the estimate smooths
  CHECK(r.gnss.position_h.rms < 10.0);
  CHECK(r.gnss.position_h.samples > 200);
  CHECK(r.wind.vs_reference.rms < 2.0);
  CHECK(r.validity.nan_cells == 0);
  std::size_t drops = 0;  // valid -> invalid after the first valid state (the flight's first 0.2 s has one)
  for (std::size_t k = 1, seen = 0; k < state.rows.size(); ++k) {
    seen = seen || state.at(k - 1, "valid") == 1.0;
    drops += seen && state.at(k - 1, "valid") == 1.0 && state.at(k, "valid") == 0.0 ? 1 : 0;
  }
  CHECK(r.validity.valid_to_invalid == drops);
  CHECK(r.validity.divergences == drops);  // no filter reset
  CHECK(measurement(r, "gnss_pos").gate == "ekf.gnss_pos_gate = 16.266");
  CHECK(measurement(r, "gnss_pos").window.count > 200);
  // the physics check scores the truth and this estimate (0.2 deg from it) alike: the same scatter
  // (the GNSS velocity's noise, the realistic IMU's vibration; 1-3 deg RMS) and no bias beyond 1 deg
  const auto& sf = r.specific_force;
  CHECK(sf.epochs > 50);
  CHECK(sf.roll.samples > 20);  // along-track acceleration within 0.5 m/s^2: roll judged
  CHECK(sf.pitch.samples > 20);
  CHECK(sf.reference_roll.samples == sf.roll.samples);  // the same epochs for every attitude judged
  CHECK(sf.reference_pitch.samples == sf.pitch.samples);
  CHECK(std::fabs(sf.roll.rms - sf.reference_roll.rms) < 0.5);
  CHECK(std::fabs(sf.pitch.rms - sf.reference_pitch.rms) < 0.5);
  for (const auto* e : {&sf.roll, &sf.pitch, &sf.reference_roll, &sf.reference_pitch}) CHECK(std::fabs(e->mean) < 1.0);
  MESSAGE(tern::core::format_replay_table(r));
}
