// core/apps/sysid/jackknife.cpp: the delete-one-batch jackknife (jackknife.hpp).
#include "sysid/jackknife.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "sysid/regression.hpp"

namespace tern::core::sysid {

namespace {

/// The block each trim window falls in: runs of `per_block` consecutive windows (the last run
/// shorter than half of it joins the one before).
std::vector<std::size_t> window_blocks(std::size_t windows, std::size_t per_block) {
  const std::size_t blocks = std::max<std::size_t>(1, (windows + per_block / 2) / per_block);
  std::vector<std::size_t> block(windows);
  for (std::size_t i = 0; i < windows; ++i) block[i] = std::min(i / per_block, blocks - 1);
  return block;
}

}  // namespace

Eigen::VectorXd jackknife_se(const std::vector<Eigen::VectorXd>& thetas, Eigen::Index p) {
  Eigen::VectorXd se = Eigen::VectorXd::Zero(p);
  if (thetas.size() < 3) return se;
  const double G = static_cast<double>(thetas.size());
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(p);
  for (const auto& t : thetas) mean += t / G;
  for (const auto& t : thetas) se += (t - mean).cwiseAbs2();
  return (se * (G - 1.0) / G).cwiseSqrt();
}

Eigen::VectorXd batch_scatter(const Spectra& spectra, const Eigen::MatrixXcd& X, const Eigen::VectorXcd& z, const Eigen::MatrixXcd& Z,
                              bool iv) {
  std::vector<Eigen::VectorXd> thetas;
  for (const auto& [first, n] : spectra.segment_rows()) {
    if (n == 0 || X.rows() - n <= 3 * X.cols()) continue;
    const Eigen::Index rest = X.rows() - n, tail = X.rows() - first - n;
    Eigen::MatrixXcd Xr(rest, X.cols()), Zr(rest, X.cols());
    Eigen::VectorXcd zr(rest);
    Xr << X.topRows(first), X.bottomRows(tail);
    Zr << Z.topRows(first), Z.bottomRows(tail);
    zr << z.head(first), z.tail(tail);
    thetas.push_back(least_squares_frequency(Xr, zr, iv ? &Zr : nullptr).theta);
  }
  return jackknife_se(thetas, X.cols());
}

Eigen::VectorXd trim_jackknife(const Layout& L, double window_s, const Eigen::MatrixXd& X, const Eigen::VectorXd& z,
                               const Eigen::MatrixXd* Z) {
  const auto per_block = static_cast<std::size_t>(std::max(1.0, std::ceil(kTrimBlock / window_s)));
  const std::vector<std::size_t> block = window_blocks(L.windows.size(), per_block);
  std::vector<Eigen::VectorXd> thetas;
  for (std::size_t b = 0; !block.empty() && b <= block.back(); ++b) {
    std::vector<Eigen::Index> keep;
    for (std::size_t i = 0; i < block.size(); ++i)
      if (block[i] != b) keep.push_back(static_cast<Eigen::Index>(i));
    if (keep.size() <= 3 * static_cast<std::size_t>(X.cols())) continue;
    const Eigen::MatrixXd Xb = X(keep, Eigen::all), Zb = Z != nullptr ? Eigen::MatrixXd((*Z)(keep, Eigen::all)) : Xb;
    const Eigen::VectorXd zb = z(keep);
    if (std::abs((Zb.transpose() * Xb).determinant()) < 1e-12 * (Zb.norm() * Xb.norm())) continue;  // a block held every airspeed
    thetas.push_back(least_squares(Xb, zb, 3, Z != nullptr ? &Zb : nullptr).theta);
  }
  return jackknife_se(thetas, X.cols());
}

}  // namespace tern::core::sysid
