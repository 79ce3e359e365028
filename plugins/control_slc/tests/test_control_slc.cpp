// control_slc plugin tests: the plugin in the SDK harness, flying the uavbook's linearised
// models (control_common/testing/linear_model.hpp) with the gains files
// configs/gains/*.yaml, as the host would run it.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "control_common/testing/closed_loop.hpp"
#include "control_slc.hpp"

using namespace tern;
using namespace tern::control;
using namespace tern::control::testmodel;

namespace {

struct Aircraft {
  const char* gains;
  Coefficients k;
};
const Aircraft kAircraft[] = {{TERN_GAINS_DIR "/anaconda.yaml", anaconda()}, {TERN_GAINS_DIR "/aerosonde.yaml", aerosonde()}};

std::unique_ptr<ClosedLoop> make(const Aircraft& a) { return settled_loop(std::make_unique<ControlSlc>(), a.k, a.gains); }
}  // namespace

TEST_CASE("slc: 10 m altitude step settles within 2 m in < 15 s with < 3 m overshoot") {
  for (const auto& a : kAircraft) {
    CAPTURE(a.gains);
    auto Lp = make(a);
    auto& L = *Lp;
    const double h0 = L.plant.h;
    L.cmd.h_c = h0 + 10.0;
    StepResponse r{h0, h0 + 10.0, 2.0};
    const double t0 = to_seconds(L.t);
    L.run(40.0, [&](double t, const LinearAircraft& p) { r.add(t - t0, p.h); });
    MESSAGE(std::string(a.gains), ": overshoot ", r.overshoot, " m, settles (2 m) at ", r.settle_time, " s");
    CHECK(r.overshoot < 3.0);
    CHECK(r.settle_time < 15.0);
    CHECK(std::fabs(L.plant.h - (h0 + 10.0)) < 0.5);  // and gets there (integrator)
    // down again
    StepResponse d{h0 + 10.0, h0, 2.0};
    L.cmd.h_c = h0;
    const double t1 = to_seconds(L.t);
    L.run(40.0, [&](double t, const LinearAircraft& p) { d.add(t - t1, p.h); });
    CHECK(d.overshoot < 3.0);
    CHECK(d.settle_time < 15.0);
  }
}

TEST_CASE("slc: 90-degree course step overshoots < 10 degrees, either way and across +-180") {
  for (const auto& a : kAircraft) {
    CAPTURE(a.gains);
    for (double chi_c : {90.0, -90.0, 170.0}) {
      auto Lp = make(a);
      auto& L = *Lp;
      const double start = chi_c == 170.0 ? -100.0 : 0.0;  // -100 -> 170: 90 deg left across 180
      L.cmd.chi_c = start * kRadPerDeg;
      L.run(30.0);
      L.cmd.chi_c = chi_c * kRadPerDeg;
      const double dir = chi_c == 170.0 ? -1.0 : (chi_c > 0 ? 1.0 : -1.0);
      double overshoot = 0.0;
      L.run(40.0, [&](double, const LinearAircraft& p) {
        overshoot = std::max(overshoot, dir * wrap_pi(p.chi - chi_c * kRadPerDeg) / kRadPerDeg);
      });
      MESSAGE(std::string(a.gains), ": course step to ", chi_c, " deg overshoots ", overshoot, " deg");
      CHECK(overshoot < 10.0);
      CHECK(std::fabs(wrap_pi(L.plant.chi - chi_c * kRadPerDeg)) < 1.0 * kRadPerDeg);
      CHECK(std::fabs(L.plant.phi) <= 0.7854 + 0.05);  // roll limit respected
    }
  }
}

TEST_CASE("slc: 3 m/s airspeed step settles in < 10 s") {
  for (const auto& a : kAircraft) {
    CAPTURE(a.gains);
    for (double step : {3.0, -3.0}) {
      auto Lp = make(a);
      auto& L = *Lp;
      const double V0 = L.plant.Va;
      L.cmd.Va_c = V0 + step;
      StepResponse r{V0, V0 + step, 0.3};  // settled: within 10 % of the step
      const double t0 = to_seconds(L.t);
      double h_dev = 0.0;
      const double h0 = L.plant.h;
      L.run(30.0, [&](double t, const LinearAircraft& p) {
        r.add(t - t0, p.Va);
        h_dev = std::max(h_dev, std::fabs(p.h - h0));
      });
      MESSAGE(std::string(a.gains), ": airspeed step ", step, " m/s settles (0.3 m/s) at ", r.settle_time, " s, altitude deviation ", h_dev,
              " m");
      CHECK(r.settle_time < 10.0);
      CHECK(h_dev < 5.0);
    }
  }
}

