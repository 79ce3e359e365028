// Turn-then-line path lengths and the wind triangle (path_estimate.hpp).
#include <doctest/doctest.h>

#include <cmath>

#include "tern/coordination/path_estimate.hpp"
#include "tern/math.hpp"

using tern::kPi;
using tern::coord::Vec2;

TEST_CASE("path length: straight ahead is the distance") {
  CHECK(tern::coord::turn_then_line_length({0, 0}, 0.0, {1000, 0}, 50.0) == doctest::Approx(1000.0));
  CHECK(tern::coord::turn_then_line_length({10, 20}, 0.3, {10, 20}, 50.0) == 0.0);
}

TEST_CASE("path length: a target behind costs a half turn") {
  // right turn about (0, 50): the half turn ends at (0, 100), 100 m abeam the target, so the
  // turn goes on by 2 atan(50 / 1000) more; the tangent from the circle is sqrt(D^2 - R^2) = 1000
  CHECK(tern::coord::turn_then_line_length({0, 0}, 0.0, {-1000, 0}, 50.0) ==
        doctest::Approx(50.0 * (kPi + 2.0 * std::atan(0.05)) + 1000.0));
}

TEST_CASE("path length: a target on the turn circle is reached by the arc alone") {
  // (0, 100) lies on the right turn circle about (0, 50): a half circle, shorter than the left turn
  CHECK(tern::coord::turn_then_line_length({0, 0}, 0.0, {0, 100}, 50.0) == doctest::Approx(50.0 * kPi));
}

TEST_CASE("path length: a target inside one turn circle takes the other turn") {
  // (0, 50) is the right circle's centre: left turn about (0, -50), D = 100, tangent sqrt(7500),
  // exit course pi/3, arc 2 pi - pi/3
  const double L = tern::coord::turn_then_line_length({0, 0}, 0.0, {0, 50}, 50.0);
  CHECK(L == doctest::Approx(50.0 * (2.0 * kPi - kPi / 3.0) + std::sqrt(7500.0)));
}

TEST_CASE("path length: never shorter than the distance, never longer than a full turn more") {
  for (int i = 0; i < 72; ++i) {
    const double chi = i * 5.0 * tern::kRadPerDeg;
    for (double r : {30.0, 120.0, 900.0}) {
      const Vec2 target(r * std::cos(0.7 * i), r * std::sin(0.7 * i));
      const double L = tern::coord::turn_then_line_length({0, 0}, chi, target, 50.0);
      CHECK(L >= target.norm() - 1e-9);
      CHECK(L <= target.norm() + 2.0 * kPi * 50.0 + 100.0);
    }
  }
}

TEST_CASE("wind triangle: tail, head and cross wind, and back") {
  const Vec2 north(1, 0);
  CHECK(tern::coord::ground_speed(17.0, {0, 0}, north) == doctest::Approx(17.0));
  CHECK(tern::coord::ground_speed(17.0, {5, 0}, north) == doctest::Approx(22.0));
  CHECK(tern::coord::ground_speed(17.0, {-5, 0}, north) == doctest::Approx(12.0));
  CHECK(tern::coord::ground_speed(17.0, {0, 5}, north) == doctest::Approx(std::sqrt(17.0 * 17.0 - 25.0)));
  CHECK(tern::coord::ground_speed(13.0, {-20, 0}, north) == 1.0);  // cannot make way: the floor
  for (int i = 0; i < 12; ++i) {
    const Vec2 q(std::cos(0.5 * i), std::sin(0.5 * i));
    const Vec2 w(3.5, -3.5);
    CHECK(tern::coord::airspeed_for(tern::coord::ground_speed(16.0, w, q), w, q) == doctest::Approx(16.0));
  }
}
