// core/apps/sysid/equation_error.cpp: the band, bias and trim fits (equation_error.hpp).
#include "sysid/equation_error.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "sysid/band_weights.hpp"
#include "sysid/jackknife.hpp"
#include "tern/math.hpp"

namespace tern::core::sysid {

namespace {

/// Why a term's regressor was not excited, or "".
std::string unexcited(Context& c, const Term& t) {
  const Excitation& x = t.excitation;
  if (x.signal == nullptr) return "";
  const double level = x.peak ? peak(*x.signal) : rms(detrended(*x.signal, c.L));
  return level > x.threshold ? "" : x.what;
}

/// Why each free term fails after a fit (collinear, poorly determined), by name.
std::map<std::string, std::string> failures(Context& c, const std::vector<Term>& free, const LsEstimate& e, const Eigen::MatrixXd& R) {
  std::map<std::string, std::string> bad;
  for (std::size_t j = 0; j < free.size(); ++j) {
    const auto J = static_cast<Eigen::Index>(j);
    for (std::size_t i = 0; i < free.size(); ++i)
      if (i != j && std::abs(R(J, static_cast<Eigen::Index>(i))) > c.o.max_correlation) {
        bad[free[j].name] = fmt::format("collinear with {} (r = {:.2f})", free[i].name, R(J, static_cast<Eigen::Index>(i)));
        break;
      }
    if (!bad.count(free[j].name) && e.std_error[J] > c.o.max_relative_error * std::abs(e.theta[J]))
      bad[free[j].name] = fmt::format("{}: {:.3g} +- {:.2g}", kPoorlyDetermined, e.theta[J], e.std_error[J]);
  }
  return bad;
}

/// The trim windows' means of each column, as a matrix (rows: windows).
Eigen::MatrixXd window_matrix(const Context& c, const std::vector<const Col*>& columns) {
  Eigen::MatrixXd X(static_cast<Eigen::Index>(c.L.windows.size()), static_cast<Eigen::Index>(columns.size()));
  for (std::size_t j = 0; j < columns.size(); ++j) {
    const Col m = window_means(*columns[j], c.L);
    for (std::size_t i = 0; i < m.size(); ++i) X(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = m[i];
  }
  return X;
}

}  // namespace

std::size_t least_determined(const Eigen::VectorXd& estimate, const Eigen::VectorXd& std_error, const std::vector<double>& prior,
                             const std::vector<bool>& failed) {
  const auto n = static_cast<Eigen::Index>(failed.size());
  if (estimate.size() != n || std_error.size() != n || prior.size() != failed.size())
    throw std::invalid_argument("least_determined: estimate, std_error, prior and failed differ in length");
  std::size_t worst = failed.size();
  double worst_ratio = -1.0;
  for (std::size_t j = 0; j < failed.size(); ++j) {
    const auto J = static_cast<Eigen::Index>(j);
    const double size = prior[j] != 0.0 ? std::abs(prior[j]) : std::abs(estimate[J]);
    const double ratio = std_error[J] / std::max(size, 1e-300);
    if (failed[j] && (worst == failed.size() || ratio > worst_ratio)) worst = j, worst_ratio = ratio;
  }
  return worst;
}

CoefficientEstimate& record(Context& c, const Term& t, const std::string& method) {
  CoefficientEstimate e;
  e.name = t.name;
  e.prior = c.prior.*t.member;
  e.estimate = c.coef.*t.member;
  e.method = method;
  e.equation_error = e.estimate;
  c.result.coefficients.push_back(e);
  return c.result.coefficients.back();
}

void band_fit(Context& c, const std::string& axis, const Col& z, const std::vector<Term>& terms) {
  std::vector<Term> free;
  std::map<std::string, std::string> why;
  for (const Term& t : terms) {
    const std::string u = unexcited(c, t);
    if (u.empty())
      free.push_back(t);
    else
      why[t.name] = u;
  }
  while (!free.empty()) {
    Eigen::VectorXcd zf = c.spectra.of(z);
    for (const Term& t : terms)
      if (why.count(t.name)) zf -= (c.prior.*t.member) * c.spectra.of(*t.x);
    Eigen::MatrixXcd X(zf.size(), static_cast<Eigen::Index>(free.size())), Z(X.rows(), X.cols());
    bool instrumented = false;
    for (std::size_t j = 0; j < free.size(); ++j) {
      X.col(static_cast<Eigen::Index>(j)) = c.spectra.of(*free[j].x);
      Z.col(static_cast<Eigen::Index>(j)) = c.spectra.of(free[j].instrument != nullptr ? *free[j].instrument : *free[j].x);
      instrumented = instrumented || free[j].instrument != nullptr;
    }
    if (X.rows() <= X.cols())
      throw std::runtime_error(fmt::format("{}: too few frequency rows in {}..{} Hz", axis, c.o.band_lo_hz, c.o.band_hi_hz));
    LsEstimate e = least_squares_frequency(X, zf, instrumented ? &Z : nullptr);
    // with instruments the estimate rests on Z: collinear instruments leave it undetermined (judged
    // on the rows as measured: weights that single out a few rows do not make regressors collinear)
    const Eigen::MatrixXd R = column_correlation(instrumented ? Z : X);
    // the rows weighted by the inverse of the first fit's residual power (band_weights.hpp; an exact
    // fit has nothing to weight)
    Eigen::VectorXd w = residual_power_weights(c.spectra.row_frequencies(), e.residual);
    if (w.size() == 0) w = Eigen::VectorXd::Ones(X.rows());
    X = w.asDiagonal() * X, Z = w.asDiagonal() * Z, zf = w.asDiagonal() * zf;
    const Eigen::VectorXd equal_rows = e.theta;
    e = least_squares_frequency(X, zf, instrumented ? &Z : nullptr);
    // an instrument that shares some of the noise biases the two fits differently: what they
    // disagree by goes into the bound
    e.std_error = (e.std_error.cwiseAbs2() + (e.theta - equal_rows).cwiseAbs2()).cwiseSqrt();
    e.std_error = e.std_error.cwiseMax(batch_scatter(c.spectra, X, zf, Z, instrumented));
    const std::map<std::string, std::string> bad = failures(c, free, e, R);
    if (bad.empty()) {
      for (const Term& t : terms) {  // the kept priors as consider parameters
        if (!why.count(t.name)) continue;
        const Eigen::VectorXcd shifted = zf - kPriorUncertainty * (c.prior.*t.member) * (w.asDiagonal() * c.spectra.of(*t.x));
        const LsEstimate moved = least_squares_frequency(X, shifted, instrumented ? &Z : nullptr);
        e.std_error = (e.std_error.cwiseAbs2() + (moved.theta - e.theta).cwiseAbs2()).cwiseSqrt();
      }
      c.result.fits.push_back({axis, "band", e.r_squared, std::sqrt(e.s2), e.rows, e.r_squared_generalized});
      for (std::size_t j = 0; j < free.size(); ++j) {
        c.coef.*free[j].member = e.theta[static_cast<Eigen::Index>(j)];
        CoefficientEstimate& r = record(c, free[j], "band");
        r.std_error = e.std_error[static_cast<Eigen::Index>(j)];
        r.identified = true;
      }
      break;
    }
    // one term at a time, the least determined first: of two collinear terms the other may then stand
    std::vector<double> prior(free.size());
    std::vector<bool> failed(free.size());
    for (std::size_t j = 0; j < free.size(); ++j) prior[j] = c.prior.*free[j].member, failed[j] = bad.count(free[j].name) > 0;
    const std::size_t worst = least_determined(e.theta, e.std_error, prior, failed);
    why[free[worst].name] = bad.at(free[worst].name);
    free.erase(free.begin() + static_cast<std::ptrdiff_t>(worst));
  }
  for (const Term& t : terms)
    if (why.count(t.name)) {
      c.coef.*t.member = c.prior.*t.member;
      record(c, t, "band").note = why[t.name];
    }
}

void bias_fit(Context& c, const std::string& name, Member member, const Col& z, const std::vector<Term>& terms) {
  Col resid(z);
  for (const Term& t : terms)
    for (std::size_t k = 0; k < z.size(); ++k) resid[k] -= (c.coef.*t.member) * (*t.x)[k];
  const Col m = window_means(resid, c.L);
  Eigen::MatrixXd X = Eigen::MatrixXd::Ones(static_cast<Eigen::Index>(m.size()), 1);
  const Eigen::VectorXd zz = Eigen::Map<const Eigen::VectorXd>(m.data(), static_cast<Eigen::Index>(m.size()));
  const LsEstimate e = least_squares(X, zz, 3);
  c.coef.*member = e.theta[0];
  CoefficientEstimate& r = record(c, {name, member, nullptr, {}}, "trim");
  r.std_error = e.std_error[0];
  r.identified = true;
}

LsEstimate trim_fit(Context& c, const Col& z, const std::vector<const Col*>& columns, const std::vector<const Col*>& instruments) {
  const Col zm = window_means(z, c.L);
  const Eigen::MatrixXd X = window_matrix(c, columns);
  if (X.rows() <= X.cols()) throw std::runtime_error(fmt::format("too few trim windows ({}) of {} s", X.rows(), c.o.trim_window_s));
  const Eigen::MatrixXd Z = instruments.empty() ? X : window_matrix(c, instruments);
  const Eigen::Map<const Eigen::VectorXd> zz(zm.data(), static_cast<Eigen::Index>(zm.size()));
  const Eigen::MatrixXd* iv = instruments.empty() ? nullptr : &Z;
  LsEstimate e = least_squares(X, zz, 3, iv);
  e.std_error = e.std_error.cwiseMax(trim_jackknife(c.L, c.o.trim_window_s, X, zz, iv));
  return e;
}

Signals signals(const AeroSamples& a, const Col& alpha, const Col& beta) {
  const double angle = kMinAngleMotion, rate = 5.0 * kRadPerDeg;
  return {{&alpha, false, angle, "alpha never moved more than 0.3 deg about its trim"},
          {&beta, false, angle, "sideslip never moved more than 0.3 deg about its trim"},
          {&a.p, true, 2.0 * rate, "roll rate never above 10 deg/s"},
          {&a.q, true, rate, "pitch rate never above 5 deg/s"},
          {&a.r, true, rate, "yaw rate never above 5 deg/s"},
          {&a.delta_a, false, angle, "aileron never moved more than 0.3 deg about its trim"},
          {&a.delta_e, false, angle, "elevator never moved more than 0.3 deg about its trim"},
          {&a.delta_r, false, angle, "rudder never moved more than 0.3 deg about its trim"}};
}

const CoefficientEstimate* find_estimate(const SysidResult& r, const std::string& name) {
  const auto it = std::find_if(r.coefficients.begin(), r.coefficients.end(), [&](const CoefficientEstimate& e) { return e.name == name; });
  return it == r.coefficients.end() ? nullptr : &*it;
}

CoefficientEstimate* find_estimate(SysidResult& r, const std::string& name) {
  return const_cast<CoefficientEstimate*>(find_estimate(static_cast<const SysidResult&>(r), name));
}

std::optional<CoefficientEstimate> take_out(Context& c, const std::string& name) {
  auto& all = c.result.coefficients;
  const auto it = std::find_if(all.begin(), all.end(), [&](const CoefficientEstimate& e) { return e.name == name; });
  std::optional<CoefficientEstimate> out;
  if (it == all.end()) return out;
  if (it->identified) out = *it;
  all.erase(it);
  return out;
}

}  // namespace tern::core::sysid
