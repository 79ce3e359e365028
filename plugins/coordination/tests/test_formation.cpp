// The orbit spacing law (formation.hpp), alone and closed on a kinematic orbit.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "tern/coordination/formation.hpp"
#include "tern/math.hpp"

using namespace tern::coord;

TEST_CASE("formation config: orbit, direction and room for the followers") {
  FormationConfig c;
  CHECK_NOTHROW(c.validate(2));
  CHECK_THROWS_AS(c.validate(10), std::invalid_argument);  // 10 x 100 m > 2 pi 150 m
  c.direction = 0;
  CHECK_THROWS_AS(c.validate(2), std::invalid_argument);
  c = FormationConfig{};
  c.Va_nominal = 30.0;
  CHECK_THROWS_AS(c.validate(2), std::invalid_argument);
}

TEST_CASE("formation: orbit angle and arc error, both directions") {
  FormationConfig c;  // radius 150, spacing 100
  CHECK(orbit_angle({100, 200}, {100, 50}) == doctest::Approx(tern::kPi / 2));
  const double want = c.spacing / c.radius;  // follower 1's place behind the leader, rad
  CHECK(spacing_error(0.3, 0.3 - want, 1, c) == doctest::Approx(0.0).epsilon(1e-12));
  CHECK(spacing_error(0.3, 0.3 - want - 0.2, 1, c) == doctest::Approx(30.0));  // too far behind: > 0
  CHECK(spacing_error(0.3, 0.3 - 2 * want + 0.1, 2, c) == doctest::Approx(-15.0));
  c.direction = -1;  // counter-clockwise: behind means a larger angle
  CHECK(spacing_error(0.3, 0.3 + want + 0.2, 1, c) == doctest::Approx(30.0));
  // half an orbit off: the error stays within pi rho
  CHECK(std::fabs(spacing_error(0.0, tern::kPi, 1, c)) <= tern::kPi * c.radius);
}

TEST_CASE("formation: the airspeed command is proportional and saturated") {
  FormationConfig c;
  CHECK(follower_airspeed(0.0, c) == c.Va_nominal);
  CHECK(follower_airspeed(20.0, c) == doctest::Approx(c.Va_nominal + c.gain * 20.0));
  CHECK(follower_airspeed(1000.0, c) == c.Va_max);
  CHECK(follower_airspeed(-1000.0, c) == c.Va_min);
}

TEST_CASE("formation: on a kinematic orbit two followers converge to their places") {
  FormationConfig c;
  double th_l = 0.0, th1 = 2.5, th2 = -1.0;  // followers far from their places
  const double dt = 0.1;
  for (int i = 0; i < 3000; ++i) {  // 300 s
    const double v1 = follower_airspeed(spacing_error(th_l, th1, 1, c), c);
    const double v2 = follower_airspeed(spacing_error(th_l, th2, 2, c), c);
    th_l += c.direction * c.Va_nominal / c.radius * dt;
    th1 += c.direction * v1 / c.radius * dt;
    th2 += c.direction * v2 / c.radius * dt;
  }
  CHECK(std::fabs(spacing_error(th_l, th1, 1, c)) < 0.5);
  CHECK(std::fabs(spacing_error(th_l, th2, 2, c)) < 0.5);
}
