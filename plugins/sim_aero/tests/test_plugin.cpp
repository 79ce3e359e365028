// Plugin-level tests of sim_aero through the SDK harness: rates, drop-outs, truth, determinism.
#include <doctest/doctest.h>

#include <dlfcn.h>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "sim_aero_plugin.hpp"
#include "tern/testing/harness.hpp"

using tern::from_seconds;
using tern::Nanos;
namespace msg = tern::msg;

namespace {
const std::string kAircraftDir = TERN_AIRCRAFT_DIR;

tern::testing::Harness make(std::map<std::string, tern::ParamValue> params, std::uint64_t seed = 1) {
  tern::testing::HarnessOptions o;
  o.instance = "sim";
  o.seed = seed;
  o.aircraft_file = kAircraftDir + "/anaconda.yaml";
  return tern::testing::Harness(std::make_unique<tern::sim_aero::SimAero>(), std::move(params), o);
}

void run(tern::testing::Harness& h, double seconds) {
  const Nanos dt = 2'500'000;
  for (Nanos t = 0; t <= from_seconds(seconds); t += dt) h.step(t);
}
}  // namespace

TEST_CASE("plugin: sensors publish at their own rates; truth is filled") {
  auto h = make({{"init_mode", std::string("trim")}});
  run(h, 1.0);  // steps at 0, 2.5 ms, ..., 1 s
  CHECK(h.published("imu") == 401);
  CHECK(h.published("mag") == 51);
  CHECK(h.published("baro") == 101);
  CHECK(h.published("diff_pressure") == 101);
  CHECK(h.published("gnss") == 11);
  CHECK(h.published("range") == 51);
  CHECK(h.published("truth") == 401);
  CHECK(h.published("rc") == 51);
  CHECK(h.published("fcu_status") == 11);
  const auto& s = h.output<msg::State>("truth");
  CHECK(s.stamp == from_seconds(1.0));
  CHECK(s.Va == doctest::Approx(17.0).epsilon(0.01));  // no controller: trim inputs held
  CHECK(s.Vg == doctest::Approx(17.0).epsilon(0.01));
  CHECK(s.p_n == doctest::Approx(17.0).epsilon(0.02));
  CHECK(s.altitude() == doctest::Approx(100.0).epsilon(0.01));
  CHECK(std::fabs(s.chi) < 0.01);
  CHECK(s.origin_lat == 40.2463724);
  CHECK(s.valid);
  CHECK(s.quat.norm() == doctest::Approx(1.0));
  const auto& g = h.output<msg::Gnss>("gnss");
  CHECK(g.fix_type == msg::FixType::fix_3d);
  CHECK(g.alt == doctest::Approx(1387.0 + 100.0).epsilon(1e-3));
  CHECK(h.output<msg::FcuStatus>("fcu_status").armed);
  const auto& imu = h.output<msg::Imu>("imu");
  CHECK(imu.accel.z() == doctest::Approx(-9.81).epsilon(0.1));  // lift = weight: -g in z
}

TEST_CASE("plugin: a sensor can be switched off or dropped out for a time window") {
  auto h = make({{"imu_enabled", false}, {"baro_dropout", std::vector<double>{0.2, 0.5}}, {"gnss_dropout", std::vector<double>{0.3, 0.6}}});
  int gnss_nofix = 0;
  Nanos last_baro = -1;
  for (Nanos t = 0; t <= from_seconds(1.0); t += 2'500'000) {
    const auto before = h.published("gnss");
    h.step(t);
    if (h.published("gnss") != before && h.output<msg::Gnss>("gnss").fix_type == msg::FixType::none) ++gnss_nofix;
    if (h.published("baro") > 0) {
      last_baro = h.output<msg::Baro>("baro").stamp;
      CHECK((last_baro < from_seconds(0.2) || last_baro >= from_seconds(0.5)));
    }
  }
  CHECK(h.published("imu") == 0);
  CHECK(h.published("baro") == 101 - 30);
  CHECK(h.published("gnss") == 11);  // the receiver keeps reporting, without a fix
  CHECK(gnss_nofix == 3);            // 0.3, 0.4, 0.5 s
  CHECK(h.output<msg::Gnss>("gnss").fix_type == msg::FixType::fix_3d);
}

