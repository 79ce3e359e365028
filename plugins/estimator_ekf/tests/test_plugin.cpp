// The estimator_ekf plugin through the SDK test harness: ports, parameters, output, summary.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <memory>

#include "estimator_ekf_plugin.hpp"
#include "fly.hpp"
#include "tern/testing/harness.hpp"

using namespace tern;
using namespace tern::ekf::test;
using tern::ekf::plugin::EstimatorEkf;

namespace {

/// Feeds the harness from the truth generator for `seconds`; returns the number of steps.
template <class OnStep>
int feed(testing::Harness& h, TruthSim& sim, double seconds, OnStep on_step) {
  const int steps = static_cast<int>(std::lround(seconds / 0.0025));
  for (int i = 0; i < steps; ++i) {
    sim.advance();
    h.set_input("imu", sim.imu());
    if (sim.gnss_due()) h.set_input("gnss", sim.gnss());
    if (sim.baro_due()) h.set_input("baro", sim.baro());
    if (sim.pitot_due()) h.set_input("diff_pressure", sim.pitot());
    if (sim.mag_due()) h.set_input("mag", sim.mag());
    h.step(sim.now());
    on_step();
  }
  return steps;
}

SimOptions turning_flight() {
  SimOptions o;
  o.psi0 = -1.2;
  o.phi_ramps = {{10.0, 2.0, 0.5}, {25.0, 2.0, -0.5}};
  return o;
}

}  // namespace

TEST_CASE("plugin: ports, state output every IMU sample, origin and validity") {
  auto plugin = std::make_unique<EstimatorEkf>();
  const EstimatorEkf* p = plugin.get();
  // gnss_req_hold_time 0: the truth simulation's receiver is settled from its first fix (fly.hpp settled_receiver)
  testing::Harness h(std::move(plugin),
                     {{"gyro_noise", 0.0023}, {"mag_gate", 16.0}, {"accel_level_calibrated", false}, {"gnss_req_hold_time", 0.0}});
  REQUIRE(h.plugin().find_input("imu") != nullptr);
  CHECK(h.plugin().find_input("imu")->need() == Need::required);
  for (const char* n : {"gnss", "baro", "diff_pressure", "mag"}) {
    INFO(n);
    REQUIRE(h.plugin().find_input(n) != nullptr);
    CHECK(h.plugin().find_input(n)->need() == Need::optional);
  }
  REQUIRE(h.plugin().find_output("state") != nullptr);

  TruthSim sim(turning_flight());
  // Bind every sensor before the first step so that the plugin expects a magnetometer.
  h.set_input("mag", sim.mag());
  h.set_input("baro", sim.baro());
  h.set_input("diff_pressure", sim.pitot());
  const int steps = feed(h, sim, 40.0, [] {});
  CHECK(h.published("state") == static_cast<std::uint64_t>(steps));
  const auto& s = h.output<msg::State>("state");
  CHECK(s.valid);
  CHECK(s.origin_valid);
  CHECK(s.origin_lat == doctest::Approx(sim.options().lat0).epsilon(1e-6));
  CHECK(s.stamp == sim.now());
  const Truth& t = sim.truth();
  CHECK(std::fabs(wrap_pi(s.phi - t.phi)) < 0.5 * kPi / 180);
  CHECK(std::fabs(s.theta - t.theta) < 0.5 * kPi / 180);
  CHECK(std::fabs(wrap_pi(s.psi - t.psi)) < 1.5 * kPi / 180);  // 40 s: still learning the gyro's sensitivity (S_g)
  const Eigen::Vector3d vb = t.R.transpose() * t.v;
  CHECK(s.u == doctest::Approx(vb.x()).epsilon(0.01));
  CHECK(std::fabs(s.v - vb.y()) < 0.45);  // one instant: 1 deg of yaw at 25 m/s is 0.44 m/s
  CHECK(std::fabs(s.Va - sim.air_velocity_body().norm()) < 0.3);
  CHECK(std::fabs(s.alpha - sim.options().alpha) < 0.02);
  CHECK(std::fabs(s.beta) < 0.02);
  CHECK(std::fabs(s.w_n - sim.options().wind.x()) < 0.5);
  CHECK(std::fabs(s.w_e - sim.options().wind.y()) < 0.5);
  CHECK(std::fabs(s.w_d) < 0.3);  // the truth has no vertical wind
  CHECK(std::fabs(wrap_pi(s.chi - std::atan2(t.v.y(), t.v.x()))) < 0.5 * kPi / 180);
  CHECK(s.Vg == doctest::Approx(t.v.norm()).epsilon(0.01));
  // Rates have the bias removed: compare with the truth within the gyro noise.
  CHECK((Eigen::Vector3d(s.p, s.q, s.r) - t.omega).norm() < 0.02);
  CHECK((Eigen::Vector3d(s.b_x, s.b_y, s.b_z) - sim.options().gyro_bias).norm() < 0.004);
  CHECK(p->estimator().initialized());

  // No new IMU sample: no new output.
  const auto n = h.published("state");
  h.step(sim.now() + 1000);
  CHECK(h.published("state") == n);

  // summary() reports the counters.
  bool found = false;
  for (const auto& [name, value] : h.plugin().summary())
    if (name == "gnss_pos_accepted") found = value > 300;
  CHECK(found);
}

