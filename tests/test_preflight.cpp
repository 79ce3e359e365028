// Preflight: each arming check refuses with its own line; the flight holds (no controller) until
// the checks pass, then takes off; a time-out ends it with preflight_failed.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include "safety/preflight.hpp"
#include "test_util.hpp"

using namespace tern::core;
using tern::msg::Gnss;
using tern::msg::Innovations;
using tern::msg::State;

namespace {
State aligned() {
  State s;
  s.valid = true;
  s.status = tern::msg::StateStatus::ok;
  s.P_diag.fill(1e-4);                                                          // 0.6 deg tilt/yaw sigma, 1 cm position
  for (std::size_t i = 0; i < 3; ++i) s.P_diag[State::P_gyro_bias + i] = 1e-6;  // 0.06 deg/s
  return s;
}

Gnss good_fix() {
  Gnss g;
  g.fix_type = tern::msg::FixType::fix_3d;
  g.num_sats = 12;
  g.h_acc = 1.2;
  g.v_acc = 2.5;
  return g;
}

PreflightInputs inputs(const State* s, const Innovations* i, const Gnss* g) {
  PreflightInputs in;
  in.state = s;
  in.innovations = i;
  in.gnss = g;
  return in;
}

std::string only_failure(const PreflightInputs& in, const PreflightLimits& limits = {}) {
  const auto f = preflight_failures(in, limits);
  REQUIRE(f.size() == 1);
  return f[0];
}

std::string only_failure(const State* s, const Innovations* i, const Gnss* g) { return only_failure(inputs(s, i, g)); }

}  // namespace

TEST_CASE("preflight: an aligned estimator, a good fix and an aircraft at rest pass") {
  const State s = aligned();
  const Gnss g = good_fix();
  const Innovations i;  // nothing fused yet: no ratio
  CHECK(preflight_failures(inputs(&s, &i, &g), PreflightLimits{}).empty());
}

TEST_CASE("preflight: each check refuses with its own line") {
  const Gnss g = good_fix();
  CHECK(only_failure(nullptr, nullptr, nullptr) == "no state yet (estimator silent)");
  State s = aligned();
  s.valid = false;
  s.status = tern::msg::StateStatus::invalid;
  CHECK(only_failure(&s, nullptr, &g) == "estimator not ready (status invalid)");
  s = aligned();
  s.P_diag[7] = 0.05 * 0.05;
  CHECK(only_failure(&s, nullptr, &g) == "estimator not aligned: tilt sigma 2.86 deg > 2.29 deg");
  s = aligned();
  s.P_diag[8] = 0.3 * 0.3;
  CHECK(only_failure(&s, nullptr, &g) == "estimator not aligned: yaw sigma 17.2 deg > 9.7 deg");
  s = aligned();
  s.v_e = 3.0;
  CHECK(only_failure(&s, nullptr, &g) == "aircraft moving: ground speed 3.00 m/s > 2.00 m/s");
  s = aligned();
  Innovations i;
  i.gnss_vel = 1.7;
  CHECK(only_failure(&s, &i, &g).rfind("gnss velocity innovation test ratio 1.70 >= 1", 0) == 0);
  Gnss bad = good_fix();
  bad.h_acc = 4.2;
  CHECK(only_failure(&s, nullptr, &bad) == "GNSS h_acc 4.2 m > 2.5 m");
  bad = good_fix();
  bad.num_sats = 4;
  CHECK(only_failure(&s, nullptr, &bad) == "GNSS 4 satellites < 6");
  bad.fix_type = tern::msg::FixType::fix_2d;
  CHECK(only_failure(&s, nullptr, &bad) == "GNSS fix type 2 (3-D fix required)");
  s.P_diag[State::P_gyro_bias + 2] = 0.01 * 0.01;
  CHECK(only_failure(&s, nullptr, &g) == "estimator gyro bias not converged: sigma 0.57 deg/s > 0.29 deg/s");
}

