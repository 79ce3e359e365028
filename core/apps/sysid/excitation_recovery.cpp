// core/apps/sysid/excitation_recovery.cpp: the two-stage method's first stage (excitation_recovery.hpp).
#include "sysid/excitation_recovery.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <fmt/ranges.h>

namespace tern::core::sysid {

namespace {

/// x less its centred moving mean over `half` samples each side (the ends over what there is);
/// NaN where x is.
std::vector<double> highpassed(const std::vector<double>& x, std::size_t half) {
  const std::size_t n = x.size();
  std::vector<double> sum(n + 1, 0.0);
  std::vector<std::size_t> count(n + 1, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const bool ok = std::isfinite(x[k]);
    sum[k + 1] = sum[k] + (ok ? x[k] : 0.0);
    count[k + 1] = count[k] + (ok ? 1 : 0);
  }
  std::vector<double> out(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t b = k > half ? k - half : 0, e = std::min(n, k + half + 1);
    const std::size_t c = count[e] - count[b];
    out[k] = std::isfinite(x[k]) && c > 0 ? x[k] - (sum[e] - sum[b]) / static_cast<double>(c) : std::nan("");
  }
  return out;
}

/// x through a first-order low-pass of time constant tau (s) at step dt, causal as a controller
/// is; restarted from the sample after each NaN (NaN there).
std::vector<double> lowpassed(const std::vector<double>& x, double tau, double dt) {
  const double a = dt / (tau + dt);
  std::vector<double> out(x.size(), std::nan(""));
  bool started = false;
  double y = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!std::isfinite(x[k])) {
      started = false;
      continue;
    }
    y = started ? y + a * (x[k] - y) : x[k];
    started = true;
    out[k] = y;
  }
  return out;
}

double median_abs(std::vector<double> v) {
  if (v.empty()) return 0.0;
  for (double& x : v) x = std::abs(x);
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

struct Fit {
  std::vector<double> excitation;  ///< the command less the fitted feedback (0 where a regressor is missing)
  double r_squared = 0.0;          ///< of the kept samples
  double left_out = 0.0;           ///< share of the valid samples left out as manoeuvres
  std::size_t valid = 0;
};

/// Rows of the feedback regression's normal equations accumulated at a time (feedback_fit).
constexpr Eigen::Index kBlockRows = 1024;

/// Stage 1 for one command (header): X's columns the lagged, high-passed regressors.
Fit feedback_fit(const std::vector<double>& command, const std::vector<std::vector<double>>& X, const std::vector<unsigned char>& usable,
                 const ExcitationRecoveryOptions& o) {
  const std::size_t n = command.size(), m = X.size();
  std::vector<std::size_t> rows;
  for (std::size_t k = 0; k < n; ++k)
    if (usable[k] && std::isfinite(command[k])) rows.push_back(k);
  Fit f;
  f.excitation.assign(n, 0.0);
  f.valid = rows.size();
  if (rows.size() <= 2 * m) return f;
  std::vector<unsigned char> keep(rows.size(), 1);
  Eigen::VectorXd beta = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m));
  for (int pass = 0; pass < std::max(1, o.passes); ++pass) {
    // the normal equations in blocks of kBlockRows kept rows (a blocked product, not one rank-1
    // update per row: at a 250-Hz IMU that was a tenth of a sysid run)
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(m));
    Eigen::VectorXd b = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m));
    Eigen::MatrixXd block(kBlockRows, static_cast<Eigen::Index>(m));
    Eigen::VectorXd z(kBlockRows);
    Eigen::Index filled = 0;
    const auto flush = [&] {
      A.selfadjointView<Eigen::Lower>().rankUpdate(block.topRows(filled).transpose());
      b += block.topRows(filled).transpose() * z.head(filled);
      filled = 0;
    };
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (!keep[i]) continue;
      for (std::size_t j = 0; j < m; ++j) block(filled, static_cast<Eigen::Index>(j)) = X[j][rows[i]];
      z[filled++] = command[rows[i]];
      if (filled == kBlockRows) flush();
    }
    if (filled > 0) flush();
    A = A.selfadjointView<Eigen::Lower>();
    beta = A.ldlt().solve(b);
    std::vector<double> residual(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      double fb = 0.0;
      for (std::size_t j = 0; j < m; ++j) fb += beta[static_cast<Eigen::Index>(j)] * X[j][rows[i]];
      residual[i] = command[rows[i]] - fb;
    }
    std::vector<double> kept;
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (keep[i]) kept.push_back(residual[i]);
    const double spread = 1.4826 * median_abs(kept);
    double ss_res = 0.0, ss_tot = 0.0;
    std::size_t out = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      f.excitation[rows[i]] = residual[i];
      if (keep[i]) ss_res += residual[i] * residual[i], ss_tot += command[rows[i]] * command[rows[i]];
      keep[i] = std::abs(residual[i]) <= o.outlier_sigmas * spread;
      out += keep[i] ? 0 : 1;
    }
    f.r_squared = ss_tot > 0.0 ? 1.0 - ss_res / ss_tot : 0.0;
    f.left_out = static_cast<double>(out) / static_cast<double>(rows.size());
  }
  return f;
}

}  // namespace