TEST_CASE("plugin: output decimation, parameter ranges, run-time changes, reset") {
  testing::Harness h(std::make_unique<EstimatorEkf>(), {{"output_decimation", std::int64_t{4}}, {"gnss_req_hold_time", 0.0}});
  TruthSim sim(turning_flight());
  feed(h, sim, 2.0, [] {});
  CHECK(h.published("state") == 200);
  CHECK_THROWS_AS(h.set_param("gyro_noise", -1.0), ParamError);
  CHECK_THROWS_AS(h.set_param("min_gnss_fix_type", std::int64_t{5}), ParamError);
  CHECK_THROWS_AS(testing::Harness(std::make_unique<EstimatorEkf>(), {{"baro_noise", 0.0}}), ParamError);
  // A run-time change applies: with a tiny GNSS gate every position is rejected.
  h.set_param("gnss_pos_gate", 1e-9);
  const auto& est = dynamic_cast<EstimatorEkf&>(h.plugin()).estimator();
  const auto rejected = est.gnss_position_model().stats.rejected;
  feed(h, sim, 1.0, [] {});
  CHECK(est.gnss_position_model().stats.rejected >= rejected + 9);
  h.reset();
  CHECK_FALSE(est.initialized());
  CHECK_FALSE(est.origin_valid());
}

TEST_CASE("plugin: the default air density is the aircraft file's") {
  testing::HarnessOptions opt;
  opt.aircraft_file = std::string(TERN_EKF_AIRCRAFT_DIR) + "/anaconda.yaml";
  testing::Harness h(std::make_unique<EstimatorEkf>(), {}, opt);
  CHECK(std::get<double>(h.plugin().find_param("rho")->value()) == doctest::Approx(1.2682));
  testing::Harness plain(std::make_unique<EstimatorEkf>());
  CHECK(std::get<double>(plain.plugin().find_param("rho")->value()) == doctest::Approx(1.225));
  opt.aircraft_file = "/nonexistent/aircraft.yaml";
  CHECK_THROWS_AS(testing::Harness(std::make_unique<EstimatorEkf>(), {}, opt), std::runtime_error);
}

TEST_CASE("plugin: the side- and normal-force models take mass, wing area and chord, C_Y_* and C_L_* from the aircraft file") {
  const auto real = [](testing::Harness& h, const char* name) { return std::get<double>(h.plugin().find_param(name)->value()); };
  for (const char* file : {"/anaconda.yaml", "/../../plugins/sim_aero/tests/data/anaconda_dynamics.yaml"}) {
    CAPTURE(file);  // tern's format and ROSflight's, unchanged
    testing::HarnessOptions opt;
    opt.aircraft_file = std::string(TERN_EKF_AIRCRAFT_DIR) + file;
    testing::Harness h(std::make_unique<EstimatorEkf>(), {}, opt);
    CHECK(real(h, "mass") == doctest::Approx(4.5));
    CHECK(real(h, "wing_S") == doctest::Approx(0.52));
    CHECK(real(h, "C_Y_beta") == doctest::Approx(-0.98));
    CHECK(real(h, "C_Y_delta_a") == doctest::Approx(0.075));
    CHECK(real(h, "C_Y_delta_r") == doctest::Approx(0.19));
    CHECK(real(h, "wing_c") == doctest::Approx(0.235));
    CHECK(real(h, "C_L_0") == doctest::Approx(0.506));  // ROSflight's C_L_O
    CHECK(real(h, "C_L_alpha") == doctest::Approx(5.61));
    CHECK(real(h, "C_L_q") == doctest::Approx(7.95));
    CHECK(real(h, "C_L_delta_e") == doctest::Approx(0.13));
    const auto& est = dynamic_cast<const EstimatorEkf&>(h.plugin()).estimator();
    CHECK(est.config().side_force_active());
    CHECK(est.config().normal_force_active());
  }
  // a coefficient that is not a number: one error naming the file, the key and the value
  const std::filesystem::path bad = std::filesystem::temp_directory_path() / "tern_ekf_nan_aircraft.yaml";
  {
    std::ifstream in(std::string(TERN_EKF_AIRCRAFT_DIR) + "/anaconda.yaml");
    std::ofstream out(bad);
    for (std::string line; std::getline(in, line);) out << (line.rfind("  C_L_alpha:", 0) == 0 ? "  C_L_alpha: .nan" : line) << "\n";
  }
  testing::HarnessOptions opt;
  opt.aircraft_file = bad.string();
  try {
    testing::Harness h(std::make_unique<EstimatorEkf>(), {}, opt);
    FAIL("a NaN coefficient was accepted");
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    CHECK(what.rfind(bad.string() + ":", 0) == 0);
    CHECK(what.find(": aero.C_L_alpha: value .nan is not finite") != std::string::npos);
  }
  std::filesystem::remove(bad);
  // without an aircraft file the zero-sideslip pseudo-measurement stays in use
  testing::Harness plain(std::make_unique<EstimatorEkf>());
  CHECK(real(plain, "mass") == 0.0);
  CHECK_FALSE(dynamic_cast<const EstimatorEkf&>(plain.plugin()).estimator().config().side_force_active());
}

