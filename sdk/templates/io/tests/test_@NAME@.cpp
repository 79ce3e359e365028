// Tests of @NAME@: the guidance model alone (steps to commands, turn limits) and the plugin
// through the SDK harness.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "guidance_model.hpp"
#include "plugin.hpp"
#include "tern/math.hpp"
#include "tern/reflect.hpp"
#include "tern/testing/harness.hpp"

using namespace tern_@NAME@;

namespace {
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

TEST_CASE("plugin: after reset() a flight is the first one again, bit for bit") {
  // The contract of tern/plugin.hpp: what a flight changes lives in @CLASS@::Flight, which
  // reset() replaces. Two flights of the same commands with a reset() between them must publish
  // the same truth; a field kept outside Flight (the model's state and last valid command, the
  // time of the last step) would carry the first flight into the second and fail this.
  tern::testing::Harness h(std::make_unique<@CLASS@>(), {{"init_heading", 0.5}});
  auto fly = [&h] {
    std::vector<std::vector<unsigned char>> published;
    for (int i = 0; i <= 500; ++i) {  // 5 s: no valid command for 0.5 s, then a climbing right turn, faster
      tern::msg::ControllerCommand c;
      c.chi_c = i < 50 ? NAN : 2.0;
      c.h_c = 120.0;
      c.Va_c = 20.0;
      h.set_input("controller_command", c);
      h.step(tern::from_seconds(0.01 * i));
      published.push_back(logged(h.output<tern::msg::State>("truth")));
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

TEST_CASE("plugin: the initial state is start-only; a change between flights flies from the next one") {
  tern::testing::Harness h(std::make_unique<@CLASS@>());
  h.step(0);
  CHECK(h.output<tern::msg::State>("truth").altitude() == doctest::Approx(100.0));
  h.set_param("init_altitude", 150.0);  // the host refuses this in flight, takes it between flights
  h.reset();
  h.step(0);
  CHECK(h.output<tern::msg::State>("truth").altitude() == doctest::Approx(150.0));
  CHECK_FALSE(h.plugin().find_param("init_altitude")->spec().live);
}
