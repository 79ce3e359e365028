// Tests of @NAME@: the guidance model alone (steps to commands, turn limits) and the plugin
// through the SDK harness.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <memory>

#include "guidance_model.hpp"
#include "plugin.hpp"
#include "tern/math.hpp"
#include "tern/testing/harness.hpp"

using namespace tern_@NAME@;

TEST_CASE("model: straight and level flight covers Va * t") {
  GuidanceModel m;
  m.set_state({0, 0, 100, 0.0, 0, 0, 20.0});
  for (int i = 0; i < 100; ++i) m.step({0.0, 100.0, 20.0, 0.0}, 0.1);
  CHECK(m.state().p_n == doctest::Approx(200.0));
  CHECK(m.state().p_e == doctest::Approx(0.0));
  CHECK(m.state().h == doctest::Approx(100.0));
}

TEST_CASE("model: reaches course, altitude and airspeed commands; turns within phi_max") {
  GuidanceModel m;
  m.set_state({0, 0, 100, 0.0, 0, 0, 17.0});
  double max_phi = 0.0, max_climb = 0.0;
  for (int i = 0; i < 600; ++i) {  // 60 s
    m.step({3.0, 150.0, 20.0, 0.0}, 0.1);  // a right turn of 3 rad (the short way)
    max_phi = std::max(max_phi, std::fabs(m.phi()));
    max_climb = std::max(max_climb, m.state().h_dot);
  }
  CHECK(m.state().chi == doctest::Approx(3.0).epsilon(1e-3));
  CHECK(m.state().h == doctest::Approx(150.0).epsilon(1e-3));
  CHECK(m.state().Va == doctest::Approx(20.0).epsilon(1e-3));
  CHECK(max_phi <= 0.7 + 1e-9);
  CHECK(max_climb <= 5.0 + 1e-9);
  // course across +-pi goes the short way: from 3 to -3 is 0.28 rad to the right
  m.step({-3.0, 150.0, 20.0, 0.0}, 0.1);
  CHECK(m.state().chi_dot > 0.0);
}

TEST_CASE("model: a steady turn with the orbit feed-forward") {
  GuidanceModel m;
  m.set_state({0, 0, 100, 0.0, 0, 0, 17.0});
  // the course command of an orbit follower on the circle: chi_c = chi_0 + (g tan(phi_ff) / Va) t
  const double phi_ff = 0.3, chidot = 9.81 * std::tan(phi_ff) / 17.0;
  for (int i = 1; i <= 3000; ++i) m.step({tern::wrap_pi(chidot * 0.01 * i), 100.0, 17.0, phi_ff}, 0.01);
  CHECK(m.phi() == doctest::Approx(phi_ff).epsilon(0.01));
  CHECK(m.state().chi_dot == doctest::Approx(chidot).epsilon(0.01));
}

TEST_CASE("plugin: publishes a valid truth from the initial state and follows commands") {
  tern::testing::Harness h(std::make_unique<@CLASS@>(),
                           {{"init_altitude", 80.0}, {"init_heading", 1.5707963}, {"init_airspeed", 15.0}});
  h.step(0);
  const auto& s = h.output<tern::msg::State>("truth");
  CHECK(s.valid);
  CHECK(s.origin_valid);
  CHECK(s.p_d == doctest::Approx(-80.0));
  CHECK(s.chi == doctest::Approx(1.5707963));
  CHECK(s.v_e == doctest::Approx(15.0));
  for (int i = 1; i <= 100; ++i) h.step(tern::from_seconds(0.01 * i));  // 1 s east, no command
  CHECK(h.output<tern::msg::State>("truth").p_e == doctest::Approx(15.0).epsilon(1e-6));
  tern::msg::ControllerCommand c;
  c.chi_c = 1.5707963;
  c.h_c = 100.0;
  c.Va_c = 15.0;
  h.set_input("controller_command", c);
  for (int i = 101; i <= 3000; ++i) h.step(tern::from_seconds(0.01 * i));
  CHECK(h.output<tern::msg::State>("truth").altitude() == doctest::Approx(100.0).epsilon(1e-3));
  CHECK_THROWS_AS(h.set_param("phi_max", 2.0), tern::ParamError);
}
