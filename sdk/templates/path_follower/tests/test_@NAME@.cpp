// Tests of @NAME@: the vector fields alone (converging to a line, orbit tangent, altitude) and
// the plugin through the SDK harness.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <memory>

#include "plugin.hpp"
#include "tern/testing/harness.hpp"
#include "vector_field.hpp"

using namespace tern_@NAME@;

TEST_CASE("line: a kinematic aircraft converges onto the line and holds it") {
  // Line north through the origin at 100 m altitude; start 200 m east of it, flying east.
  const Eigen::Vector3d r(0, 0, -100), q(1, 0, 0);
  Eigen::Vector3d p(0, 200, -100);
  double chi = 1.5708;
  const double Va = 17.0, dt = 0.01, tau_chi = 1.0;  // course follows chi_c with a 1 s lag
  const FollowerGains g;
  for (int i = 0; i < 12000; ++i) {  // 120 s
    const Guidance u = follow_line(r, q, p, chi, g);
    chi += dt * (u.chi_c - chi) / tau_chi;
    p += dt * Va * Eigen::Vector3d(std::cos(chi), std::sin(chi), 0.0);
  }
  CHECK(std::fabs(cross_track_error(r, q, p)) < 0.5);
  CHECK(std::fabs(chi) < 0.01);  // flying north, along the line
}

TEST_CASE("line: course and altitude commands") {
  const FollowerGains g;
  // On the line: the line's course. Far to its right (east of a north line): chi_inf towards it.
  CHECK(follow_line({0, 0, -50}, {1, 0, 0}, {10, 0, -50}, 0.0, g).chi_c == doctest::Approx(0.0));
  CHECK(follow_line({0, 0, -50}, {1, 0, 0}, {0, 1e6, -50}, 0.0, g).chi_c == doctest::Approx(-g.chi_inf).epsilon(1e-4));
  // Course is unwrapped near the current course: a line to the south seen from chi = 3 rad.
  CHECK(follow_line({0, 0, -50}, {-1, 0, 0}, {0, 0, -50}, 3.0, g).chi_c == doctest::Approx(3.14159265).epsilon(1e-6));
  // A climbing line (1 m up per 10 m north): 100 m along it, 10 m higher (eq. 10.5).
  CHECK(follow_line({0, 0, -50}, {10, 0, -1}, {100, 30, -50}, 0.0, g).h_c == doctest::Approx(60.0));
  CHECK(std::isnan(follow_line({0, 0, 0}, {0, 0, -1}, {0, 0, 0}, 0.0, g).chi_c));  // vertical line
}

TEST_CASE("orbit: tangent on the circle, towards it from outside, feed-forward") {
  const FollowerGains g;
  // Clockwise orbit of radius 100 around the origin, aircraft north of the centre: fly east.
  const Guidance on = follow_orbit({0, 0, -80}, 100.0, 1, {100, 0, -80}, 1.0, 17.0, g);
  CHECK(on.chi_c == doctest::Approx(3.14159265 / 2));
  CHECK(on.h_c == doctest::Approx(80.0));
  CHECK(on.phi_ff == doctest::Approx(std::atan(17.0 * 17.0 / (9.81 * 100.0))));
  // Far outside: heads almost at the centre (course near south from the north).
  const Guidance out = follow_orbit({0, 0, -80}, 100.0, 1, {5000, 0, -80}, 3.0, 17.0, g);
  CHECK(std::fabs(out.chi_c - 3.14159265) < 0.05);
  CHECK(out.phi_ff == 0.0);
}

TEST_CASE("plugin: commands from the path, nothing while the state is invalid") {
  tern::testing::Harness h(std::make_unique<@CLASS@>(), {{"k_path", 0.05}});
  tern::msg::CurrentPath path;
  path.path_type = tern::msg::CurrentPath::line;
  path.Va_d = 18.0;
  path.r = {0, 0, -100};
  path.q = {0, 1, 0};  // east
  tern::msg::State x;
  x.p_d = -90.0;
  x.chi = 1.5;
  h.set_input("state", x);
  h.set_input("current_path", path);
  h.step(tern::from_seconds(0.01));
  CHECK(h.published("controller_command") == 0);
  x.valid = true;
  h.set_input("state", x);
  h.step(tern::from_seconds(0.02));
  REQUIRE(h.published("controller_command") == 1);
  const auto& c = h.output<tern::msg::ControllerCommand>("controller_command");
  CHECK(c.Va_c == 18.0);
  CHECK(c.h_c == doctest::Approx(100.0));
  CHECK(c.chi_c == doctest::Approx(3.14159265 / 2));
  CHECK(c.stamp == tern::from_seconds(0.02));
  CHECK_THROWS_AS(h.set_param("chi_inf", 2.0), tern::ParamError);
}
