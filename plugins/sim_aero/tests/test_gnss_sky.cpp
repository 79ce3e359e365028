// The GNSS antenna's sky view (gnss_sky.hpp): satellites lost when the antenna faces away, the
// solution's dilution and jumps, no fix below four, reacquisition, the platform model's lag.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "tern/math.hpp"
#include "tern_sim_aero/gnss_sky.hpp"

using namespace tern::sim;

namespace {
const Eigen::Vector3d kUp(0.0, 0.0, -1.0), kDown(0.0, 0.0, 1.0), kEast(0.0, 1.0, 0.0);

GnssSkyParams twelve() {
  GnssSkyParams p;
  p.satellites = 12;
  p.elevation_mask = 10.0 * tern::kRadPerDeg;
  p.antenna_cutoff = 0.0;
  p.reacquisition = 1.0;
  p.horizontal_sigma = 1.2;
  p.velocity_sigma = 0.05;
  p.range_tau = 180.0;
  return p;
}
}  // namespace

TEST_CASE("gnss sky: dilutions of precision of a known geometry; fewer than four satellites give none") {
  // the zenith and three on the horizon 120 deg apart: H^T H is diagonal with 1.5, 1.5, 1, 4 and
  // the clock couples with the vertical; G's position block gives HDOP sqrt(4/3), VDOP sqrt(4/3)
  const double c = std::cos(120.0 * tern::kRadPerDeg), s = std::sin(120.0 * tern::kRadPerDeg);
  std::vector<Eigen::Vector3d> los{{0, 0, -1}, {1, 0, 0}, {c, s, 0}, {c, -s, 0}};
  const Dops d = dilutions_of_precision(los);
  CHECK(d.h == doctest::Approx(std::sqrt(4.0 / 3.0)));
  CHECK(d.v == doctest::Approx(std::sqrt(4.0 / 3.0)));
  CHECK(d.p == doctest::Approx(std::sqrt(d.h * d.h + d.v * d.v)));
  los.pop_back();
  CHECK(std::isinf(dilutions_of_precision(los).h));
}

TEST_CASE("gnss sky: facing up the antenna sees the whole sky and adds nothing") {
  GnssSky sky(twelve(), 7);
  for (int k = 1; k <= 50; ++k) {
    const GnssSkyFix f = sky.step(0.1 * k, 0.1, kUp, Eigen::Vector3d(20, 0, 0));
    REQUIRE(f.fix);
    CHECK(f.tracked == 12);
    CHECK(f.hdop_ratio == 1.0);
    CHECK(f.pdop_ratio == 1.0);
    CHECK(f.position_error == Eigen::Vector3d::Zero());
    CHECK(f.velocity_error == Eigen::Vector3d::Zero());
    CHECK(f.hdop > 0.5);
    CHECK(f.hdop < 2.0);
  }
}

TEST_CASE("gnss sky: inverted the antenna loses every satellite; back up, they return after the reacquisition time") {
  GnssSky sky(twelve(), 3);
  int k = 0;
  const auto fix_at = [&](const Eigen::Vector3d& boresight) { return sky.step(0.1 * ++k, 0.1, boresight, Eigen::Vector3d::Zero()); };
  CHECK(fix_at(kUp).fix);
  const GnssSkyFix inverted = fix_at(kDown);
  CHECK(inverted.tracked == 0);
  CHECK_FALSE(inverted.fix);
  CHECK(fix_at(kUp).tracked == 0);  // in view again (t = 0.3 s), not yet tracked
  for (int n = 0; n < 9; ++n) CHECK_FALSE(fix_at(kUp).fix);
  const GnssSkyFix back = fix_at(kUp);  // t = 1.3 s: 1.0 s in view
  CHECK(back.fix);
  CHECK(back.tracked == 12);
  CHECK(back.position_error == Eigen::Vector3d::Zero());
}

TEST_CASE("gnss sky: on a knife edge half the sky is lost: the accuracy worsens and the solution jumps") {
  // over seeds: the tracked satellites are those on the east side, the DOPs grow, the errors move
  int degraded = 0;
  double jump = 0.0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    GnssSky sky(twelve(), seed);
    sky.step(0.1, 0.1, kUp, Eigen::Vector3d::Zero());
    const GnssSkyFix f = sky.step(0.2, 0.1, kEast, Eigen::Vector3d::Zero());
    int east = 0;
    for (const auto& los : sky.lines_of_sight()) east += los.y() >= 0.0 ? 1 : 0;
    CHECK(f.tracked == east);
    if (!f.fix) continue;
    ++degraded;
    CHECK(f.hdop_ratio > 1.0);
    CHECK(f.pdop_ratio > 1.0);
    CHECK(f.position_error.norm() > 0.0);
    jump = std::max(jump, f.position_error.norm());
  }
  CHECK(degraded >= 10);
  CHECK(jump > 1.0);  // metres: the range errors are sized to the whole sky's 1.2 m per axis
  CHECK(jump < 60.0);
}

TEST_CASE("gnss sky: beyond the platform model's bound the velocity lags, then catches up") {
  GnssSkyParams p;  // no sky: only the receiver's filter
  p.max_acceleration = 2.0 * tern::kStandardGravity;
  p.lag_tau = 0.5;
  GnssSky sky(p, 1);
  CHECK(sky.step(0.1, 0.1, kUp, Eigen::Vector3d(20, 0, 0)).velocity_error.isZero());
  // 2 g: followed
  Eigen::Vector3d v(20, 0, 0);
  CHECK(sky.step(0.2, 0.1, kUp, v += Eigen::Vector3d(0, 0, -1.9 * tern::kStandardGravity * 0.1)).velocity_error.isZero());
  // 4 g for 0.5 s: the 2 g beyond the bound lag, each fix's share decaying with 0.5 s
  GnssSkyFix f;
  double expected = 0.0;
  for (int k = 0; k < 5; ++k) {
    f = sky.step(0.3 + 0.1 * k, 0.1, kUp, v += Eigen::Vector3d(0, 0, -4.0 * tern::kStandardGravity * 0.1));
    expected = std::exp(-0.2) * expected + 2.0 * tern::kStandardGravity * 0.1;
  }
  CHECK(f.velocity_error.z() == doctest::Approx(expected));  // the output's climb rate lags (NED: +)
  CHECK(f.velocity_lag == doctest::Approx(expected));
  for (int k = 0; k < 30; ++k) f = sky.step(0.8 + 0.1 * k, 0.1, kUp, v);
  CHECK(f.velocity_lag < 0.01 * expected);
  p.lag_tau = 0.0;
  CHECK_THROWS_AS(GnssSky(p, 1), std::invalid_argument);
}

TEST_CASE("gnss sky: the same seed draws the same sky; parameters outside their ranges throw") {
  GnssSky a(twelve(), 5), b(twelve(), 5), c(twelve(), 6);
  CHECK(a.lines_of_sight() == b.lines_of_sight());
  CHECK(a.lines_of_sight() != c.lines_of_sight());
  for (const auto& los : a.lines_of_sight()) CHECK(-los.z() >= std::sin(10.0 * tern::kRadPerDeg) - 1e-12);
  GnssSkyParams bad = twelve();
  bad.satellites = 65;
  CHECK_THROWS_AS(GnssSky(bad, 1), std::invalid_argument);
  bad = twelve();
  bad.reacquisition = -1.0;
  CHECK_THROWS_AS(GnssSky(bad, 1), std::invalid_argument);
}
