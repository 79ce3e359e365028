#include <doctest/doctest.h>

#include <cmath>

#include "tern/geodesy.hpp"
#include "tern/math.hpp"

using namespace tern;

namespace {
const GeoPoint kHome{40.2463724, -111.6474138, 1387.0};                            // BYU's field, the shipped missions' origin
constexpr double kA = 6378137.0, kF = 1.0 / 298.257223563, kE2 = kF * (2.0 - kF);  // WGS-84
}  // namespace

TEST_CASE("geodesy: the origin is NED zero and a point round-trips") {
  const GeoOrigin o(kHome);
  CHECK(o.to_ned(kHome).norm() < 1e-9);
  const Eigen::Vector3d p(1234.5, -678.9, -150.25);
  const GeoPoint g = o.to_geodetic(p);
  CHECK((o.to_ned(g) - p).norm() < 1e-8);
  const GeoOrigin copy = o;  // copies convert alike
  CHECK(copy.to_ned(g) == o.to_ned(g));
  CHECK(copy.origin() == kHome);
}

TEST_CASE("geodesy: NED axes follow the WGS-84 radii of curvature at the origin") {
  const GeoOrigin o(kHome);
  const double s = std::sin(kHome.lat * kRadPerDeg), w = std::sqrt(1.0 - kE2 * s * s);
  const double M = kA * (1.0 - kE2) / (w * w * w), N = kA / w;  // meridian, prime vertical
  const double d = 1e-3;                                        // deg: about 111 m
  const Eigen::Vector3d north = o.to_ned(kHome.lat + d, kHome.lon, kHome.alt);
  CHECK(north.x() == doctest::Approx((M + kHome.alt) * d * kRadPerDeg).epsilon(1e-5));
  CHECK(std::fabs(north.y()) < 1e-6);
  const Eigen::Vector3d east = o.to_ned(kHome.lat, kHome.lon + d, kHome.alt);
  CHECK(east.y() == doctest::Approx((N + kHome.alt) * std::cos(kHome.lat * kRadPerDeg) * d * kRadPerDeg).epsilon(1e-5));
  CHECK(east.z() > 0.0);  // the surface curves away below the tangent plane
  CHECK(o.to_ned(kHome.lat, kHome.lon, kHome.alt + 10.0).z() == doctest::Approx(-10.0).epsilon(1e-9));
}

TEST_CASE("geodesy: a latitude beyond the pole gives NaN, not an exception") {
  const GeoOrigin o(kHome);
  CHECK(std::isnan(o.to_ned(91.0, 0.0, 0.0).x()));
  CHECK(std::isnan(GeoOrigin(GeoPoint{std::nan(""), 0.0, 0.0}).to_ned(kHome).x()));
}
