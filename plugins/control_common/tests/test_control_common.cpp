#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "tern/math.hpp"
#include "control_common/autopilot.hpp"
#include "control_common/pid.hpp"
#include "control_common/testing/linear_model.hpp"

using namespace tern::control;

namespace {}

TEST_CASE("pid: proportional, integral and derivative terms, saturation") {
  Pid pid({2.0, 1.0, 0.5, -1.0, 1.0});
  CHECK(pid.update(0.1, 0.0, 0.0) == doctest::Approx(0.2));
  // trapezoidal integral of a constant error 0.1 over 1 s (100 steps) -> 0.1
  for (int i = 0; i < 100; ++i) pid.update(0.1, 0.0, 0.01);
  CHECK(pid.integrator() == doctest::Approx(0.1));
  CHECK(pid.update(0.1, 0.2, 0.0) == doctest::Approx(0.2 + 0.1 - 0.1));
  CHECK(pid.update(5.0, 0.0, 0.0) == doctest::Approx(1.0));
  CHECK(pid.update(-5.0, 0.0, 0.0) == doctest::Approx(-1.0));
}

TEST_CASE("pid: the integrator does not wind up while the output is saturated") {
  Pid pid({1.0, 1.0, 0.0, -1.0, 1.0});
  for (int i = 0; i < 1000; ++i) pid.update(2.0, 0.0, 0.01);  // 10 s saturated high
  CHECK(pid.last_output() == doctest::Approx(1.0));
  CHECK(pid.integrator() <= 1.0 + 1e-12);  // |ki I| <= half the output range
  // error reverses: the output leaves saturation at once instead of after unwinding 20 units
  const double u = pid.update(-0.5, 0.0, 0.01);
  CHECK(u < 1.0);
}

TEST_CASE("pid: initialise gives the requested output (bumpless) and reports what it cannot reach") {
  Pid pid({0.5, 0.2, 0.1, -1.0, 1.0});
  CHECK(pid.initialise(0.3, 0.4, 0.1, 0.05) == doctest::Approx(0.0));
  CHECK(pid.update(0.4, 0.1, 0.0, 0.05) == doctest::Approx(0.3));
  Pid pd({0.5, 0.0, 0.0, -1.0, 1.0});  // no integrator: the remainder is reported
  CHECK(pd.initialise(0.3, 0.4, 0.0) == doctest::Approx(0.1));
}

TEST_CASE("dirty derivative and washout") {
  DirtyDerivative d(0.05);
  double v = 0.0;
  for (int i = 0; i <= 200; ++i) v = d.update(3.0 * i * 0.01, 0.01);  // ramp of slope 3
  CHECK(v == doctest::Approx(3.0).epsilon(1e-6));
  Washout w(0.5);
  w.update(0.0, 0.01);
  double y = w.update(1.0, 0.01);  // step
  CHECK(y == doctest::Approx(1.0).epsilon(0.01));
  for (int i = 0; i < 2000; ++i) y = w.update(1.0, 0.01);  // 20 s = 10 time constants
  CHECK(std::fabs(y) < 1e-3);
}

TEST_CASE("course errors are wrapped: the short way round") {
  LateralLoops lat;
  LateralGains g;
  g.course_ki = 0.0;
  lat.set_gains(g);
  // from -179 deg to +179 deg: turn left 2 deg, not right 358 deg
  const double phi_c = lat.course(179 * tern::kRadPerDeg, -179 * tern::kRadPerDeg, 0.0, 0.0, 0.01);
  CHECK(phi_c == doctest::Approx(-2.0 * 2 * tern::kRadPerDeg));
}

TEST_CASE("yaw damper opposes a yaw-rate change and washes out a steady turn") {
  LateralLoops lat;
  lat.yaw_damper(0.0, 0.01);
  const double dr = lat.yaw_damper(0.2, 0.01);  // nose-right rate: positive rudder yaws nose left
  CHECK(dr > 0.05);
  double last = dr;
  for (int i = 0; i < 3000; ++i) last = lat.yaw_damper(0.2, 0.01);
  CHECK(std::fabs(last) < 0.005);
}

