// core/apps/sysid/instrumentation.cpp: the pitot's scale and the accelerometer's x bias beside the
// drag polar (instrumentation.hpp).
#include "sysid/instrumentation.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/SVD>
#include <fmt/format.h>

#include "sysid/regression.hpp"
#include "tern/math.hpp"

namespace tern::core::sysid {

namespace {

/// Every n-th sample enters the wind triangle's fit: neighbours at 50 Hz carry the same gust.
constexpr std::size_t kWindStride = 25;
/// Samples of lag (after the stride) of the wind fit's coloured-residual bound: gusts last tens
/// of seconds at the Dryden model's scale lengths.
constexpr std::size_t kWindMaxLag = 60;

double mean(const Eigen::VectorXd& x) { return x.size() ? x.mean() : 0.0; }

/// The polar's slope K +- sigma and the Oswald factor 1 / (pi AR K) from it, identified when K > 0
/// and sigma below `max_relative_error` of K.
void slope(double K, double sigma, double AR, double max_relative_error, NuisanceEstimate& K_out, NuisanceEstimate& e_out) {
  K_out = {K, sigma, K > 0.0 && sigma < max_relative_error * K, ""};
  if (K_out.identified) {
    e_out = {1.0 / (kPi * AR * K), sigma / (kPi * AR * K * K), true, ""};
  } else {
    K_out.note = e_out.note = fmt::format("the polar's slope {:.4f} +- {:.2g} is not determined", K, sigma);
  }
}

/// The wind triangle's rows over every kWindStride-th sample of `idx` with a pitot reading:
/// X = [Va_pitot cos(alpha) cos(beta), R(0,0), R(1,0)] (k's regressor, the wind's N and E columns
/// along body x), z = u_ground (instrumentation.hpp).
struct WindTriangle {
  Eigen::MatrixXd X;
  Eigen::VectorXd z;
};

WindTriangle wind_triangle(const FlightSeries& s, const std::vector<std::size_t>& idx, double rho) {
  std::vector<std::size_t> use;
  for (std::size_t i = 0; i < idx.size(); i += kWindStride)
    if (std::isfinite(s.qbar[idx[i]]) && s.qbar[idx[i]] > 0.0) use.push_back(idx[i]);
  const auto n = static_cast<Eigen::Index>(use.size());
  WindTriangle w{Eigen::MatrixXd(n, 3), Eigen::VectorXd(n)};
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::size_t k = use[static_cast<std::size_t>(i)];
    const Eigen::Matrix3d R = rotation_from_euler(s.phi[k], s.theta[k], s.psi[k]);
    const double Va_pitot = std::sqrt(2.0 * s.qbar[k] / rho);
    // u_ground - (R^T w)_x = k Va_pitot cos(alpha) cos(beta); the vertical wind taken as 0
    w.X(i, 0) = Va_pitot * std::cos(s.alpha[k]) * std::cos(s.beta[k]);
    w.X(i, 1) = R(0, 0), w.X(i, 2) = R(1, 0);
    w.z[i] = s.u[k];
  }
  return w;
}

constexpr const char* kNoPitot = "no pitot in the log (the airspeed is the estimator's)";

}  // namespace

AirspeedScale airspeed_scale(const FlightSeries& s, const std::vector<std::size_t>& idx, double rho, double max_correlation) {
  AirspeedScale out;
  out.k.estimate = 1.0;
  const WindTriangle t = wind_triangle(s, idx, rho);
  out.samples = static_cast<std::size_t>(t.z.size());
  if (out.samples < 10) {
    out.k.note = kNoPitot;
    return out;
  }
  // k's regressor against what the wind's columns explain of it (uncentred: no intercept in the
  // model), as a multiple correlation; rank-revealing, so one heading (the wind's columns constant
  // and collinear with each other) is caught too
  const Eigen::MatrixXd W = t.X.rightCols(2);
  const Eigen::VectorXd explained = W * W.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(t.X.col(0));
  const double r = explained.norm() / t.X.col(0).norm();
  if (r > max_correlation) {
    out.k.note = fmt::format("airspeed and the wind's projection collinear (|r| {:.2f}): fly turns", r);
    return out;
  }
  const LsEstimate e = least_squares(t.X, t.z, kWindMaxLag);
  out.k = {e.theta[0], e.std_error[0], true, ""};
  out.w_n = e.theta[1], out.w_e = e.theta[2];
  out.rms_residual = std::sqrt(e.s2);
  return out;
}