TEST_CASE("plugin: on the ground without a controller the aircraft waits; actuators fly it") {
  {
    auto hw = make({{"wind", std::vector<double>{0.0, 3.0, 0.0}}});
    hw.step(0);
    CHECK(hw.output<msg::State>("truth").w_e == 3.0);  // wind acts from the first sample
    CHECK(hw.output<msg::State>("truth").Va == doctest::Approx(3.0));
  }
  auto h = make({});
  run(h, 2.0);
  CHECK(h.output<msg::State>("truth").Vg < 0.01);
  msg::Actuators a;
  a.delta_t = 1.0;
  a.delta_e = 0.1;
  h.set_input("actuators", a);
  for (Nanos t = from_seconds(2.0); t <= from_seconds(5.0); t += 2'500'000) h.step(t);
  CHECK(h.output<msg::State>("truth").altitude() > 3.0);
  a.delta_a = std::nan("");
  h.set_input("actuators", a);
  CHECK_THROWS_WITH_AS(h.step(from_seconds(5.1)), "actuators: delta_a is not finite", std::runtime_error);
}

TEST_CASE("plugin: the same seed gives bit-identical sensor streams; another seed differs") {
  auto fly = [](std::uint64_t seed) {
    auto h = make({{"init_mode", std::string("trim")}, {"turbulence", std::string("light")}}, seed);
    run(h, 2.0);
    return std::make_tuple(h.output<msg::State>("truth"), h.output<msg::Imu>("imu"), h.output<msg::Gnss>("gnss"));
  };
  const auto a = fly(42), b = fly(42), c = fly(43);
  CHECK(std::get<0>(a).p_n == std::get<0>(b).p_n);
  CHECK(std::get<0>(a).psi == std::get<0>(b).psi);
  CHECK(std::get<1>(a).accel == std::get<1>(b).accel);
  CHECK(std::get<1>(a).gyro == std::get<1>(b).gyro);
  CHECK(std::get<2>(a).lat == std::get<2>(b).lat);
  CHECK(std::get<1>(a).accel != std::get<1>(c).accel);
  CHECK(std::get<0>(a).p_n != std::get<0>(c).p_n);
}

TEST_CASE("plugin: bad parameters and files are refused with one line") {
  CHECK_THROWS_WITH_AS(make({{"gnss_dropout", std::vector<double>{1.0}}}),
                       "parameter 'sim.gnss_dropout': needs pairs [start, end], got 1 values", tern::ParamError);
  CHECK_THROWS_WITH_AS(make({{"imu_rate", 390.0}}), doctest::Contains("parameter 'sim.imu_rate': rate 390"), tern::ParamError);
  CHECK_THROWS_WITH_AS(make({{"aircraft", std::string("/nonexistent/plane.yaml")}}), "/nonexistent/plane.yaml: cannot open aircraft file",
                       std::runtime_error);
  CHECK_THROWS_AS(make({{"init_mode", std::string("orbit")}}), tern::ParamError);
}

TEST_CASE("plugin: noise and bias parameters reach the sensors (all zero: sensors read the truth)") {
  auto h = make({{"init_mode", std::string("trim")},
                 {"accel_noise", 0.0},
                 {"accel_bias_range", 0.0},
                 {"accel_bias_walk", 0.0},
                 {"gyro_noise", 0.0},
                 {"gyro_bias_range", 0.0},
                 {"gyro_bias_walk", 0.0},
                 {"baro_noise", 0.0},
                 {"baro_bias_range", 0.0},
                 {"baro_bias_walk", 0.0},
                 {"diff_pressure_noise", 0.0},
                 {"diff_pressure_bias_range", 0.0},
                 {"diff_pressure_bias_walk", 0.0},
                 {"mag_noise", 0.0},
                 {"mag_gm_sigma", 0.0},
                 {"gnss_h_sigma", 0.0},
                 {"gnss_v_sigma", 0.0},
                 {"gnss_vel_noise", 0.0},
                 {"origin_alt", 100.0},
                 {"wind", std::vector<double>{2.0, -1.0, 0.0}}});
  run(h, 1.0);
  const auto& s = h.output<msg::State>("truth");
  const auto& imu = h.output<msg::Imu>("imu");
  CHECK(imu.stamp == s.stamp);
  CHECK(imu.gyro.x() == s.p);
  CHECK(imu.gyro.z() == s.r);
  CHECK(s.b_x == 0.0);
  CHECK(h.output<msg::Baro>("baro").pressure == doctest::Approx(tern::sim::standard_pressure(100.0 + s.altitude())).epsilon(1e-12));
  CHECK(h.output<msg::DiffPressure>("diff_pressure").pressure == doctest::Approx(0.5 * 1.2682 * s.Va * s.Va).epsilon(0.01));
  const auto& g = h.output<msg::Gnss>("gnss");
  CHECK(g.vel.x() == doctest::Approx(s.v_n).epsilon(1e-6));
  CHECK(g.alt == doctest::Approx(100.0 + s.altitude()).epsilon(1e-6));
  CHECK(s.w_n == 2.0);
  CHECK(s.w_e == -1.0);
  // The wind blows the aircraft along: ground speed differs from airspeed.
  CHECK(s.Vg != doctest::Approx(s.Va).epsilon(0.01));
  const auto& m = h.output<msg::Mag>("mag");
  CHECK(m.field.norm() == doctest::Approx(5.07163e-5).epsilon(1e-6));
}