namespace {
struct Loop {
  SlcLongitudinal law;
  Autopilot ap{law};
  testmodel::LinearAircraft plant{testmodel::anaconda()};
  Loop() {
    // an earlier design for the Anaconda (configs/gains/README.md)
    law.set_gains({0.1579, 0.0636, 0.0, 0.35, -0.35}, {0.0963, 0.0651, 0.0, 0.5676, 1.0, 0.0, 0.05});
    ap.set_pitch_gains({4.15, 0.0, 0.283, 0.1679, 0.61});
  }
};
}  // namespace

TEST_CASE("autopilot: a NaN state holds the last command and keeps the integrators") {
  Loop L;
  Command c{17.0, 100.0, 0.0, 0.0, 0.0, 0.0, false, false};
  AutopilotOutput o;
  for (int i = 0; i < 100; ++i) {
    o = L.ap.update(Mode::cruise, L.plant.state(), c, {}, 0.01);
    L.plant.step(o.surfaces, 0.01);
  }
  auto x = L.plant.state();
  x.theta = std::numeric_limits<double>::quiet_NaN();
  const auto held = L.ap.update(Mode::cruise, x, c, {}, 0.01);
  CHECK(held.held);
  CHECK(held.surfaces.finite());
  CHECK(held.surfaces.delta_e == o.surfaces.delta_e);
  c.h_c = std::numeric_limits<double>::infinity();
  CHECK(L.ap.update(Mode::cruise, L.plant.state(), c, {}, 0.01).held);
}

TEST_CASE("autopilot: take_over starts from the last command, and mode changes are bumpless") {
  Loop L;
  Command c{17.0, 110.0, 0.5, 0.0, 0.0, 0.0, false, false};
  L.plant.phi = 0.2;
  L.plant.q = 0.05;
  const Surfaces last{0.12, -0.05, 0.03, 0.8};
  L.ap.take_over(last);
  auto o = L.ap.update(Mode::cruise, L.plant.state(), c, {}, 0.01);
  CHECK(o.surfaces.delta_a == doctest::Approx(last.delta_a).epsilon(1e-9));
  CHECK(o.surfaces.delta_e == doctest::Approx(last.delta_e).epsilon(1e-9));
  CHECK(o.surfaces.delta_r == doctest::Approx(last.delta_r).epsilon(1e-9));
  CHECK(o.surfaces.delta_t == doctest::Approx(last.delta_t).epsilon(1e-9));
  // a run of steps: no surface moves more than 0.05 rad per 10 ms step
  Surfaces prev = o.surfaces;
  Mode modes[] = {Mode::cruise, Mode::climb, Mode::cruise};
  for (Mode m : modes) {
    for (int i = 0; i < 300; ++i) {
      L.plant.step(prev, 0.01);
      o = L.ap.update(m, L.plant.state(), c, {}, 0.01);
      CHECK(std::fabs(o.surfaces.delta_a - prev.delta_a) < 0.05);
      CHECK(std::fabs(o.surfaces.delta_e - prev.delta_e) < 0.05);
      prev = o.surfaces;
    }
  }
  // roll override on and off: no jump either
  c.override_phi = true;
  c.phi_c = -0.3;
  o = L.ap.update(Mode::cruise, L.plant.state(), c, {}, 0.01);
  CHECK(std::fabs(o.surfaces.delta_a - prev.delta_a) < 0.05);
}

TEST_CASE("autopilot: takeoff is wings level at takeoff throttle and rotates at rotation_Va") {
  Loop L;
  AutopilotSettings s;
  s.takeoff_throttle = 0.9;
  s.rotation_Va = 12.0;
  s.takeoff_pitch = 0.15;
  L.ap.set_settings(s);
  Command c{17.0, 50.0, 1.0, 0.0, 0.0, 0.0, false, false};
  VehicleState x;
  x.Va = 5.0;
  auto o = L.ap.update(Mode::takeoff, x, c, {}, 0.01);
  CHECK(o.phi_c == 0.0);
  CHECK(o.theta_c == 0.0);
  CHECK(o.surfaces.delta_t == doctest::Approx(0.9));
  x.Va = 12.5;
  o = L.ap.update(Mode::takeoff, x, c, {}, 0.01);
  CHECK(o.theta_c == doctest::Approx(0.15));
  x.Va = 11.0;  // latched for the phase
  o = L.ap.update(Mode::takeoff, x, c, {}, 0.01);
  CHECK(o.theta_c == doctest::Approx(0.15));
}

