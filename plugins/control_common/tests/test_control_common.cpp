#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "control_common/autopilot.hpp"
#include "control_common/pid.hpp"
#include "linear_model.hpp"

using namespace tern::control;

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
}

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
  const double phi_c = lat.course(179 * kDeg, -179 * kDeg, 0.0, 0.0, 0.01);
  CHECK(phi_c == doctest::Approx(-2.0 * 2 * kDeg));
  CHECK(wrap_angle(3.5 * 3.14159265358979323846) == doctest::Approx(-0.5 * 3.14159265358979323846));
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
