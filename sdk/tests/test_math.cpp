#include <doctest/doctest.h>

#include "tern/math.hpp"
#include "tern/random.hpp"
#include "tern/time.hpp"

using namespace tern;

TEST_CASE("wrap_pi maps every angle to [-pi, pi)") {
  CHECK(wrap_pi(0.0) == doctest::Approx(0.0));
  CHECK(wrap_pi(3 * kPi) == doctest::Approx(-kPi));
  CHECK(wrap_pi(-3 * kPi / 2) == doctest::Approx(kPi / 2));
  CHECK(wrap_pi(7.0) == doctest::Approx(7.0 - 2 * kPi));
  CHECK(wrap_2pi(-0.5) == doctest::Approx(2 * kPi - 0.5));
  CHECK(wrap_2pi(-1e-17) < 2 * kPi);  // rounds to 2 pi in the sum: must come back as 0
  CHECK(unwrap_near(3.0, -3.0) == doctest::Approx(3.0 - 2 * kPi));
}

TEST_CASE("angle constants: rad per deg and deg per rad") {
  CHECK(90.0 * kRadPerDeg == doctest::Approx(kPi / 2));
  CHECK(kPi * kDegPerRad == doctest::Approx(180.0));
  CHECK(kRadPerDeg * kDegPerRad == doctest::Approx(1.0));
}

TEST_CASE("splitmix64: Vigna's reference outputs") {
  // splitmix64.c seeded with 0 returns splitmix64(0), then splitmix64(0x9e3779b97f4a7c15), ...
  CHECK(splitmix64(0) == 0xe220a8397b1dcdafULL);
  CHECK(splitmix64(0x9e3779b97f4a7c15ULL) == 0x6e789e6aa1b965f4ULL);
}

TEST_CASE("FNV-1a: the reference vectors from the true offset basis; tern's seeds from its own") {
  Fnv1a a{Fnv1a::kOffsetBasis};
  a.chars("a");
  CHECK(a.h == 0xaf63dc4c8601ec8cULL);  // draft-eastlake-fnv's test vector for "a"
  CHECK(Fnv1a{Fnv1a::kOffsetBasis}.h == 14695981039346656037ULL);
  // an instance's seed as every flight so far derived it (splitmix64(seed ^ FNV-1a field from
  // kTernBasis)): changing it would change every flight's noise
  CHECK(derive_seed(1, "sim") == 0x7c860fd76b57de94ULL);
  CHECK(derive_seed(1, "sim") != derive_seed(2, "sim"));
  CHECK(derive_seed(1, "sim") != derive_seed(1, "ekf"));
}

TEST_CASE("Euler, quaternion and rotation matrix agree and round-trip") {
  const double phi = 0.3, theta = -0.2, psi = 2.5;
  const Eigen::Quaterniond q = quaternion_from_euler(phi, theta, psi);
  const Eigen::Matrix3d R = rotation_from_euler(phi, theta, psi);
  CHECK((q.toRotationMatrix() - R).norm() < 1e-12);
  const Eigen::Vector3d e = euler_from_quaternion(q);
  CHECK(e.x() == doctest::Approx(phi));
  CHECK(e.y() == doctest::Approx(theta));
  CHECK(e.z() == doctest::Approx(psi));
  // A body x axis pitched up 0.2 rad points up (negative down) in NED.
  const Eigen::Vector3d nose = rotation_from_euler(0, 0.2, 0) * Eigen::Vector3d::UnitX();
  CHECK(nose.z() == doctest::Approx(-std::sin(0.2)));
}

TEST_CASE("time: integer nanoseconds and exact periods") {
  CHECK(period_from_hz(400) == 2'500'000);
  CHECK(period_from_hz(10) == 100'000'000);
  CHECK_THROWS_WITH_AS(period_from_hz(390), doctest::Contains("no whole-nanosecond period"), std::invalid_argument);
  CHECK_THROWS_AS(period_from_hz(0), std::invalid_argument);
  CHECK(from_seconds(1.5) == 1'500'000'000);
  CHECK(to_seconds(2'500'000) == doctest::Approx(0.0025));
}
