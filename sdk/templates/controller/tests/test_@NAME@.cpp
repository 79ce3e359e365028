// Tests of @NAME@: the loops alone (signs, limits, anti-windup, a closed loop on the uavbook's
// transfer functions) and the plugin through the SDK harness.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "plugin.hpp"
#include "slc.hpp"
#include "tern/reflect.hpp"
#include "tern/testing/harness.hpp"

using tern_@NAME@::Command;
using tern_@NAME@::Slc;
using tern_@NAME@::State;

namespace {
const State kLevel{0.0, 0.0, 0.0, 0.0, 0.0, 70.0, 17.0};  // phi theta chi p q h Va: on course, on altitude
const Command kHold{0.0, 70.0, 17.0, 0.0};                 // chi_c h_c Va_c phi_ff

/// What the flight log records of a message: the bytes of every field its describe() names.
template <class M>
std::vector<unsigned char> logged(const M& m) {
  std::vector<unsigned char> bytes;
  for (const tern::reflect::Column& c : tern::reflect::layout<M>()) {
    const auto* p = reinterpret_cast<const unsigned char*>(&m) + c.offset;
    bytes.insert(bytes.end(), p, p + tern::reflect::scalar_size(c.kind));
  }
  return bytes;
}
}  // namespace

TEST_CASE("loops: on the command, trim surfaces") {
  Slc s;
  const auto o = s.update(kHold, kLevel, 0.01);
  CHECK(o.delta_a == doctest::Approx(s.gains().trim_a));
  CHECK(o.delta_e == doctest::Approx(s.gains().trim_e));
  CHECK(o.delta_t == doctest::Approx(s.gains().trim_t));
}

TEST_CASE("loops: signs of the corrections") {
  Slc s;
  const auto& g = s.gains();
  Command c = kHold;
  c.chi_c = 0.1;  // course to the right: bank right, positive aileron
  auto o = s.update(c, kLevel, 0.01);
  CHECK(o.phi_c > 0.0);
  CHECK(o.delta_a > g.trim_a);
  c.chi_c = 3.0;  // from chi = -3.0 that is 0.28 rad to the left (wrapped), not 6 rad to the right
  State x = kLevel;
  x.chi = -3.0;
  o = s.update(c, x, 0.0);
  CHECK(o.phi_c < 0.0);
  CHECK(o.delta_a < g.trim_a);
  c = kHold;
  c.phi_ff = 0.3;  // orbit feed-forward: the roll command on course
  CHECK(Slc().update(c, kLevel, 0.0).phi_c == doctest::Approx(0.3));
  c = kHold;
  c.h_c = 80.0;  // too low: pitch up, elevator below trim (negative delta_e raises the nose)
  o = s.update(c, kLevel, 0.0);
  CHECK(o.theta_c > 0.0);
  CHECK(o.delta_e < g.trim_e);
  c = kHold;
  c.Va_c = 20.0;  // too slow: more throttle than trim
  CHECK(s.update(c, kLevel, 0.01).delta_t > g.trim_t);
}

TEST_CASE("loops: outputs within the limits, no wind-up, reset clears the integrators") {
  Slc s;
  const auto& g = s.gains();
  const Command far{3.0, 500.0, 40.0, 0.0};  // far right, far above, far too slow
  for (int i = 0; i < 3000; ++i) {           // 30 s
    const auto o = s.update(far, kLevel, 0.01);
    REQUIRE(std::fabs(o.phi_c) <= g.roll_max);
    REQUIRE(std::fabs(o.theta_c) <= g.theta_max);
    REQUIRE(std::fabs(o.delta_a) <= g.max_a);
    REQUIRE(std::fabs(o.delta_e) <= g.max_e);
    REQUIRE(o.delta_t >= 0.0);
    REQUIRE(o.delta_t <= 1.0);
  }
  // the integrators did not grow while saturated: once past the command, the outputs reverse at once
  State past = kLevel;
  past.chi = 0.2;
  past.h = 80.0;
  past.Va = 20.0;
  auto o = s.update(kHold, past, 0.01);
  CHECK(o.phi_c < 0.0);
  CHECK(o.theta_c < 0.0);
  CHECK(o.delta_t < g.trim_t);
  // integrate a steady error for 10 s, then reset: back to the proportional terms alone
  for (int i = 0; i < 1000; ++i) s.update({0.05, 71.0, 17.5, 0.0}, kLevel, 0.01);
  const auto wound = s.update({0.05, 71.0, 17.5, 0.0}, kLevel, 0.0);
  s.reset();
  o = s.update({0.05, 71.0, 17.5, 0.0}, kLevel, 0.0);
  CHECK(o.phi_c == doctest::Approx(g.course_kp * 0.05));
  CHECK(o.theta_c == doctest::Approx(g.altitude_kp * 1.0));
  CHECK(o.delta_t == doctest::Approx(g.trim_t + g.airspeed_kp * 0.5));
  CHECK(wound.phi_c > o.phi_c);
  CHECK(wound.delta_t > o.delta_t);
}