TEST_CASE("slc: take_over is bumpless (first command within 0.05 rad of the last)") {
  auto Lp = make(kAircraft[0]);
  auto& L = *Lp;
  L.cmd.h_c += 20.0;
  L.cmd.chi_c = 60 * kRadPerDeg;
  L.run(2.0);
  msg::Actuators last;
  last.delta_a = L.last.delta_a + 0.2;                                                  // another controller commanded something else
  last.delta_e = L.last.delta_e > 0.0 ? L.last.delta_e - 0.15 : L.last.delta_e + 0.15;  // within max_e
  last.delta_r = 0.1;
  last.delta_t = 0.3;
  L.h.plugin().take_over(last);
  L.run(0.01);
  const auto& a = L.h.output<msg::Actuators>("actuators");
  CHECK(std::fabs(a.delta_a - last.delta_a) < 0.05);
  CHECK(std::fabs(a.delta_e - last.delta_e) < 0.05);
  CHECK(std::fabs(a.delta_r - last.delta_r) < 0.05);
  CHECK(std::fabs(a.delta_t - last.delta_t) < 0.05);
  // and keeps flying: no step larger than 0.05 rad afterwards, altitude reached
  Surfaces prev = L.last;
  double max_jump = 0.0;
  for (int i = 0; i < 3000; ++i) {
    L.run(0.01);
    max_jump = std::max({max_jump, std::fabs(L.last.delta_a - prev.delta_a), std::fabs(L.last.delta_e - prev.delta_e)});
    prev = L.last;
  }
  CHECK(max_jump < 0.08);  // the loops' own response to the disturbed state: no jumps (< 8 rad/s)
  CHECK(std::fabs(L.plant.h - L.cmd.h_c) < 2.0);
}

TEST_CASE("slc: out-of-range gains are rejected") {
  CHECK_THROWS_AS(testing::Harness(std::make_unique<ControlSlc>(), {{"roll_kp", -0.1}}), ParamError);
  CHECK_THROWS_AS(testing::Harness(std::make_unique<ControlSlc>(), {{"altitude_ki", 100.0}}), ParamError);
  CHECK_THROWS_AS(testing::Harness(std::make_unique<ControlSlc>(), {{"manual_mode", std::string("acro")}}), ParamError);
  CHECK_THROWS_AS(testing::Harness(std::make_unique<ControlSlc>(), {{"min_t", 0.8}, {"max_t", 0.5}}), ParamError);
  testing::Harness h(std::make_unique<ControlSlc>());
  CHECK_THROWS_AS(h.set_param("pitch_kd", std::numeric_limits<double>::quiet_NaN()), ParamError);
  CHECK_THROWS_AS(h.set_param("max_t", 1.5), ParamError);
  // every value of the gains files is accepted
  for (const auto& a : kAircraft) CHECK_NOTHROW(testing::Harness(std::make_unique<ControlSlc>(), load_gains(a.gains)));
}

TEST_CASE("slc: a gain changed in flight takes effect at the next step") {
  auto Lp = make(kAircraft[0]);
  auto& L = *Lp;
  L.cmd.chi_c = 0.5;
  L.h.set_param("roll_rate_max", 0.0);  // no slew limit: the course loop's output is the roll command
  L.h.set_param("course_kp", 0.0);
  L.h.set_param("course_ki", 0.0);
  L.run(0.01);
  CHECK(L.h.output<msg::ControllerInternals>("controller_internals").phi_c == doctest::Approx(0.0).epsilon(1e-3));
  L.h.set_param("course_kp", 1.0);
  L.run(0.01);
  CHECK(L.h.output<msg::ControllerInternals>("controller_internals").phi_c > 0.3);
}

TEST_CASE("slc: a NaN state holds the last command, no NaN reaches the actuators") {
  auto Lp = make(kAircraft[0]);
  auto& L = *Lp;
  const Surfaces before = L.last;
  auto s = to_state(L.plant, L.t);
  s.theta = std::numeric_limits<double>::quiet_NaN();
  s.Va = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 10; ++i) {
    L.h.set_input("state", s);
    L.h.step(L.t += from_seconds(0.01));
    const auto& a = L.h.output<msg::Actuators>("actuators");
    CHECK(std::isfinite(a.delta_a));
    CHECK(std::isfinite(a.delta_e));
    CHECK(std::isfinite(a.delta_t));
    CHECK(a.delta_e == before.delta_e);
  }
  auto cmd = L.cmd;
  cmd.h_c = std::numeric_limits<double>::quiet_NaN();
  L.h.set_input("controller_command", cmd);
  L.h.set_input("state", to_state(L.plant, L.t));
  L.h.step(L.t += from_seconds(0.01));
  CHECK(L.h.output<msg::Actuators>("actuators").delta_t == before.delta_t);
  // recovers when the inputs are finite again
  L.run(5.0);
  CHECK(std::fabs(L.plant.h - L.cmd.h_c) < 1.0);
  CHECK(L.h.plugin().summary().front().second == doctest::Approx(11.0));
}

TEST_CASE("slc: roll and pitch overrides of the controller command are honoured") {
  auto Lp = make(kAircraft[0]);
  auto& L = *Lp;
  L.cmd.override_phi = true;
  L.cmd.phi_c = 0.3;
  L.cmd.override_theta = true;
  L.cmd.theta_c = 0.1;
  L.run(5.0);
  CHECK(L.plant.phi == doctest::Approx(0.3).epsilon(0.05));
  CHECK(L.h.output<msg::ControllerInternals>("controller_internals").theta_c == doctest::Approx(0.1));
  CHECK(L.plant.theta > 0.03);  // nose up (the PD pitch loop has a DC gain < 1)
}

