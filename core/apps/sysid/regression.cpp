// core/apps/sysid/regression.cpp: least squares in the time and frequency domains (regression.hpp).
#include "sysid/regression.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "tern/avx_clones.hpp"
#include "tern/math.hpp"

namespace tern::core::sysid {

namespace {

void check_shapes(Eigen::Index rows, Eigen::Index z_rows, Eigen::Index cols) {
  if (rows != z_rows) throw std::invalid_argument("least squares: X and z have different numbers of rows");
  if (rows <= cols) throw std::invalid_argument("least squares: fewer rows than parameters");
}

Eigen::MatrixXd inverse_spd(const Eigen::MatrixXd& A) { return A.ldlt().solve(Eigen::MatrixXd::Identity(A.rows(), A.cols())); }

}  // namespace

LsEstimate least_squares(const Eigen::MatrixXd& X, const Eigen::VectorXd& z, std::size_t max_lag, const Eigen::MatrixXd* instruments) {
  check_shapes(X.rows(), z.rows(), X.cols());
  const Eigen::MatrixXd& Z = instruments != nullptr ? *instruments : X;
  if (Z.rows() != X.rows() || Z.cols() != X.cols()) throw std::invalid_argument("least squares: instruments and X differ in shape");
  const Eigen::Index n = X.rows(), p = X.cols();
  // D = (Z^T X)^-1: (X^T X)^-1 for ordinary least squares
  const Eigen::MatrixXd D = instruments != nullptr ? Eigen::MatrixXd((Z.transpose() * X).inverse()) : inverse_spd(X.transpose() * X);
  LsEstimate e;
  e.rows = static_cast<std::size_t>(n);
  e.theta = D * (Z.transpose() * z);
  e.residual = z - X * e.theta;
  e.s2 = e.residual.squaredNorm() / static_cast<double>(n - p);
  e.std_error_white = (e.s2 * D * (Z.transpose() * Z) * D.transpose()).diagonal().cwiseMax(0.0).cwiseSqrt();
  // K&M eq. 5.81: the middle term sum_k R_vv(k) sum_i (z_i z_{i+k}^T + z_{i+k} z_i^T), k > 0
  const Eigen::VectorXd& v = e.residual;
  Eigen::MatrixXd M = v.squaredNorm() / static_cast<double>(n) * (Z.transpose() * Z);
  const Eigen::Index lags = std::min<Eigen::Index>(static_cast<Eigen::Index>(max_lag), n - 1);
  for (Eigen::Index k = 1; k <= lags; ++k) {
    const double R = v.head(n - k).dot(v.tail(n - k)) / static_cast<double>(n);
    const Eigen::MatrixXd C = Z.topRows(n - k).transpose() * Z.bottomRows(n - k);
    M += R * (C + C.transpose());
  }
  const Eigen::MatrixXd cov = D * M * D.transpose();
  e.std_error = cov.diagonal().cwiseMax(0.0).cwiseSqrt().cwiseMax(e.std_error_white);
  const double zc = (z.array() - z.mean()).matrix().squaredNorm();
  e.r_squared = zc > 0.0 ? 1.0 - v.squaredNorm() / zc : 0.0;
  e.r_squared_generalized = e.r_squared;
  if (instruments != nullptr && zc > 0.0) {  // X^ theta = Z (Z^T Z)^-1 Z^T X theta
    const Eigen::VectorXd fitted = Z * inverse_spd(Z.transpose() * Z) * (Z.transpose() * (X * e.theta));
    e.r_squared_generalized = 1.0 - (z - fitted).squaredNorm() / zc;
  }
  return e;
}

LsEstimate least_squares_frequency(const Eigen::MatrixXcd& X, const Eigen::VectorXcd& z, const Eigen::MatrixXcd* instruments) {
  check_shapes(X.rows(), z.rows(), X.cols());
  const Eigen::MatrixXcd& Z = instruments != nullptr ? *instruments : X;
  if (Z.rows() != X.rows() || Z.cols() != X.cols()) throw std::invalid_argument("least squares: instruments and X differ in shape");
  const Eigen::Index n = X.rows(), p = X.cols();
  const Eigen::MatrixXd D = (Z.adjoint() * X).real().inverse();
  LsEstimate e;
  e.rows = static_cast<std::size_t>(n);
  e.theta = D * (Z.adjoint() * z).real();
  const Eigen::VectorXcd v = z - X * e.theta.cast<std::complex<double>>();
  e.residual = v.cwiseAbs();
  e.s2 = v.squaredNorm() / static_cast<double>(n - p);
  e.std_error_white = (e.s2 * D * (Z.adjoint() * Z).real() * D.transpose()).diagonal().cwiseMax(0.0).cwiseSqrt();
  // residual power differing from frequency to frequency (coloured residuals): the sandwich
  // D Re(Z^H diag(|v|^2) Z) D^T, scaled by n / (n - p) as s^2 is
  const Eigen::MatrixXcd Zw = v.cwiseAbs2().cast<std::complex<double>>().asDiagonal() * Z;
  const Eigen::MatrixXd M = (Z.adjoint() * Zw).real() * (static_cast<double>(n) / static_cast<double>(n - p));
  e.std_error = (D * M * D.transpose()).diagonal().cwiseMax(0.0).cwiseSqrt().cwiseMax(e.std_error_white);
  const double zz = z.squaredNorm();
  e.r_squared = zz > 0.0 ? 1.0 - v.squaredNorm() / zz : 0.0;
  e.r_squared_generalized = e.r_squared;
  if (instruments != nullptr && zz > 0.0) {  // X^ theta = Z Re(Z^H Z)^-1 Re(Z^H X theta): real parameters
    const Eigen::VectorXcd Xt = X * e.theta.cast<std::complex<double>>();
    const Eigen::VectorXd g = inverse_spd((Z.adjoint() * Z).real()) * (Z.adjoint() * Xt).real();
    e.r_squared_generalized = 1.0 - (z - Z * g.cast<std::complex<double>>()).squaredNorm() / zz;
  }
  return e;
}

// Built for AVX too (tern/avx_clones.hpp): the block of phasors is 2 AVX registers a line, where
// the baseline takes 4; the same results.
TERN_AVX_CLONES
Eigen::VectorXcd fourier(const std::vector<double>& x, const std::vector<double>& t, const std::vector<double>& f_hz) {
  if (x.size() != t.size()) throw std::invalid_argument("fourier: x and t differ in length");
  Eigen::VectorXcd out = Eigen::VectorXcd::Zero(static_cast<Eigen::Index>(f_hz.size()));
  if (x.size() < 2) return out;
  const double dt = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  // kBlock frequencies at a time, each phasor advanced by a recurrence per sample (exp(-j w dt)
  // once), in real arithmetic the compiler vectorises across the block; renormalised now and then
  constexpr std::size_t kBlock = 8;
  for (std::size_t i0 = 0; i0 < f_hz.size(); i0 += kBlock) {
    const std::size_t nb = std::min(kBlock, f_hz.size() - i0);
    std::array<double, kBlock> c{}, s{}, step_c{}, step_s{}, re{}, im{};
    for (std::size_t j = 0; j < nb; ++j) {
      const double w = 2.0 * kPi * f_hz[i0 + j];
      step_c[j] = std::cos(w * dt), step_s[j] = -std::sin(w * dt);
      c[j] = std::cos(w * t.front()), s[j] = -std::sin(w * t.front());
    }
    for (std::size_t k = 0; k < x.size(); ++k) {
      const double xk = x[k];
      for (std::size_t j = 0; j < kBlock; ++j) {
        re[j] += xk * c[j], im[j] += xk * s[j];
        const double cn = c[j] * step_c[j] - s[j] * step_s[j];
        s[j] = c[j] * step_s[j] + s[j] * step_c[j], c[j] = cn;
      }
      if ((k & 1023) == 1023)
        for (std::size_t j = 0; j < kBlock; ++j) {
          const double norm = std::hypot(c[j], s[j]);
          if (norm > 0.0) c[j] /= norm, s[j] /= norm;
        }
    }
    for (std::size_t j = 0; j < nb; ++j) out[static_cast<Eigen::Index>(i0 + j)] = std::complex<double>(re[j], im[j]) * dt;
  }
  return out;
}

Eigen::MatrixXd column_correlation(const Eigen::MatrixXd& X) {
  Eigen::MatrixXd C = X.rowwise() - X.colwise().mean();
  const Eigen::VectorXd norms = C.colwise().norm();
  Eigen::MatrixXd R = C.transpose() * C;
  for (Eigen::Index i = 0; i < R.rows(); ++i)
    for (Eigen::Index j = 0; j < R.cols(); ++j) R(i, j) = norms[i] * norms[j] > 0.0 ? R(i, j) / (norms[i] * norms[j]) : 0.0;
  return R;
}

Eigen::MatrixXd column_correlation(const Eigen::MatrixXcd& X) {
  const Eigen::VectorXd norms = X.colwise().norm();
  Eigen::MatrixXd R = (X.adjoint() * X).real();
  for (Eigen::Index i = 0; i < R.rows(); ++i)
    for (Eigen::Index j = 0; j < R.cols(); ++j) R(i, j) = norms[i] * norms[j] > 0.0 ? R(i, j) / (norms[i] * norms[j]) : 0.0;
  return R;
}

}  // namespace tern::core::sysid
