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

TEST_CASE("formation: without wind the airspeed command is proportional and saturated") {
  FormationConfig c;
  const OrbitPlace l{0.3, Vec2::Zero()}, f{-0.4, Vec2::Zero()};
  CHECK(follower_airspeed(0.0, l, f, c) == doctest::Approx(c.Va_nominal).epsilon(1e-12));
  CHECK(follower_airspeed(20.0, l, f, c) == doctest::Approx(c.Va_nominal + c.gain * 20.0));
  CHECK(follower_airspeed(1000.0, l, f, c) == c.Va_max);
  CHECK(follower_airspeed(-1000.0, l, f, c) == c.Va_min);
}

TEST_CASE("formation: in wind the follower is given the leader's ground speed where it is") {
  FormationConfig c;  // clockwise: at theta = 0 (north of the centre) the tangent points east
  CHECK(orbit_tangent(0.0, c).isApprox(Vec2(0.0, 1.0)));
  c.direction = -1;
  CHECK(orbit_tangent(0.0, c).isApprox(Vec2(0.0, -1.0)));
  c.direction = 1;
  const Vec2 w(0.0, 5.0);  // 5 m/s towards the east
  // leader at theta = 0 flies downwind (Vg 22), follower at theta = pi flies upwind: Va 27 -> Va_max
  CHECK(follower_airspeed(0.0, {0.0, w}, {tern::kPi, w}, c) == c.Va_max);
  // follower at pi / 2 (east of the centre, flying south): crosswind, |(-22, 0) - (0, 5)|
  c.Va_max = 30.0;
  CHECK(follower_airspeed(0.0, {0.0, w}, {tern::kPi / 2, w}, c) == doctest::Approx(std::hypot(22.0, 5.0)).epsilon(1e-9));
}

TEST_CASE("formation: on a kinematic orbit in wind two followers converge to their places") {
  for (double wind : {0.0, 5.0}) {
    FormationConfig c;  // a speed range wide enough for the wind's +-5 m/s (no saturation)
    c.radius = 200.0;
    c.Va_min = 8.0;
    c.Va_max = 30.0;
    const Vec2 w(wind, 0.0);
    double th_l = 0.0, th1 = 2.5, th2 = -1.0;  // followers far from their places
    const double dt = 0.1;
    auto vg = [&](double Va, double th) { return ground_speed(Va, w, orbit_tangent(th, c)); };
    double worst = 0.0;
    for (int i = 0; i < 6000; ++i) {  // 600 s
      const double v1 = follower_airspeed(spacing_error(th_l, th1, 1, c), {th_l, w}, {th1, w}, c);
      const double v2 = follower_airspeed(spacing_error(th_l, th2, 2, c), {th_l, w}, {th2, w}, c);
      const double g0 = vg(c.Va_nominal, th_l), g1 = vg(v1, th1), g2 = vg(v2, th2);
      th_l += c.direction * g0 / c.radius * dt;
      th1 += c.direction * g1 / c.radius * dt;
      th2 += c.direction * g2 / c.radius * dt;
      if (i > 3000) worst = std::max({worst, std::fabs(spacing_error(th_l, th1, 1, c)), std::fabs(spacing_error(th_l, th2, 2, c))});
    }
    CAPTURE(wind);
    CHECK(worst < 0.5);
  }
}
