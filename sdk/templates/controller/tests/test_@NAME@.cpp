// Tests of @NAME@: the loops alone (signs, saturation, closed loop on the uavbook's transfer
// functions) and the plugin through the SDK harness.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <memory>

#include "attitude_hold.hpp"
#include "plugin.hpp"
#include "tern/testing/harness.hpp"

using tern_@NAME@::AttitudeHold;

TEST_CASE("loops: signs of the corrections") {
  AttitudeHold h;
  const auto& g = h.gains();
  // left wing down (phi < 0): roll right, positive aileron
  CHECK(h.update({0.0, 0.0, 17.0}, {-0.1, 0.0, 0.0, 0.0, 17.0}, 0.01).delta_a > g.trim_a);
  // nose below the setpoint: nose up, elevator below trim
  CHECK(h.update({0.0, 0.1, 17.0}, {0.0, 0.0, 0.0, 0.0, 17.0}, 0.01).delta_e < g.trim_e);
  // too slow: more throttle than trim
  CHECK(h.update({0.0, 0.0, 17.0}, {0.0, 0.0, 0.0, 0.0, 14.0}, 0.01).delta_t > g.trim_t);
  // NaN state: trim surfaces
  const auto s = h.update({0.0, 0.0, 17.0}, {NAN, 0.0, 0.0, 0.0, 17.0}, 0.01);
  CHECK(s.delta_a == g.trim_a);
  CHECK(s.delta_e == g.trim_e);
  CHECK(s.delta_t == g.trim_t);
}

TEST_CASE("loops: throttle saturates without winding up") {
  AttitudeHold h;
  for (int i = 0; i < 3000; ++i) CHECK(h.update({0, 0, 40.0}, {0, 0, 0, 0, 10.0}, 0.01).delta_t <= 1.0);
  // 30 s at full throttle; once the aircraft is too fast, the throttle comes off at once
  CHECK(h.update({0, 0, 17.0}, {0, 0, 0, 0, 20.0}, 0.01).delta_t < h.gains().trim_t);
}

TEST_CASE("loops: closed loop on the uavbook's roll and airspeed transfer functions") {
  // Beard & McLain sec. 5.4: phi'' = -a_phi1 phi' + a_phi2 delta_a and
  // Va' = -a_V1 (Va - Va*) + a_V2 (delta_t - delta_t*), Anaconda coefficients at 17 m/s.
  const double a_phi1 = 25.65, a_phi2 = 137.9, a_V1 = 0.52, a_V2 = 15.35;
  AttitudeHold h;
  double phi = 0.5, p = 0.0, Va = 14.0;
  const double dt = 0.001;
  for (int i = 0; i < 20000; ++i) {  // 20 s
    const auto s = h.update({0.0, 0.0, 17.0}, {phi, 0.0, p, 0.0, Va}, dt);
    p += dt * (-a_phi1 * p + a_phi2 * s.delta_a);
    phi += dt * p;
    Va += dt * (-a_V1 * (Va - 17.0) + a_V2 * (s.delta_t - h.gains().trim_t - 0.05));  // trim off by 0.05
    if (i == 3000) CHECK(std::fabs(phi) < 0.01);  // wings level within 3 s
  }
  CHECK(std::fabs(phi) < 1e-3);
  CHECK(Va == doctest::Approx(17.0).epsilon(0.003));  // the integrator removes the trim error
}

TEST_CASE("plugin: holds trim until the state is valid, then corrects") {
  tern::testing::Harness h(std::make_unique<@CLASS@>(), {{"Va_c", 18.0}});
  tern::msg::State x;
  x.phi = 0.2;
  x.Va = 18.0;
  h.set_input("state", x);
  h.step(tern::from_seconds(0.01));
  const auto& a = h.output<tern::msg::Actuators>("actuators");
  CHECK(a.delta_a == doctest::Approx(0.0));
  CHECK(a.delta_t == doctest::Approx(0.568));
  x.valid = true;
  h.set_input("state", x);
  h.step(tern::from_seconds(0.02));
  CHECK(h.output<tern::msg::Actuators>("actuators").delta_a == doctest::Approx(-0.2));  // roll_kp 1
  CHECK(h.output<tern::msg::Actuators>("actuators").stamp == tern::from_seconds(0.02));
}

TEST_CASE("plugin: airspeed from controller_command, bumpless take-over, parameter ranges") {
  tern::testing::Harness h(std::make_unique<@CLASS@>());
  tern::msg::State x;
  x.valid = true;
  x.Va = 20.0;
  tern::msg::ControllerCommand c;
  c.Va_c = 20.0;
  h.set_input("state", x);
  h.set_input("controller_command", c);
  h.step(tern::from_seconds(0.01));
  tern::msg::Actuators last;
  last.delta_t = 0.8;
  h.plugin().take_over(last);
  h.step(tern::from_seconds(0.02));
  CHECK(h.output<tern::msg::Actuators>("actuators").delta_t == doctest::Approx(0.8).epsilon(1e-6));
  CHECK(h.output<tern::msg::ControllerInternals>("controller_internals").phi_c == 0.0);
  CHECK_THROWS_AS(h.set_param("roll_kp", -1.0), tern::ParamError);
  CHECK_THROWS_AS(tern::testing::Harness(std::make_unique<@CLASS@>(), {{"Va_c", 100.0}}), tern::ParamError);
}