TEST_CASE("plugin: sensor_profile sets every default; a single parameter still overrides it") {
  auto ideal = make({{"sensor_profile", std::string("ideal")}, {"init_mode", std::string("trim")}});
  auto real = make({{"sensor_profile", std::string("realistic")}, {"gnss_latency", 0.2}});
  auto dflt = make({});
  const tern::sim::SensorParams r = tern::sim::sensor_profile("realistic");
  auto value = [](tern::testing::Harness& h, const char* name) { return std::get<double>(h.plugin().find_param(name)->value()); };
  CHECK(std::get<std::string>(dflt.plugin().find_param("sensor_profile")->value()) == "rosflight");
  CHECK(value(dflt, "gnss_h_sigma") == tern::sim::SensorParams{}.gnss_h_sigma);
  CHECK(value(real, "gnss_h_sigma") == r.gnss_h_sigma);
  CHECK(value(real, "accel_vibration") == r.accel_vibration);
  CHECK(value(real, "servo_rate_limit") == tern::sim::actuator_profile("realistic").servo_rate_limit);
  CHECK(value(real, "servo_rate_limit") > 0.0);
  CHECK(value(real, "gnss_latency") == 0.2);  // the override wins over the profile's value
  CHECK(value(ideal, "accel_noise") == 0.0);
  CHECK_THROWS_AS(make({{"sensor_profile", std::string("perfect")}}), tern::ParamError);
  // ideal: the sensors read the truth
  run(ideal, 0.5);
  const auto& s = ideal.output<msg::State>("truth");
  CHECK(ideal.output<msg::Imu>("imu").gyro.y() == s.q);
  CHECK(ideal.output<msg::Gnss>("gnss").vel.x() == doctest::Approx(s.v_n).epsilon(1e-9));
}

TEST_CASE("plugin: sensor_profile set between flights moves every default nobody set; set ones stay") {
  auto h = make({{"sensor_profile", std::string("realistic")}, {"gnss_latency", 0.2}});
  auto value = [&h](const char* name) { return std::get<double>(h.plugin().find_param(name)->value()); };
  h.set_param("accel_noise", 0.5);  // set by the user after configure()
  h.set_param("sensor_profile", std::string("ideal"));
  const tern::sim::SensorParams ideal = tern::sim::sensor_profile("ideal");
  CHECK(value("gnss_h_sigma") == ideal.gnss_h_sigma);
  CHECK(value("gyro_noise") == ideal.gyro_noise);
  CHECK(value("servo_rate_limit") == tern::sim::actuator_profile("ideal").servo_rate_limit);
  CHECK(value("gnss_latency") == 0.2);  // the mission set it
  CHECK(value("accel_noise") == 0.5);   // the user set it
  h.set_param("sensor_profile", std::string("realistic"));
  CHECK(value("gnss_h_sigma") == tern::sim::sensor_profile("realistic").gnss_h_sigma);
  // the next flight flies the new profile: with "ideal" and no noise set, the gyro reads the truth
  auto g = make({{"init_mode", std::string("trim")}, {"accel_noise", 0.0}});
  g.set_param("sensor_profile", std::string("ideal"));
  g.reset();
  run(g, 0.5);
  CHECK(g.output<msg::Imu>("imu").gyro.y() == g.output<msg::State>("truth").q);
}