TEST_CASE("autopilot: manual pass-through and angle mode") {
  Loop L;
  Command c{17.0, 100.0, 0.0, 0.0, 0.0, 0.0, false, false};
  const Sticks st{0.5, 0.5, -1.0, 0.3};
  auto o = L.ap.update(Mode::manual_passthrough, L.plant.state(), c, st, 0.01);
  CHECK(o.surfaces.delta_a == doctest::Approx(0.5 * 0.6981));
  CHECK(o.surfaces.delta_e == doctest::Approx(-0.5 * 0.61));  // stick back: nose up: negative delta_e
  CHECK(o.surfaces.delta_r == doctest::Approx(0.523));        // stick left: nose left: positive delta_r
  CHECK(o.surfaces.delta_t == doctest::Approx(0.3));
  // angle mode: the aircraft settles at the stick's roll and pitch
  AutopilotSettings s;
  s.angle_roll_max = 0.6;
  s.angle_pitch_max = 0.3;
  L.ap.set_settings(s);
  for (int i = 0; i < 500; ++i) {
    o = L.ap.update(Mode::manual_angle, L.plant.state(), c, {0.5, 0.2, 0.0, 0.7}, 0.01);
    L.plant.step(o.surfaces, 0.01);
  }
  CHECK(L.plant.phi == doctest::Approx(0.3).epsilon(0.05));
  // the PD pitch loop tracks with its DC gain K_theta_DC (0.6 here) about the trim attitude
  CHECK(L.plant.theta - L.plant.coefficients().alpha_trim > 0.03);
  CHECK(o.surfaces.delta_t == doctest::Approx(0.7).epsilon(0.01));  // handover offset decayed
}

TEST_CASE("roll command shaping: slew limit, rate feed-forward, a ramp followed without the type-0 lag") {
  const auto k = testmodel::anaconda();
  LateralGains g;
  g.roll_kp = 1.86365;  // configs/gains/anaconda.yaml
  g.roll_kd = 0.0;
  g.roll_rate_max = 1.5;
  LateralLoops lat;
  lat.set_gains(g);
  // a 0 -> 0.6 rad step is slewed at 1.5 rad/s: 0.015 rad per 10 ms step, reached after 0.4 s
  CHECK(lat.shape_roll(0.0, 0.01) == 0.0);
  CHECK(lat.shape_roll(0.6, 0.01) == doctest::Approx(0.015));
  double phi_c = 0.0;
  for (int i = 0; i < 39; ++i) phi_c = lat.shape_roll(0.6, 0.01);
  CHECK(phi_c == doctest::Approx(0.6));
  CHECK(lat.p_c() > 1.0);  // the rate of the ramp (band-limited)
  for (int i = 0; i < 100; ++i) phi_c = lat.shape_roll(0.6, 0.01);
  CHECK(std::fabs(lat.p_c()) < 1e-3);
  // no limit when roll_rate_max = 0
  g.roll_rate_max = 0.0;
  lat.set_gains(g);
  CHECK(lat.shape_roll(-0.6, 0.01) == doctest::Approx(-0.6));

  // On the roll model phi/delta_a = a_phi2 / (s (s + a_phi1)) a 1.5 rad/s ramp lags by
  // p_c a_phi1 / (a_phi2 kp) = 0.15 rad without the feed-forward; with roll_ff = a_phi1/a_phi2
  // the lag is gone.
  auto ramp_lag = [&](double roll_ff) {
    LateralGains gg = g;
    gg.roll_rate_max = 1.5;
    gg.roll_ff = roll_ff;
    LateralLoops l;
    l.set_gains(gg);
    l.shape_roll(0.0, 0.01);  // the first command after a reset passes unshaped
    double phi = 0.0, p = 0.0, worst = 0.0;
    for (int i = 0; i < 100; ++i) {  // 1 s: the shaped command ramps 0 -> 0.785 in 0.52 s
      const double c = l.shape_roll(0.785, 0.01);
      const double da = l.roll(c, phi, p, 0.01);
      for (int j = 0; j < 10; ++j) {
        p += 0.001 * (-k.a_phi1 * p + k.a_phi2 * da);
        phi += 0.001 * p;
      }
      if (i > 20 && i < 50) worst = std::max(worst, std::fabs(l.shape_roll(c, 0.0) - phi));
    }
    return worst;
  };
  const double lag_without = ramp_lag(0.0), lag_with = ramp_lag(k.a_phi1 / k.a_phi2);
  MESSAGE("roll error on a 1.5 rad/s ramp: " << lag_without / tern::kRadPerDeg << " deg without, " << lag_with / tern::kRadPerDeg
                                             << " deg with the rate feed-forward");
  CHECK(lag_without > 0.1);
  CHECK(lag_with < 0.3 * lag_without);
}

