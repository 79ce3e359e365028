// The band fits' weights (sysid/band_weights.hpp): a frequency-domain regression whose residual is
// ten times larger (a hundred times the power) below 0.5 Hz, as the side force's is where the
// lateral gusts the flight path misses live. Weighted by the first fit's residual power, the
// estimate scatters less than the unweighted one, and its reported bound still holds.
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>
#include <vector>

#include "sysid/band_weights.hpp"
#include "sysid/regression.hpp"

namespace {

using cd = std::complex<double>;

/// Rows at 0.1-4 Hz (three 100-s pieces, 0.01 Hz apart), a regressor of unit power, z = 2 x + v
/// with |v| ten times larger below 0.5 Hz.
struct Rows {
  std::vector<double> f;
  Eigen::MatrixXcd X;
  Eigen::VectorXcd z;
};

Rows coloured_rows(std::mt19937& rng) {
  std::normal_distribution<double> n01;
  Rows r;
  for (int piece = 0; piece < 3; ++piece)
    for (int m = 10; m <= 400; ++m) r.f.push_back(m / 100.0);
  const auto n = static_cast<Eigen::Index>(r.f.size());
  r.X.resize(n, 1), r.z.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const cd x(n01(rng), n01(rng)), v(n01(rng), n01(rng));
    r.X(i, 0) = x;
    r.z[i] = 2.0 * x + (r.f[static_cast<std::size_t>(i)] < 0.5 ? 5.0 : 0.5) * v;
  }
  return r;
}

}  // namespace

TEST_CASE("band weights: the inverse of the residual power about each row's frequency") {
  std::mt19937 rng(7);
  const Rows r = coloured_rows(rng);
  const auto first = tern::core::sysid::least_squares_frequency(r.X, r.z);
  const Eigen::VectorXd w = tern::core::sysid::residual_power_weights(r.f, first.residual);
  REQUIRE(w.size() == r.X.rows());
  CHECK(w.squaredNorm() / static_cast<double>(w.size()) == doctest::Approx(1.0));
  double low = 0.0, high = 0.0;  // mean weight well inside each half
  int nl = 0, nh = 0;
  for (std::size_t i = 0; i < r.f.size(); ++i) {
    if (r.f[i] < 0.4) low += w[static_cast<Eigen::Index>(i)] * w[static_cast<Eigen::Index>(i)], ++nl;
    if (r.f[i] > 0.6) high += w[static_cast<Eigen::Index>(i)] * w[static_cast<Eigen::Index>(i)], ++nh;
  }
  const double ratio = (low / nl) / (high / nh);  // the inverse of the power's ratio, 1:100
  CAPTURE(ratio);
  CHECK(ratio > 0.0065);
  CHECK(ratio < 0.0135);
  CHECK(tern::core::sysid::residual_power_weights(r.f, Eigen::VectorXd::Zero(w.size())).size() == 0);
  CHECK_THROWS_AS(tern::core::sysid::residual_power_weights({0.1, 0.2}, first.residual), std::invalid_argument);
}

TEST_CASE("band weights: the weighted estimate scatters less, and its bound holds") {
  std::mt19937 rng(11);
  double plain = 0.0, weighted = 0.0, se2 = 0.0;
  const int trials = 200;
  for (int k = 0; k < trials; ++k) {
    const Rows r = coloured_rows(rng);
    const auto e = tern::core::sysid::least_squares_frequency(r.X, r.z);
    const Eigen::VectorXd w = tern::core::sysid::residual_power_weights(r.f, e.residual);
    const Eigen::MatrixXcd Xw = w.asDiagonal() * r.X;
    const Eigen::VectorXcd zw = w.asDiagonal() * r.z;
    const auto g = tern::core::sysid::least_squares_frequency(Xw, zw);
    plain += std::pow(e.theta[0] - 2.0, 2), weighted += std::pow(g.theta[0] - 2.0, 2), se2 += std::pow(g.std_error[0], 2);
  }
  const double rms_plain = std::sqrt(plain / trials), rms_weighted = std::sqrt(weighted / trials), se = std::sqrt(se2 / trials);
  CAPTURE(rms_plain);
  CAPTURE(rms_weighted);
  CAPTURE(se);
  CHECK(rms_weighted < 0.5 * rms_plain);  // the noisy tenth of the rows dominated the plain fit
  // the bound holds; it is sqrt(2) wide of the scatter: s^2 Re(X^H X)^-1 (K&M sec. 7.2.2) counts a
  // circular residual's whole power against the real parameter, which sees half of it
  CHECK(se > rms_weighted);
  CHECK(se < 1.7 * rms_weighted);
}
