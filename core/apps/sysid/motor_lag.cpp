// core/apps/sysid/motor_lag.cpp: the motor's lag from the x force (motor_lag.hpp).
#include "sysid/motor_lag.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Core>
#include <fmt/format.h>

#include "sysid/aero_samples.hpp"
#include "sysid/regression.hpp"

namespace tern::core::sysid {

namespace {

/// x less its centred moving average over `half` samples each side, within each stretch of
/// consecutive samples (`source` consecutive).
std::vector<double> high_passed(const std::vector<double>& x, const std::vector<std::size_t>& source, std::size_t half) {
  std::vector<double> out(x.size());
  std::size_t begin = 0;
  for (std::size_t k = 1; k <= x.size(); ++k) {
    if (k < x.size() && source[k] == source[k - 1] + 1) continue;
    std::vector<double> sum(k - begin + 1, 0.0);  // prefix sums of the stretch
    for (std::size_t i = begin; i < k; ++i) sum[i - begin + 1] = sum[i - begin] + x[i];
    for (std::size_t i = begin; i < k; ++i) {
      const std::size_t lo = i - begin >= half ? i - begin - half : 0, hi = std::min(k - begin, i - begin + half + 1);
      out[i] = x[i] - (sum[hi] - sum[lo]) / static_cast<double>(hi - lo);
    }
    begin = k;
  }
  return out;
}

/// The x force's residual mean square with the throttle `delta_t` (header).
double residual(const FlightSeries& series, const std::vector<double>& delta_t, const Aircraft& prior, const AirborneFilter& airborne,
                double highpass_s) {
  FlightSeries s = series;
  s.delta_t = delta_t;
  const AeroSamples a = aero_samples(s, prior, airborne);
  if (a.size() < 10) return std::nan("");
  const double dt = (a.t.back() - a.t.front()) / static_cast<double>(a.size() - 1);
  const auto half = static_cast<std::size_t>(std::max(1.0, std::round(0.5 * highpass_s / dt)));
  std::vector<double> alpha2(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) alpha2[k] = a.alpha[k] * a.alpha[k];
  const std::vector<const std::vector<double>*> columns = {&a.alpha, &alpha2, &a.q_hat, &a.delta_e};
  const auto n = static_cast<Eigen::Index>(a.size());
  Eigen::MatrixXd X(n, static_cast<Eigen::Index>(columns.size()));
  for (std::size_t j = 0; j < columns.size(); ++j) {
    const std::vector<double> c = high_passed(*columns[j], a.source, half);
    for (Eigen::Index i = 0; i < n; ++i) X(i, static_cast<Eigen::Index>(j)) = c[static_cast<std::size_t>(i)];
  }
  const std::vector<double> z = high_passed(a.C_X, a.source, half);
  return least_squares(X, Eigen::Map<const Eigen::VectorXd>(z.data(), n), 0).s2;
}

}  // namespace

MotorLag estimate_motor_lag(const FlightSeries& series, const ThrottleAt& throttle, const Aircraft& prior, const AirborneFilter& airborne,
                            double start_tau, const MotorLagOptions& o) {
  if (!(o.max_tau_s > 0.0) || !(o.step_s > 0.0))
    throw std::invalid_argument(fmt::format("motor lag: a grid to {} s by {} s has no points", o.max_tau_s, o.step_s));
  MotorLag out;
  const auto steps = static_cast<std::size_t>(std::floor(o.max_tau_s / o.step_s + 0.5));
  std::size_t best = 0;
  for (std::size_t i = 0; i <= steps; ++i) {
    const double tau = static_cast<double>(i) * o.step_s;
    const double r = residual(series, throttle(tau), prior, airborne, o.highpass_s);
    out.curve.emplace_back(tau, r);
    if (std::isfinite(r) && !(out.curve[best].second <= r)) best = i;  // a NaN residual is never the least
  }
  const double at_start = residual(series, throttle(start_tau), prior, airborne, o.highpass_s);
  const auto [tau, least] = out.curve[best];
  double lo = tau, hi = tau;  // the span within min_gain of the minimum
  for (const auto& [t, r] : out.curve)
    if (r <= least * (1.0 + o.min_gain)) lo = std::min(lo, t), hi = std::max(hi, t);
  out.tau = {start_tau, 0.0, false, ""};
  if (!std::isfinite(least) || !std::isfinite(at_start)) {
    out.tau.note = "too few airborne samples";
  } else if (best == steps) {
    out.tau.note = fmt::format("the x force's residual falls to the grid's top ({:g} s): no first-order lag explains it", o.max_tau_s);
  } else if (!(least < at_start * (1.0 - o.min_gain))) {
    out.tau.note = fmt::format("the x force's residual at {:.3f} s is within {:g} % of the servos' lag's", tau, 100.0 * o.min_gain);
  } else {
    out.tau = {tau, 0.5 * (hi - lo), true, ""};
  }
  const std::string span =
      hi - lo < 0.5 * o.step_s ? fmt::format("to the grid's {:g} s", o.step_s) : fmt::format("within {:.3f}-{:.3f} s", lo, hi);
  out.line = out.tau.identified ? fmt::format(
                                      "motor lag: {:.3f} s ({}), the thrust's first-order lag behind the throttle, from the x "
                                      "force (its residual {:.1f} % below the {:.3f} s it would be loaded with)",
                                      tau, span, 100.0 * (1.0 - least / at_start), start_tau)
                                : fmt::format("motor lag: {:.3f} s kept (the servos' lag): {}", start_tau, out.tau.note);
  return out;
}

}  // namespace tern::core::sysid