TEST_CASE("autopilot: with a roll slew limit a transfer slews the roll command and leaves the course integrator clean") {
  Loop L;
  LateralGains g;
  g.course_kp = 2.77857;  // configs/gains/anaconda.yaml
  g.course_ki = 0.111143;
  g.roll_kp = 1.86365;
  g.roll_kd = 0.0;
  g.roll_ff = 0.185969;
  g.roll_rate_max = 1.5;
  L.ap.set_lateral_gains(g);
  // wings level, then a transfer with a 1-rad course error (as takeoff -> climb)
  Command c{17.0, 100.0, 1.0, 0.0, 0.0, 0.0, false, false};
  const Surfaces last{0.0, 0.1679, 0.0, 0.5676};
  L.ap.take_over(last);
  auto o = L.ap.update(Mode::climb, L.plant.state(), c, {}, 0.01);
  CHECK(o.surfaces.delta_a == doctest::Approx(0.0).epsilon(1e-9));
  CHECK(o.phi_c == doctest::Approx(0.0).epsilon(1e-9));
  Surfaces prev = o.surfaces;
  double prev_phi_c = o.phi_c;
  for (int i = 0; i < 1000; ++i) {  // 10 s
    L.plant.step(prev, 0.01);
    o = L.ap.update(Mode::climb, L.plant.state(), c, {}, 0.01);
    CHECK(std::fabs(o.phi_c - prev_phi_c) <= 1.5 * 0.01 + 1e-12);
    // no jump: the aileron follows the slewed command (its rate fed forward), as in any roll-in
    CHECK(std::fabs(o.surfaces.delta_a - prev.delta_a) < 0.1);
    prev = o.surfaces;
    prev_phi_c = o.phi_c;
  }
  // no wound-up course integrator holding the course off for tens of seconds
  CHECK(std::fabs(tern::wrap_pi(1.0 - L.plant.chi)) < 0.01);
}

TEST_CASE("flare: the throttle winds down with the height, and holds the airspeed floor a flare begun too high would lose") {
  tern::control::LandingSettings s;
  tern::control::FlareLaw f;
  f.start(3.0, 1.3, -0.05, 0.4);
  CHECK(f.throttle(3.0, 15.0, 12.0, 0.01, s) == doctest::Approx(0.4));  // above the floor: the schedule
  CHECK(f.throttle(1.5, 15.0, 12.0, 0.01, s) == doctest::Approx(0.2));
  CHECK(f.throttle(-0.5, 15.0, 12.0, 0.01, s) == doctest::Approx(0.0));  // at the touchdown height: idle
  // flared 2 m too high: the schedule is at idle while the aircraft is 2 m/s below the floor
  double t = 0.0;
  for (int i = 0; i < 200; ++i) t = f.throttle(0.0, 10.0, 12.0, 0.01, s);  // 2 s
  CHECK(t == doctest::Approx(0.1 * 2.0 + 0.1 * 4.0));                      // kp 2 m/s + ki 2 m/s x 2 s
  // back above the floor: the integrated deficit unwinds, the throttle returns to the schedule
  for (int i = 0; i < 1000; ++i) t = f.throttle(0.0, 13.0, 12.0, 0.01, s);
  CHECK(t == doctest::Approx(0.0));
  s.flare_airspeed_ratio = 0.0;  // (the autopilot passes Va_floor = ratio x Va_c)
  CHECK(f.throttle(0.0, 10.0, 0.0, 0.01, s) == doctest::Approx(0.0));
}
