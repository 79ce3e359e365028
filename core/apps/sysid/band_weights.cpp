// core/apps/sysid/band_weights.cpp: weights from the residual power across the band (band_weights.hpp).
#include "sysid/band_weights.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace tern::core::sysid {

Eigen::VectorXd residual_power_weights(const std::vector<double>& f, const Eigen::VectorXd& residual, std::size_t neighbours) {
  if (static_cast<Eigen::Index>(f.size()) != residual.size())
    throw std::invalid_argument("residual_power_weights: the residual's rows are not row_hz's");
  const std::size_t n = f.size();
  if (n == 0 || !(residual.squaredNorm() > 0.0)) return {};
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return f[a] < f[b]; });
  // running sums of |v|^2 in frequency order: the mean over a window of `span` rows about each row
  std::vector<double> cum(n + 1, 0.0);
  for (std::size_t k = 0; k < n; ++k)
    cum[k + 1] = cum[k] + residual[static_cast<Eigen::Index>(order[k])] * residual[static_cast<Eigen::Index>(order[k])];
  const std::size_t span = std::min(std::max<std::size_t>(neighbours, 1), n);
  const double least = kMinPowerShare * cum[n] / static_cast<double>(n);
  Eigen::VectorXd w(static_cast<Eigen::Index>(n));
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t lo = std::min(k - std::min(k, span / 2), n - span);
    const double power = (cum[lo + span] - cum[lo]) / static_cast<double>(span);
    w[static_cast<Eigen::Index>(order[k])] = 1.0 / std::max(power, least);
  }
  w /= w.mean();
  return w.cwiseSqrt();
}

}  // namespace tern::core::sysid