void recover_excitation(FlightSeries& s, const ExcitationRecoveryOptions& o) {
  for (const double tau : o.lowpass_s)
    if (!(tau > 0.0 && std::isfinite(tau)))
      throw std::invalid_argument(fmt::format("excitation recovery: a low-pass time constant of {} s (each must be > 0)", tau));
  if (!s.exc_delta_a.empty() || s.size() < 3) return;
  const std::size_t n = s.size();
  const double dt = (s.t.back() - s.t.front()) / static_cast<double>(n - 1);
  const auto half = static_cast<std::size_t>(std::lround(0.5 * o.highpass_s / dt));
  const auto lags = static_cast<std::size_t>(std::lround(o.max_lag_s / dt));
  std::vector<double> height(n);
  for (std::size_t k = 0; k < n; ++k) height[k] = -s.p_d[k];
  std::vector<std::vector<double>> X;
  for (const auto* x : {&s.phi, &s.theta, &s.p, &s.q, &s.r, &s.beta, &s.Va, &height}) {
    const std::vector<double> h = highpassed(*x, half);
    for (std::size_t lag = 0; lag <= lags; ++lag) {
      std::vector<double> col(n, std::nan(""));
      for (std::size_t k = lag; k < n; ++k) col[k] = h[k - lag];
      X.push_back(std::move(col));
    }
    for (const double tau : o.lowpass_s) X.push_back(lowpassed(h, tau, dt));
  }
  std::vector<unsigned char> usable(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    bool ok = s.valid[k] != 0;
    for (const auto& col : X) ok = ok && std::isfinite(col[k]);
    usable[k] = ok ? 1 : 0;
  }
  const std::string lowpass_words =
      o.lowpass_s.empty() ? "" : fmt::format(" and through first-order low-passes of {} s", fmt::join(o.lowpass_s, ", "));
  const std::array<std::pair<const char*, std::vector<double>*>, 4> commands = {
      {{"aileron", &s.delta_a}, {"elevator", &s.delta_e}, {"rudder", &s.delta_r}, {"throttle", &s.delta_t}}};
  const std::array<std::vector<double>*, 4> parts = {&s.exc_delta_a, &s.exc_delta_e, &s.exc_delta_r, &s.exc_delta_t};
  for (std::size_t i = 0; i < commands.size(); ++i) {
    const Fit f = feedback_fit(highpassed(*commands[i].second, half), X, usable, o);
    *parts[i] = f.excitation;
    s.notes.push_back(
        f.valid <= 2 * X.size()
            ? fmt::format("excitation ({}): no excitation table, and too few valid samples ({}) to model the controller", commands[i].first,
                          f.valid)
            : fmt::format(
                  "excitation ({}): no excitation table; recovered as the command less its feedback of phi, theta, p, q, r, "
                  "beta, Va and height at lags 0-{:.0f} ms{}, fitted outside the manoeuvres (R^2 {:.2f}, {:.0f} % of the samples left "
                  "out; two-stage method, Ljung sec. 13.5)",
                  commands[i].first, 1e3 * static_cast<double>(lags) * dt, lowpass_words, f.r_squared, 100.0 * f.left_out));
  }
}

}  // namespace tern::core::sysid