TEST_CASE("plugin: every parameter has a unit or is dimensionless, a range and a description") {
  testing::Harness h(std::make_unique<EstimatorEkf>());
  CHECK(h.plugin().params().size() > 40);
  for (const ParamBase* prm : h.plugin().params()) {
    INFO(prm->name());
    CHECK_FALSE(prm->spec().description.empty());
    CHECK(prm->spec().min <= prm->spec().max);
  }
}

TEST_CASE("plugin: the Earth's field from the World Magnetic Model at the origin; a fixed value set is an override") {
  const auto field_after_origin = [](std::map<std::string, ParamValue> params) {
    params.emplace("gnss_req_hold_time", 0.0);  // fly.hpp settled_receiver
    testing::Harness h(std::make_unique<EstimatorEkf>(), std::move(params));
    TruthSim sim(turning_flight());
    feed(h, sim, 1.0, [] {});
    const auto& est = dynamic_cast<EstimatorEkf&>(h.plugin()).estimator();
    REQUIRE(est.origin_valid());
    return est.earth_field();
  };
  // the model at the origin on mag_model_date (Provo in mid 2025: 10.63 deg, 65.21 deg, 50.56 uT;
  // sdk/tests/test_magnetic_model.cpp checks the model itself against NOAA's test values)
  const tern::MagneticField model = field_after_origin({});
  CHECK(model.model == "WMM-2025");
  CHECK_FALSE(model.extrapolated);
  const auto origin = turning_flight();
  const tern::MagneticField expected = tern::world_magnetic_field(origin.lat0, origin.lon0, origin.alt0, 2025.4958904109589);
  CHECK(model.declination == doctest::Approx(expected.declination).epsilon(1e-4));  // the origin is a noisy fix
  // a date outside the models' spans is flagged
  CHECK(field_after_origin({{"mag_model_date", 2035.0}}).extrapolated);
  // one fixed value set: the configured field, the model off
  const tern::MagneticField fixed = field_after_origin({{"mag_declination", 0.2}});
  CHECK(fixed.model == "configured");
  CHECK(fixed.declination == 0.2);
  // unless the mission asks for the model as well
  CHECK(field_after_origin({{"mag_declination", 0.2}, {"mag_field_from_model", true}}).model == "WMM-2025");
}

TEST_CASE("plugin: the GNSS start-up checks hold the origin for gnss_req_hold_time (PX4 EKF2_REQ_GPS_H, 10 s); summary gnss_checks_wait") {
  testing::Harness h(std::make_unique<EstimatorEkf>());
  CHECK(std::get<double>(h.plugin().find_param("gnss_req_hold_time")->value()) == 10.0);
  CHECK(std::get<std::int64_t>(h.plugin().find_param("gnss_check")->value()) == 1023);
  SimOptions o;
  o.static_mode = true;  // at rest: the drift checks run too
  TruthSim sim(o);
  const auto& est = dynamic_cast<EstimatorEkf&>(h.plugin()).estimator();
  feed(h, sim, 9.9, [] {});
  CHECK_FALSE(est.origin_valid());
  CHECK_FALSE(h.output<msg::State>("state").valid);
  feed(h, sim, 1.0, [] {});
  REQUIRE(est.origin_valid());
  double wait = -1.0;
  for (const auto& [name, value] : h.plugin().summary())
    if (name == "gnss_checks_wait") wait = value;
  CHECK(wait >= 10.0);
  CHECK(wait < 10.15);  // the first fix after the hold (10 Hz)
}
