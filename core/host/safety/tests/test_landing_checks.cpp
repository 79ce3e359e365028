// The landing's checks alone (core/host/safety/landing_checks.hpp): the height above the runway
// from a range finder or the estimate, and the stabilised-approach criteria.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "safety/landing_checks.hpp"

using namespace tern;
using namespace tern::core;

namespace {
msg::CurrentPath glide_path() {
  msg::CurrentPath p;
  p.landing = true;
  p.r = Eigen::Vector3d(0.0, 0.0, -2.0);  // the touchdown point, 2 m above the estimate's origin
  p.q = Eigen::Vector3d(1.0, 0.0, 0.0875).normalized();
  return p;
}
}  // namespace

TEST_CASE("landing checks: the height above the runway is the range finder's while it is fresh, else the estimate's") {
  msg::State s;
  s.p_d = -7.0;  // the estimate: 5 m above the touchdown point
  s.phi = 0.1;
  s.theta = 0.05;
  const msg::CurrentPath p = glide_path();
  CHECK(runway_height(s, p, nullptr, 0) == doctest::Approx(5.0));
  msg::Range r;
  r.stamp = from_seconds(10.0);
  r.distance = 3.0;  // metres off the estimate: the range finder wins
  CHECK(runway_height(s, p, &r, from_seconds(10.05)) == doctest::Approx(3.0 * std::cos(0.1) * std::cos(0.05)));
  CHECK(runway_height(s, p, &r, from_seconds(10.2)) == doctest::Approx(5.0));  // stale
  r.distance = std::numeric_limits<double>::infinity();                        // no return (beyond 40 m)
  CHECK(runway_height(s, p, &r, from_seconds(10.05)) == doctest::Approx(5.0));
  r.distance = std::nan("");  // a failing sensor
  CHECK(runway_height(s, p, &r, from_seconds(10.05)) == doctest::Approx(5.0));
}

TEST_CASE("landing checks: along the runway from the touchdown point") {
  const msg::CurrentPath p = glide_path();  // runway heading north
  msg::State s;
  s.p_n = -30.0;
  s.p_e = 4.0;
  CHECK(along_touchdown(s, p) == doctest::Approx(-30.0));
  s.p_n = 12.0;
  CHECK(along_touchdown(s, p) == doctest::Approx(12.0));
}

TEST_CASE("landing checks: not stabilised names the criterion and its value; on the glide path it is stabilised") {
  const msg::CurrentPath p = glide_path();
  const LandingLimits l;
  msg::State s;
  s.p_n = -100.0;                 // 100 m short of the touchdown point
  s.p_d = -(2.0 + 100 * 0.0875);  // on the glide path
  s.Va = 15.0;
  CHECK(unstabilised(s, p, 15.0, l).empty());
  s.p_e = 7.0;
  CHECK(unstabilised(s, p, 15.0, l) == "cross-track 7.0 m > 5.0 m");
  s.p_e = 0.0;
  s.p_d -= 6.0;
  CHECK(unstabilised(s, p, 15.0, l) == "6.0 m above the glide path > 5.0 m");
  s.p_d += 6.0;
  s.Va = 11.0;
  CHECK(unstabilised(s, p, 15.0, l) == "airspeed 11.0 m/s < 12.0 m/s (Va_c 15.0 - 3.0)");
}