TEST_CASE("loops: non-finite input gives trim and leaves the integrators alone") {
  Slc s;
  for (int i = 0; i < 100; ++i) s.update({0.0, 70.0, 18.0, 0.0}, kLevel, 0.01);
  const double before = s.update({0.0, 70.0, 18.0, 0.0}, kLevel, 0.0).delta_t;
  State bad = kLevel;
  bad.Va = NAN;
  const auto o = s.update(kHold, bad, 0.01);
  CHECK(o.delta_a == s.gains().trim_a);
  CHECK(o.delta_e == s.gains().trim_e);
  CHECK(o.delta_t == s.gains().trim_t);
  CHECK(s.update({NAN, 70.0, 17.0, 0.0}, kLevel, 0.01).delta_t == s.gains().trim_t);
  CHECK(s.update({0.0, 70.0, 18.0, 0.0}, kLevel, 0.0).delta_t == doctest::Approx(before));
}

TEST_CASE("loops: closed loop on the uavbook's transfer functions (Anaconda, 17 m/s)") {
  // Beard & McLain sec. 5.4 with the coefficients of share/tern/configs/gains/anaconda.yaml:
  //   phi'' = -a_phi1 p + a_phi2 (delta_a - trim_a),  chi' = g/Va tan(phi)
  //   theta'' = -a_theta1 q - a_theta2 theta + a_theta3 (delta_e - trim_e),  h' = Va sin(theta)
  //   Va' = -a_V1 (Va - Va*) + a_V2 (delta_t - trim_t - 0.05)   (a throttle trim 0.05 off)
  const double a_phi1 = 25.65, a_phi2 = 137.9, a_th1 = 15.63, a_th2 = 162.2, a_th3 = -58.59;
  const double a_V1 = 0.52, a_V2 = 15.35;
  Slc s;
  const auto& g = s.gains();
  State x{0.0, 0.0, 0.0, 0.0, 0.0, 60.0, 15.0};
  const Command c{1.0, 70.0, 17.0, 0.0};  // 57 deg to the right, 10 m up, 2 m/s faster
  const double dt = 0.001;
  double max_phi = 0.0;
  for (int i = 0; i < 30000; ++i) {  // 30 s
    const auto o = s.update(c, x, dt);
    x.p += dt * (-a_phi1 * x.p + a_phi2 * (o.delta_a - g.trim_a));
    x.phi += dt * x.p;
    x.chi += dt * 9.81 / x.Va * std::tan(x.phi);
    x.q += dt * (-a_th1 * x.q - a_th2 * x.theta + a_th3 * (o.delta_e - g.trim_e));
    x.theta += dt * x.q;
    x.h += dt * x.Va * std::sin(x.theta);
    x.Va += dt * (-a_V1 * (x.Va - 17.0) + a_V2 * (o.delta_t - g.trim_t - 0.05));
    max_phi = std::max(max_phi, std::fabs(x.phi));
    if (i == 10000) CHECK(std::fabs(x.chi - 1.0) < 0.05);  // on course within 10 s
  }
  CHECK(max_phi <= g.roll_max + 0.05);  // the roll command limit holds the bank
  CHECK(x.chi == doctest::Approx(1.0).epsilon(0.005));
  CHECK(x.h == doctest::Approx(70.0).epsilon(0.005));
  CHECK(x.Va == doctest::Approx(17.0).epsilon(0.005));  // the integrator removed the trim error
}