TEST_CASE("slc: flight phases: takeoff throttle and wings level, climb and cruise") {
  auto Lp = make(kAircraft[0]);
  auto& L = *Lp;
  msg::FlightPhase ph;
  ph.phase = msg::Phase::takeoff;
  L.h.set_input("flight_phase", ph);
  L.cmd.chi_c = 1.0;
  L.run(3.0);
  const auto& in = L.h.output<msg::ControllerInternals>("controller_internals");
  CHECK(in.phi_c == 0.0);
  CHECK(in.alt_zone == static_cast<std::uint8_t>(msg::Phase::takeoff));
  CHECK(L.h.output<msg::Actuators>("actuators").delta_t == doctest::Approx(1.0).epsilon(0.02));
  CHECK(in.theta_c == doctest::Approx(0.1745));  // airspeed above rotation_Va: takeoff pitch
  ph.phase = msg::Phase::climb;
  L.h.set_input("flight_phase", ph);
  L.cmd.h_c = L.plant.h + 30.0;
  L.run(40.0);
  CHECK(std::fabs(L.plant.h - L.cmd.h_c) < 2.0);
  CHECK(std::fabs(wrap_pi(L.plant.chi - 1.0)) < 0.05);  // course hold in climb (default)
}

TEST_CASE("slc: manual modes from rc and fcu_status") {
  auto Lp = make(kAircraft[0]);
  auto& L = *Lp;
  msg::Rc rc;
  rc.roll = 0.5;
  rc.pitch = -0.5;
  rc.yaw = 0.0;
  rc.throttle = 0.4;
  rc.rc_override = true;
  L.h.set_input("rc", rc);
  L.run(0.01);
  const auto& a = L.h.output<msg::Actuators>("actuators");
  CHECK(a.delta_a == doctest::Approx(0.5 * 0.6981));  // max_a of anaconda.yaml
  CHECK(a.delta_e == doctest::Approx(0.305));
  CHECK(a.delta_t == doctest::Approx(0.4));
  // receiver failsafe: the override switch is not trusted, the autopilot flies
  rc.failsafe = true;
  L.h.set_input("rc", rc);
  L.run(0.01);
  CHECK(L.h.output<msg::Actuators>("actuators").delta_t == doctest::Approx(0.4));  // bumpless
  L.run(1.0);
  CHECK(std::fabs(L.h.output<msg::Actuators>("actuators").delta_t - 0.4) > 0.05);
  // the FCU reports the override: pass-through (from the last sticks)
  msg::FcuStatus f;
  f.rc_override = true;
  rc.failsafe = false;
  rc.rc_override = false;
  L.h.set_input("rc", rc);
  L.h.set_input("fcu_status", f);
  L.run(0.01);
  CHECK(L.h.output<msg::Actuators>("actuators").delta_a == doctest::Approx(0.5 * 0.6981));
  // angle mode selected by an aux channel: roll follows the stick's angle
  testing::Harness& h = L.h;
  h.set_param("angle_mode_aux", std::int64_t{2});
  rc.aux[2] = 1.0;
  rc.roll = 0.5;
  rc.pitch = 0.0;
  h.set_input("rc", rc);
  L.run(6.0);
  CHECK(L.plant.phi == doctest::Approx(0.5 * 0.7854).epsilon(0.05));
  // back to auto: no jump
  f.rc_override = false;
  h.set_input("fcu_status", f);
  const Surfaces before = L.last;
  L.run(0.01);
  CHECK(std::fabs(L.last.delta_a - before.delta_a) < 0.05);
  CHECK(std::fabs(L.last.delta_e - before.delta_e) < 0.05);
}

TEST_CASE("slc: no throttle before the estimator is valid; control starts when it is") {
  auto params = load_gains(kAircraft[0].gains);
  ClosedLoop L(std::make_unique<ControlSlc>(), kAircraft[0].k, params);
  msg::FlightPhase ph;
  ph.phase = msg::Phase::takeoff;
  L.h.set_input("flight_phase", ph);
  auto s = to_state(L.plant, 0);
  s.valid = false;
  L.h.set_input("state", s);
  L.h.set_input("controller_command", L.cmd);
  L.h.step(0);
  const auto& a = L.h.output<msg::Actuators>("actuators");
  CHECK(a.delta_t == 0.0);  // not the takeoff throttle
  CHECK(a.delta_e == doctest::Approx(std::get<double>(params["trim_e"])));
  s.valid = true;
  L.h.set_input("state", s);
  L.h.step(from_seconds(0.01));
  L.h.step(from_seconds(0.02));
  CHECK(L.h.output<msg::Actuators>("actuators").delta_t > 0.0);  // the takeoff begins
  L.run(2.0);
  CHECK(L.h.output<msg::Actuators>("actuators").delta_t > 0.8);
}