TEST_CASE("plugin: a GNSS fix is delivered gnss_latency after its time of validity, exact to the tick") {
  auto h = make(
      {{"init_mode", std::string("trim")}, {"gnss_latency", 0.12}, {"gnss_h_sigma", 0.0}, {"gnss_v_sigma", 0.0}, {"gnss_vel_noise", 0.0}});
  const Nanos dt = 2'500'000;
  std::uint64_t seen = 0;
  std::vector<Nanos> delivered, valid;
  std::vector<double> north_at_validity, north_reported;
  const tern::GeoOrigin origin(40.2463724, -111.6474138, 1387.0);
  std::map<Nanos, double> truth_north;
  for (Nanos t = 0; t <= from_seconds(1.0); t += dt) {
    h.step(t);
    truth_north[t] = h.output<msg::State>("truth").p_n;
    if (h.published("gnss") == seen) continue;
    seen = h.published("gnss");
    const auto& g = h.output<msg::Gnss>("gnss");
    delivered.push_back(g.stamp);
    CHECK(g.stamp == t);
    valid.push_back(g.time_of_validity);
    north_reported.push_back(origin.to_ned(g.lat, g.lon, g.alt).x());
    north_at_validity.push_back(truth_north.at(g.time_of_validity));
  }
  REQUIRE(delivered.size() == 9);  // valid at 0, 0.1, ..., 0.8 s; delivered at 0.12 ... 0.92 s
  for (std::size_t i = 0; i < delivered.size(); ++i) {
    CHECK(valid[i] == from_seconds(0.1 * static_cast<double>(i)));
    CHECK(delivered[i] - valid[i] == from_seconds(0.12));
    CHECK(north_reported[i] == doctest::Approx(north_at_validity[i]).epsilon(1e-9));  // where it was, not where it is
  }
}

TEST_CASE("plugin: scheduled 1-cosine gusts appear in the wind at their time; sub-steps of sim_rate") {
  auto h = make({{"init_mode", std::string("trim")},
                 {"sim_rate", 1000.0},  // 2.5 ms steps: sub-steps of 1, 1 and 0.5 ms
                 {"gusts", std::vector<double>{0.5, 1.0, 0.0, 4.0, 0.0}}});
  for (Nanos t = 0; t <= from_seconds(0.2); t += 2'500'000) h.step(t);
  CHECK(h.output<msg::State>("truth").w_e == 0.0);
  for (Nanos t = from_seconds(0.2) + 2'500'000; t <= from_seconds(1.0); t += 2'500'000) h.step(t);
  CHECK(h.output<msg::State>("truth").w_e == doctest::Approx(4.0));  // the peak, mid-gust
  for (Nanos t = from_seconds(1.0) + 2'500'000; t <= from_seconds(2.0); t += 2'500'000) h.step(t);
  CHECK(h.output<msg::State>("truth").w_e == 0.0);
  CHECK(h.published("imu") == 801);
  CHECK(h.output<msg::State>("truth").stamp == from_seconds(2.0));
  CHECK(h.output<msg::State>("truth").altitude() == doctest::Approx(100.0).epsilon(0.02));
  const auto summary = h.plugin().summary();
  CHECK(summary.at(0).first == "sim_steps");
  CHECK(summary.at(0).second == 2400.0);  // 3 sub-steps per 2.5 ms step
}

TEST_CASE("plugin: the shared object really unloads after dlclose (hot-swap)") {
  // The host has the SDK, spdlog, fmt and yaml-cpp loaded already, as this test does.
  const char* path = TERN_SIM_AERO_PLUGIN;
  void* h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
  REQUIRE_MESSAGE(h != nullptr, dlerror());
  CHECK(dlsym(h, "tern_plugin_handshake_v1") != nullptr);
  dlclose(h);
  CHECK(dlopen(path, RTLD_NOW | RTLD_NOLOAD) == nullptr);
}

