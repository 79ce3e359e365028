// core/apps/sysid/identify_lift.cpp: the lift (identify_lift.hpp).
#include "sysid/identify_lift.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "sysid/model_instruments.hpp"
#include "sysid/verdicts.hpp"
#include "tern/math.hpp"

namespace tern::core::sysid {

namespace {

/// C_L - C_L_q q^ - C_L_delta_e delta_e = C_L_0 + C_L_alpha alpha on the trim windows' means (the
/// two terms scaled by q_scale, delta_e_scale: the consider covariance's shifted fits).
LsEstimate lift_trim_fit(Context& c, double q_scale = 1.0, double delta_e_scale = 1.0) {
  const AeroSamples& a = c.a;
  Col z(a.size());
  for (std::size_t k = 0; k < a.size(); ++k)
    z[k] = a.C_L[k] - q_scale * c.coef.C_L_q * a.q_hat[k] - delta_e_scale * c.coef.C_L_delta_e * a.delta_e[k];
  const Col ones(a.size(), 1.0);
  // alpha's instrument: 1 / qbar (the trim's alpha at 1 g goes as m g / (qbar S)), whose error (the
  // pitot's noise, the longitudinal gust) is independent of the reconstructed alpha's (the vertical
  // gust): the window means of alpha carry that error undiminished by the flight's length, and
  // ordinary least squares on them flattens the lift curve
  Col inv_qbar(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) inv_qbar[k] = 1.0 / (a.Va[k] * a.Va[k]);
  return trim_fit(c, z, {&ones, &a.alpha}, {&ones, &inv_qbar});
}

/// The lift's trim fit with the bounds widened by what the kept pitch-rate and elevator terms'
/// uncertainty (kPriorUncertainty, or the band's standard error where identified) moves it by.
LsEstimate lift_trim_considered(Context& c) {
  LsEstimate e = lift_trim_fit(c);
  Eigen::VectorXd extra = Eigen::VectorXd::Zero(e.theta.size());
  for (const char* name : {"C_L_q", "C_L_delta_e"}) {
    double rel = kPriorUncertainty;
    for (const auto& r : c.result.coefficients)
      if (r.name == name && r.identified && r.estimate != 0.0) rel = r.std_error / std::abs(r.estimate);
    const bool q = std::string(name) == "C_L_q";
    const LsEstimate shifted = lift_trim_fit(c, q ? 1.0 + rel : 1.0, q ? 1.0 : 1.0 + rel);
    extra += (shifted.theta - e.theta).cwiseAbs2();
  }
  e.std_error = (e.std_error.cwiseAbs2() + extra).cwiseSqrt();
  return e;
}

/// The band's lift fit on the reconstructed alpha below which its terms are not taken.
constexpr double kMinLiftBandFit = 0.9;

/// The lift's pitch-rate and elevator terms back to the prior, with the reason.
void lift_band_rejected(Context& c, const std::string& why) {
  for (auto& e : c.result.coefficients)
    if ((e.name == "C_L_q" || e.name == "C_L_delta_e") && e.identified) {
      e.identified = false, e.estimate = e.prior, e.std_error = 0.0, e.note = why;
      c.coef.*(e.name == "C_L_q" ? &M::C_L_q : &M::C_L_delta_e) = e.prior;
    }
}

/// Why physics forbids the band's C_L_q (verdicts.hpp), "" when it does not or was not identified.
std::string band_C_L_q_sign(Context& c) {
  const CoefficientEstimate* q = find_estimate(c.result, "C_L_q");
  return q != nullptr && q->identified ? forbidden_sign(q->name, q->estimate) : "";
}

}  // namespace

void lift(Context& c, const Excitation& alpha, const Excitation& q, const Excitation& delta_e) {
  const AeroSamples& a = c.a;
  // the reconstructed alpha misses the vertical gusts: instrumented by the longitudinal model's
  const Col alpha_model(a.size(), 0.0);  // a key: its spectrum is put in the frequency domain
  std::string why;
  const bool iv = put_model_instrument(c, Modelled::alpha, alpha_model, why);
  if (!iv) c.result.notes.push_back(fmt::format("lift: alpha not instrumented in the band: {}", why));
  band_fit(c, "lift", a.C_L,
           {{"C_L_alpha", &M::C_L_alpha, &a.alpha, alpha, iv ? &alpha_model : nullptr},
            {"C_L_q", &M::C_L_q, &a.q_hat, q},
            {"C_L_delta_e", &M::C_L_delta_e, &a.delta_e, delta_e}});
  c.spectra.forget(&alpha_model);
  const std::optional<CoefficientEstimate> band = take_out(c, "C_L_alpha");
  c.coef.C_L_alpha = c.prior.C_L_alpha;
  const Term t0{"C_L_0", &M::C_L_0, nullptr, {}}, ta{"C_L_alpha", &M::C_L_alpha, nullptr, {}};
  const double spread = stddev(window_means(a.alpha, c.L));
  if (spread < kRadPerDeg) {
    const std::string why = fmt::format("alpha's trim never spread beyond {:.2f} deg (fly several airspeeds)", spread * kDegPerRad);
    record(c, t0, "trim").note = why;
    record(c, ta, "trim").note = why;
    lift_band_rejected(c, "not checked: no trim C_L_alpha to hold the band's against");
    return;
  }
  LsEstimate e = lift_trim_considered(c);
  const auto fit = std::find_if(c.result.fits.begin(), c.result.fits.end(), [](const AxisFit& f) { return f.axis == "lift"; });
  if (fit != c.result.fits.end() && fit->r_squared < kMinLiftBandFit) {
    lift_band_rejected(c, fmt::format("the reconstructed alpha explains R^2 {:.2f} of the lift in the band (gusts the flight path misses)",
                                      fit->r_squared));
    e = lift_trim_considered(c);
  } else if (const std::string sign = band_C_L_q_sign(c); !sign.empty()) {
    // a C_L_q physics forbids (verdicts.hpp) is the band's alpha taking the elevator's and the pitch
    // rate's parts the wrong way (a foreign Anaconda log: C_L_q -66 against 7.95, C_L_delta_e -1.9,
    // then a trim C_L_alpha of -0.29 and every pitch derivative lost): the band's terms go back to the
    // prior before alpha is reconstructed through them
    lift_band_rejected(c, fmt::format("C_L_q from the band, {}: the band's alpha does not separate it", sign));
    e = lift_trim_considered(c);
  } else if (band && std::abs(band->estimate - e.theta[1]) > std::max(3.0 * band->std_error, 0.05 * std::abs(e.theta[1]))) {
    lift_band_rejected(
        c, fmt::format("the reconstructed alpha disagrees with the lift (C_L_alpha {:.3g} +- {:.2g} in the band, {:.3g} from the trim): "
                       "gusts the flight path misses",
                       band->estimate, band->std_error, e.theta[1]));
    e = lift_trim_considered(c);
  }
  c.coef.C_L_0 = e.theta[0], c.coef.C_L_alpha = e.theta[1];
  c.result.fits.push_back({"lift", "trim", e.r_squared, std::sqrt(e.s2), e.rows, e.r_squared_generalized});
  for (int j = 0; j < 2; ++j) {
    CoefficientEstimate& r = record(c, j == 0 ? t0 : ta, "trim");
    r.std_error = e.std_error[j];
    r.identified = true;
  }
}

Col alpha_from_lift(const Context& c) {
  const AeroSamples& a = c.a;
  Col alpha = a.alpha;
  for (int pass = 0; pass < 3; ++pass)
    for (std::size_t k = 0; k < a.size(); ++k) {
      const double C_L = std::sin(alpha[k]) * a.C_X[k] - std::cos(alpha[k]) * a.C_Z[k];
      alpha[k] = (C_L - c.coef.C_L_0 - c.coef.C_L_q * a.q_hat[k] - c.coef.C_L_delta_e * a.delta_e[k]) / c.coef.C_L_alpha;
    }
  return alpha;
}

void consider_lift_terms(Context& c) {
  const double ratio = std::abs(c.coef.C_m_alpha / c.coef.C_L_alpha);
  const std::pair<const char*, const char*> pairs[] = {{"C_m_q", "C_L_q"}, {"C_m_delta_e", "C_L_delta_e"}};
  for (const auto& [moment, lift] : pairs) {
    CoefficientEstimate* m = find_estimate(c.result, moment);
    const CoefficientEstimate* l = find_estimate(c.result, lift);
    if (m == nullptr || l == nullptr || !m->identified || l->identified) continue;
    const double consider = ratio * kPriorUncertainty * std::abs(l->prior);
    m->std_error = std::hypot(m->std_error, consider);
  }
  // the lift's alpha is scaled by 1 / C_L_alpha, and C_m_alpha with it
  CoefficientEstimate* m_alpha = find_estimate(c.result, "C_m_alpha");
  const CoefficientEstimate* L_alpha = find_estimate(c.result, "C_L_alpha");
  if (m_alpha == nullptr || L_alpha == nullptr || !m_alpha->identified) return;
  const double relative =
      L_alpha->identified && L_alpha->estimate != 0.0 ? L_alpha->std_error / std::abs(L_alpha->estimate) : kPriorUncertainty;
  m_alpha->std_error = std::hypot(m_alpha->std_error, relative * m_alpha->estimate);
}

}  // namespace tern::core::sysid
