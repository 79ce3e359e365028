// The stick shaping (sticks.hpp) on values worked by hand.
#include <doctest/doctest.h>

#include "tern/joystick/sticks.hpp"

using namespace tern::joystick;

TEST_CASE("deadband: centre travel reads 0, the rest is stretched back to full") {
  CHECK(shape(0.04, 0.05, 0.0) == 0.0);
  CHECK(shape(-0.05, 0.05, 0.0) == 0.0);
  CHECK(shape(0.525, 0.05, 0.0) == doctest::Approx(0.5));  // (0.525 - 0.05) / 0.95
  CHECK(shape(-1.0, 0.05, 0.0) == doctest::Approx(-1.0));
  CHECK(shape(1.7, 0.05, 0.0) == doctest::Approx(1.0));  // clamped
}

TEST_CASE("expo: (1 - e) x + e x^3: softer near centre, full at full") {
  CHECK(shape(0.5, 0.0, 0.3) == doctest::Approx(0.7 * 0.5 + 0.3 * 0.125));
  CHECK(shape(-0.5, 0.0, 1.0) == doctest::Approx(-0.125));
  CHECK(shape(1.0, 0.0, 0.6) == doctest::Approx(1.0));
  CHECK(shape(0.5, 0.0, 0.0) == doctest::Approx(0.5));
}

TEST_CASE("mapping and reversal: mode 2 on a game controller") {
  StickShaping s;
  s.map = {StickMap{2, false}, StickMap{3, false}, StickMap{0, false}, StickMap{1, true}};
  s.deadband = 0.0;
  s.expo = 0.0;
  //                         left x  left y  right x  right y  triggers
  const std::array<double, 6> axes{0.25, -1.0, -0.5, 0.75, 0.0, 0.0};
  const Sticks st = sticks_from_axes(axes, s);
  CHECK(st.roll == doctest::Approx(-0.5));
  CHECK(st.pitch == doctest::Approx(0.75));
  CHECK(st.yaw == doctest::Approx(0.25));
  CHECK(st.throttle == doctest::Approx(1.0));  // left stick full up (SDL -1), reversed
  s.map[3].reverse = false;
  CHECK(sticks_from_axes(axes, s).throttle == doctest::Approx(0.0));
  s.map[0].axis = 7;  // no such axis: centred
  CHECK(sticks_from_axes(axes, s).roll == 0.0);
}