TEST_CASE("plugin: the world's magnetic field is the model's at the origin on `date`; a set value overrides it") {
  const auto value = [](tern::testing::Harness& h, const char* name) { return std::get<double>(h.plugin().find_param(name)->value()); };
  const double mid_2025 = tern::decimal_year(2025, 7, 1);
  const tern::MagneticField provo = tern::world_magnetic_field(40.2463724, -111.6474138, 1387.0, mid_2025);
  auto h = make({{"sensor_profile", std::string("ideal")}, {"init_mode", std::string("air")}});
  CHECK(value(h, "mag_declination") == provo.declination);  // the parameters show the field in use
  CHECK(value(h, "mag_inclination") == provo.inclination);
  CHECK(value(h, "mag_intensity") == provo.intensity);
  h.step(0);  // level, heading north, error-free magnetometer: it reads the NED field
  CHECK((h.output<msg::Mag>("mag").field - provo.ned).norm() < 1e-15);

  // Between flights: a set declination stays; moving the origin or the date moves the rest.
  h.set_param("mag_declination", 0.3);
  h.set_param("origin_lat", 47.3977);
  h.set_param("origin_lon", 8.5456);
  const tern::MagneticField zurich = tern::world_magnetic_field(47.3977, 8.5456, 1387.0, mid_2025);
  CHECK(value(h, "mag_declination") == 0.3);
  CHECK(value(h, "mag_inclination") == zurich.inclination);
  h.set_param("date", std::string("2020-01-01"));
  const tern::MagneticField zurich_2020 = tern::world_magnetic_field(47.3977, 8.5456, 1387.0, 2020.0);
  CHECK(zurich_2020.model == "WMM-2020");
  CHECK(value(h, "mag_intensity") == zurich_2020.intensity);
  h.reset();
  h.step(0);
  const Eigen::Vector3d want =
      zurich_2020.intensity * Eigen::Vector3d(std::cos(zurich_2020.inclination) * std::cos(0.3),
                                              std::cos(zurich_2020.inclination) * std::sin(0.3), std::sin(zurich_2020.inclination));
  CHECK((h.output<msg::Mag>("mag").field - want).norm() < 1e-15);

  // A mission that sets the origin gets that origin's field from the start.
  auto z = make({{"origin_lat", 47.3977}, {"origin_lon", 8.5456}});
  CHECK(value(z, "mag_declination") == zurich.declination);
  CHECK_THROWS_WITH_AS(make({{"date", std::string("2025-02-30")}}),
                       "parameter 'sim.date': date '2025-02-30': February 2025 has 28 days, not day 30", tern::ParamError);
}

TEST_CASE("plugin: a wing tip on the ground ends the flight as a crash naming it, with its speed in the summary") {
  // 1.5 m up at 17 m/s, full right aileron: the right wing tip strikes within a second
  auto h = make({{"init_mode", std::string("air")}, {"init_altitude", 1.5}});
  msg::Actuators a;
  a.delta_a = 0.6;
  a.delta_t = 0.5;
  h.set_input("actuators", a);
  run(h, 2.0);
  REQUIRE(h.end_request().has_value());
  CHECK(h.end_request()->first == "crash");
  CHECK(h.end_request()->second.find("the right wing tip struck the ground at") != std::string::npos);
  std::map<std::string, double> s;
  for (const auto& [name, value] : h.plugin().summary()) s[name] = value;
  CHECK(s["sim_crashed"] == 1.0);
  CHECK(s["impact_hard_point"] == 1.0);  // the first of anaconda.yaml's structure: the right wing tip
  CHECK(s["impact_wheel"] == 0.0);
  CHECK(s["impact_point_speed_mps"] > 5.0);  // flying at 17 m/s
  CHECK(s["impact_point_sink_mps"] > 0.0);
}

TEST_CASE("plugin: the range finder measures the height at 20 m in trim, and switching it off changes no other sensor") {
  auto fly = [](bool range) {
    auto h = make(
        {{"init_mode", std::string("trim")}, {"init_altitude", 20.0}, {"turbulence", std::string("light")}, {"range_enabled", range}}, 7);
    run(h, 2.0);
    return std::make_tuple(h.output<msg::Imu>("imu"), h.output<msg::Gnss>("gnss"), h.output<msg::Baro>("baro"),
                           h.published("range") > 0 ? h.output<msg::Range>("range").distance : 0.0, h.output<msg::State>("truth"));
  };
  const auto on = fly(true), off = fly(false);
  CHECK(std::get<0>(on).accel == std::get<0>(off).accel);  // its noise has a generator of its own
  CHECK(std::get<1>(on).lat == std::get<1>(off).lat);
  CHECK(std::get<2>(on).pressure == std::get<2>(off).pressure);
  const auto& s = std::get<4>(on);
  CHECK(std::get<3>(on) == doctest::Approx(s.altitude() / (std::cos(s.phi) * std::cos(s.theta))).epsilon(0.01));
}