TEST_CASE("plugin: trim until the state is valid and a command came, then follows it") {
  tern::testing::Harness h(std::make_unique<@CLASS@>(), {{"course_kp", 2.0}, {"course_ki", 0.0}});
  tern::msg::State x;
  x.p_d = -70.0;
  x.Va = 17.0;
  h.set_input("state", x);
  h.step(tern::from_seconds(0.01));
  const auto& a = h.output<tern::msg::Actuators>("actuators");
  CHECK(a.delta_a == doctest::Approx(0.0));
  CHECK(a.delta_e == doctest::Approx(0.168));
  CHECK(a.delta_t == doctest::Approx(0.568));
  tern::msg::ControllerCommand c;
  c.chi_c = 0.1;  // to the right
  c.h_c = 70.0;
  c.Va_c = 19.0;  // 2 m/s faster
  h.set_input("controller_command", c);
  x.valid = true;
  h.set_input("state", x);
  h.step(tern::from_seconds(0.02));
  CHECK(h.output<tern::msg::ControllerInternals>("controller_internals").phi_c == doctest::Approx(0.2));
  CHECK(h.output<tern::msg::Actuators>("actuators").delta_a > 0.0);
  CHECK(h.output<tern::msg::Actuators>("actuators").delta_t > 0.568);
  CHECK(h.output<tern::msg::Actuators>("actuators").delta_r == 0.0);
  CHECK(h.output<tern::msg::Actuators>("actuators").stamp == tern::from_seconds(0.02));
}

TEST_CASE("plugin: reset clears the integrators, take_over starts from the last throttle") {
  tern::testing::Harness h(std::make_unique<@CLASS@>());
  tern::msg::State x;
  x.valid = true;
  x.p_d = -70.0;
  x.Va = 16.0;
  tern::msg::ControllerCommand c;
  c.h_c = 70.0;
  c.Va_c = 17.0;  // 1 m/s too slow
  h.set_input("state", x);
  h.set_input("controller_command", c);
  for (int i = 1; i <= 200; ++i) h.step(tern::from_seconds(0.01 * i));  // 2 s
  const double wound = h.output<tern::msg::Actuators>("actuators").delta_t;
  h.reset();  // as between flights: the inputs are empty until the producers publish again
  h.set_input("state", x);
  h.set_input("controller_command", c);
  h.step(tern::from_seconds(2.01));
  const double fresh = h.output<tern::msg::Actuators>("actuators").delta_t;
  CHECK(fresh == doctest::Approx(0.568 + 0.161 * 1.0));  // trim + kp e: no integral
  CHECK(wound > fresh + 0.2);  // 2 s of 1 m/s error: + ki 0.147 * 2 s, up to full throttle
  tern::msg::Actuators last;
  last.delta_t = 0.9;
  h.plugin().take_over(last);
  h.step(tern::from_seconds(2.02));
  CHECK(h.output<tern::msg::Actuators>("actuators").delta_t == doctest::Approx(0.9).epsilon(1e-6));
}

TEST_CASE("plugin: after reset() a flight is the first one again, bit for bit") {
  // The contract of tern/plugin.hpp: what a flight changes lives in @CLASS@::Flight, which
  // reset() replaces. Two flights of the same inputs with a reset() between them must publish
  // the same messages; a field kept outside Flight (integrators, time of the last step) would
  // carry the first flight into the second and fail this.
  tern::testing::Harness h(std::make_unique<@CLASS@>());
  auto fly = [&h] {
    std::vector<std::vector<unsigned char>> published;
    for (int i = 1; i <= 300; ++i) {  // 3 s below, too slow and left of the commands: every integrator works
      tern::msg::State x;
      x.valid = true;
      x.p_d = -68.0;
      x.Va = 16.0;
      x.chi = 0.001 * i;
      tern::msg::ControllerCommand c;
      c.chi_c = 0.3;
      c.h_c = 70.0;
      c.Va_c = 17.0;
      h.set_input("state", x);
      h.set_input("controller_command", c);
      h.step(tern::from_seconds(0.01 * i));
      auto step = logged(h.output<tern::msg::Actuators>("actuators"));
      const auto internals = logged(h.output<tern::msg::ControllerInternals>("controller_internals"));
      step.insert(step.end(), internals.begin(), internals.end());
      published.push_back(std::move(step));
    }
    return published;
  };
  const auto first = fly();
  h.reset();
  const auto second = fly();
  REQUIRE(second.size() == first.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    CAPTURE(i);
    REQUIRE(second[i] == first[i]);
  }
}

TEST_CASE("plugin: parameter ranges") {
  tern::testing::Harness h(std::make_unique<@CLASS@>());
  CHECK_THROWS_AS(h.set_param("roll_kp", -1.0), tern::ParamError);
  CHECK_THROWS_AS(h.set_param("max_a", 0.8), tern::ParamError);  // beyond what the host accepts
  CHECK_THROWS_AS(tern::testing::Harness(std::make_unique<@CLASS@>(), {{"trim_t", 1.5}}), tern::ParamError);
}