TEST_CASE("preflight: a silent or non-finite sensor shows as the estimator's degraded or invalid status, named") {
  const Gnss g = good_fix();
  State s = aligned();
  s.status = tern::msg::StateStatus::degraded;
  s.degraded_sensors = tern::msg::sensor_bit::baro;
  CHECK(only_failure(&s, nullptr, &g) == "estimator not ready (status degraded: no usable baro (silent, non-finite or rejected))");
  s.valid = false;
  s.status = tern::msg::StateStatus::invalid;
  s.degraded_sensors = tern::msg::sensor_bit::imu | tern::msg::sensor_bit::mag;
  CHECK(only_failure(&s, nullptr, &g) == "estimator not ready (status invalid: no usable imu, mag (silent, non-finite or rejected))");
}

TEST_CASE("preflight: the FCU must be armed and error-free; RC must be heard when required") {
  const State s = aligned();
  const Gnss g = good_fix();
  PreflightInputs in = inputs(&s, nullptr, &g);
  tern::msg::FcuStatus fcu;
  in.fcu = &fcu;
  CHECK(only_failure(in) == "FCU disarmed (error code 0x00; the FCU link says what is missing)");
  fcu.armed = true;
  fcu.error_code = 0x20;
  CHECK(only_failure(in) == "FCU error code 0x20 (the FCU link says which)");
  fcu.error_code = 0;
  CHECK(preflight_failures(in, PreflightLimits{}).empty());
  PreflightLimits rc;
  rc.require_rc = true;
  CHECK(only_failure(in, rc) == "no RC frame yet (the config requires the transmitter: preflight_require_rc)");
  in.rc_age = 0.8;
  CHECK(only_failure(in, rc) == "RC silent for 0.8 s > 0.5 s (the config requires the transmitter)");
  in.rc_age = 0.02;
  CHECK(preflight_failures(in, rc).empty());
}

TEST_CASE("preflight: the wind seen at rest (airspeed, estimated wind) beyond preflight_max_wind refuses the takeoff") {
  State s = aligned();
  const Gnss g = good_fix();
  PreflightLimits l;
  l.max_wind = 8.0;
  s.Va = 7.9;
  CHECK(preflight_failures(inputs(&s, nullptr, &g), l).empty());
  s.Va = 9.0;  // a 9 m/s headwind on the pitot
  CHECK(only_failure(inputs(&s, nullptr, &g), l) ==
        "wind at rest 9.0 m/s > 8.0 m/s (airspeed 9.0 m/s, estimated wind 0.0 m/s): beyond the takeoff limit preflight_max_wind");
  s.Va = 0.0;
  s.w_n = 6.0;
  s.w_e = -6.0;  // the estimate's wind
  CHECK(only_failure(inputs(&s, nullptr, &g), l).rfind("wind at rest 8.5 m/s > 8.0 m/s", 0) == 0);
}

TEST_CASE("preflight: the flight holds with no controller until the checks pass, then takes off") {
  std::string cfg = base_config("", "phases: {takeoff: ctl, climb: ctl, cruise: ctl}\nphase_machine: {preflight_time: 0.5}\n");
  const std::string filter = "plugin: test_filter, trigger: imu}";
  cfg.replace(cfg.find(filter), filter.size(), "plugin: test_filter, trigger: imu, params: {valid: true}}");
  const FlightResult r = fly_yaml(cfg, "preflight_pass");
  REQUIRE(r.ok);
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  REQUIRE(s["phases"].size() >= 2);
  CHECK(s["phases"][0]["phase"] == "preflight");
  CHECK(s["phases"][1]["phase"] == "takeoff");
  CHECK(s["preflight_s"].get<double>() == doctest::Approx(0.5).epsilon(0.05));
  CHECK(s["controller_handovers"][0]["to"] == "(none)");
  CHECK(s["controller_handovers"][1]["to"] == "ctl");
}

TEST_CASE("preflight: an estimator that never aligns ends the flight with preflight_failed") {
  const FlightResult r = fly_yaml(
      base_config("", "phases: {takeoff: ctl, climb: ctl, cruise: ctl}\nphase_machine: {preflight_timeout: 1}\n"), "preflight_fail");
  CHECK_FALSE(r.ok);
  CHECK(r.end_reason == "preflight_failed: estimator not ready (status degraded)");
  CHECK(tern::to_seconds(r.flown) == doctest::Approx(1.0).epsilon(0.01));
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  CHECK(s["end_reason"] == r.end_reason);
}