void check_stated_pitot_scale(double k, double std_error) {
  if (!(k >= kMinPitotScale && k <= kMaxPitotScale))
    throw std::invalid_argument(fmt::format("{}: expected {:g} .. {:g} (Va_true / Va_pitot)", k, kMinPitotScale, kMaxPitotScale));
  if (!(std_error >= 0.0 && std_error < kMaxPitotScaleStdError))
    throw std::invalid_argument(fmt::format("standard error {}: expected 0 .. {:g}", std_error, kMaxPitotScaleStdError));
}

AirspeedScale stated_airspeed_scale(const FlightSeries& s, const std::vector<std::size_t>& idx, double rho, double k, double std_error) {
  check_stated_pitot_scale(k, std_error);
  AirspeedScale out;
  out.k = {k, std_error, false, kStatedPitotScale};
  const WindTriangle t = wind_triangle(s, idx, rho);
  out.samples = static_cast<std::size_t>(t.z.size());
  if (out.samples < 10) {
    out.k.note = std::string(kStatedPitotScale) + "; " + kNoPitot;
    return out;
  }
  // the wind along body x with k held: rank-revealing, so one heading gives the wind's least-norm part
  const Eigen::MatrixXd W = t.X.rightCols(2);
  const Eigen::VectorXd v = t.z - k * t.X.col(0);
  const Eigen::Vector2d w = W.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(v);
  out.w_n = w[0], out.w_e = w[1];
  out.rms_residual = std::sqrt((v - W * w).squaredNorm() / static_cast<double>(v.size()));
  return out;
}

DragPolar drag_polar(const std::vector<PolarWindow>& w, double AR, double max_relative_error, std::size_t max_lag, bool fit_bias,
                     double C_D_p_prior) {
  if (w.size() < 4) throw std::invalid_argument(fmt::format("drag polar: {} trim windows, at least 4 needed", w.size()));
  const auto n = static_cast<Eigen::Index>(w.size());
  Eigen::MatrixXd X(n, 3);
  Eigen::VectorXd z(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const PolarWindow& p = w[static_cast<std::size_t>(i)];
    X(i, 0) = 1.0, X(i, 1) = p.C_Lw_squared, X(i, 2) = p.bias_regressor;
    z[i] = p.C_D;
  }
  DragPolar out;
  const double bias_mean = mean(X.col(2));
  const double bias_spread = std::sqrt((X.col(2).array() - bias_mean).square().mean());
  bool with_bias = fit_bias && bias_spread > 0.01 * std::abs(bias_mean);
  LsEstimate e;
  if (with_bias) {
    e = least_squares(X, z, max_lag);
    // the bias's uncertainty as drag at the mean window: beyond max_relative_error of the drag, undetermined
    if (e.std_error[2] * std::abs(bias_mean) > max_relative_error * std::abs(mean(z))) {
      with_bias = false;
      out.bias_x.note = fmt::format("not identifiable: not separated from the polar (+-{:.2g} m/s^2 moves the drag by more than {:.0f} %)",
                                    e.std_error[2], 100.0 * max_relative_error);
    }
  } else if (fit_bias) {
    out.bias_x.note = "not identifiable: one airspeed: a constant force along body x and the drag at trim are the same line";
  } else {
    out.bias_x.note = "not fitted (tern sysid --accel-x-bias fits it)";
  }
  if (with_bias) {
    out.bias_x = {e.theta[2], e.std_error[2], true, ""};
  } else {
    e = least_squares(X.leftCols(2), z, max_lag);
  }
  out.C_D_p = {e.theta[0], e.std_error[0], true, ""};
  const double K_std_error = e.std_error[1];
  slope(e.theta[1], K_std_error, AR, max_relative_error, out.K, out.e);
  Eigen::MatrixXd centred = X.leftCols(with_bias ? 3 : 2);
  out.C_Lw_squared_mean = mean(X.col(1));
  centred.col(1).array() -= out.C_Lw_squared_mean;
  const LsEstimate at_mean = least_squares(centred, z, max_lag);
  out.C_D_at_mean = {at_mean.theta[0], at_mean.std_error[0], true, ""};
  const LsEstimate held = least_squares(X.middleCols(1, with_bias ? 2 : 1), (z.array() - C_D_p_prior).matrix(), max_lag);
  slope(held.theta[0], K_std_error, AR, max_relative_error, out.K_held, out.e_held);
  out.r_squared = e.r_squared, out.rms_residual = std::sqrt(e.s2), out.rows = e.rows;
  return out;
}

}  // namespace tern::core::sysid
