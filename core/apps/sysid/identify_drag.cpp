// core/apps/sysid/identify_drag.cpp: the polar (identify_drag.hpp).
#include "sysid/identify_drag.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "sysid/instrumentation.hpp"
#include "tern/math.hpp"
#include "tern/aero/model.hpp"

namespace tern::core::sysid {

namespace {

/// The drag coefficient with the body forces turned through `alpha`.
Col drag_at(const AeroSamples& a, const Col& alpha) {
  Col C_D(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) C_D[k] = -(std::cos(alpha[k]) * a.C_X[k] + std::sin(alpha[k]) * a.C_Z[k]);
  return C_D;
}

/// The polar's trim windows (instrumentation.hpp): C_D - C_D_q q^ - C_D_delta_e delta_e, C_Lw^2 with
/// C_Lw = C_L_scale (C_L_0 + C_L_alpha alpha) (sim_aero's drag_coefficient in the linear range) and
/// the accelerometer bias's regressor -m cos(alpha) / (qbar_xz S), each a window's mean.
std::vector<PolarWindow> polar_windows(const Context& c, const AeroSamples& a, const Col& alpha, const Aircraft& ac, double C_L_scale,
                                       double kept_scale = 1.0) {
  const Col C_D = drag_at(a, alpha);
  Col z(a.size()), clw2(a.size()), bias(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    z[k] = C_D[k] - kept_scale * (c.coef.C_D_q * a.q_hat[k] + c.coef.C_D_delta_e * a.delta_e[k]);
    const double C_Lw = C_L_scale * (c.coef.C_L_0 + c.coef.C_L_alpha * alpha[k]);
    clw2[k] = C_Lw * C_Lw;
    const double V_xz = a.Va[k] * std::cos(a.beta[k]);
    bias[k] = -ac.mass * std::cos(alpha[k]) / (0.5 * ac.rho * V_xz * V_xz * ac.S);
  }
  const Col zm = window_means(z, c.L), cm = window_means(clw2, c.L), bm = window_means(bias, c.L);
  std::vector<PolarWindow> w(zm.size());
  for (std::size_t i = 0; i < zm.size(); ++i) w[i] = {zm[i], cm[i], bm[i]};
  return w;
}

/// What the kept C_D_q and C_D_delta_e (kPriorUncertainty of their prior) move the polar at the
/// flight's trim by: the windows take the change up in the polar, the trim's own elevator term
/// adds it back, and the two differ where the elevator's trim moves with the airspeed.
double kept_terms_at_trim(const Context& c, const Col& alpha, const Aircraft& prior, const DragPolar& p) {
  const double s = 1.0 + kPriorUncertainty;
  const DragPolar q =
      drag_polar(polar_windows(c, c.a, alpha, prior, 1.0, s), prior.AR(), c.o.max_relative_error, 3, c.o.fit_accel_x_bias, c.prior.C_D_p);
  const double C_Lw = c.coef.C_L_0 + c.coef.C_L_alpha * c.result.trim_alpha;
  const double polar =
      (q.C_D_at_mean.estimate - p.C_D_at_mean.estimate) + (C_Lw * C_Lw - p.C_Lw_squared_mean) * (q.K.estimate - p.K.estimate);
  return std::abs(polar + (s - 1.0) * c.coef.C_D_delta_e * c.result.trim_delta_e);
}

/// sigma widened by what `shifted` moved the estimate by (a consider term: the pitot scale's).
void widen(NuisanceEstimate& e, const NuisanceEstimate& shifted) {
  if (e.identified && shifted.identified) e.std_error = std::hypot(e.std_error, shifted.estimate - e.estimate);
}

}  // namespace

void drag(Context& c, const Col& alpha, const Aircraft& prior, const AeroSamples* at_k_plus_sigma, double C_L_scale) {
  const double C_D_p_prior = c.prior.C_D_p;
  DragPolar p =
      drag_polar(polar_windows(c, c.a, alpha, prior, 1.0), prior.AR(), c.o.max_relative_error, 3, c.o.fit_accel_x_bias, C_D_p_prior);
  if (at_k_plus_sigma != nullptr) {
    const DragPolar q = drag_polar(polar_windows(c, *at_k_plus_sigma, alpha, prior, C_L_scale), prior.AR(), c.o.max_relative_error, 3,
                                   c.o.fit_accel_x_bias, C_D_p_prior);
    widen(p.C_D_p, q.C_D_p), widen(p.K, q.K), widen(p.e, q.e), widen(p.bias_x, q.bias_x), widen(p.e_held, q.e_held);
    widen(p.C_D_at_mean, q.C_D_at_mean);
    c.result.trim_drag_bound.pitot_shift = std::abs(q.C_D_at_mean.estimate - p.C_D_at_mean.estimate);
  }
  TrimDragBound& bound = c.result.trim_drag_bound;
  bound.kept_terms = kept_terms_at_trim(c, alpha, prior, p);
  bound.C_Lw_squared_mean = p.C_Lw_squared_mean, bound.C_D_at_mean = p.C_D_at_mean, bound.K_std_error = p.K.std_error;
  c.result.fits.push_back({"drag", "trim", p.r_squared, p.rms_residual, p.rows, p.r_squared});
  c.coef.C_D_p = p.C_D_p.estimate;
  const Term tp{"C_D_p", &AeroCoefficients::C_D_p, nullptr, {}};
  CoefficientEstimate& r = record(c, tp, "trim");
  r.std_error = p.C_D_p.std_error;
  r.identified = true;
  const double prior_e = c.result.aircraft.e;
  if (p.e.identified) {
    c.result.aircraft.e = p.e.estimate;
    c.result.notes.push_back(fmt::format("e (Oswald factor): {:.3f} +- {:.2g} (prior {:.3f}), from the polar's slope {:.4f} +- {:.2g}",
                                         p.e.estimate, p.e.std_error, prior_e, p.K.estimate, p.K.std_error));
  } else {
    c.result.notes.push_back(fmt::format("e (Oswald factor): kept, {}", p.K.note));
  }
  c.result.oswald = p.e;
  c.result.oswald_C_D_p_held = p.e_held;
  c.result.accel_x_bias = p.bias_x;
  if (!p.bias_x.identified) c.result.notes.push_back(fmt::format("accelerometer x bias: {}; 0 taken", p.bias_x.note));
  for (const Term& t :
       {Term{"C_D_q", &AeroCoefficients::C_D_q, nullptr, {}}, Term{"C_D_delta_e", &AeroCoefficients::C_D_delta_e, nullptr, {}}})
    record(c, t, "trim").note = "kept: small beside the polar's terms at trim";
}

void trim_point(SysidResult& r, const Col& alpha, const AeroSamples& a) {
  double al = 0.0, de = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) al += alpha[k], de += a.delta_e[k];
  r.trim_alpha = al / static_cast<double>(a.size()), r.trim_delta_e = de / static_cast<double>(a.size());
}

void drag_at_trim(SysidResult& r, const Aircraft& prior) {
  const double al = r.trim_alpha, de = r.trim_delta_e;
  r.C_D_trim_prior = sim::drag_coefficient(prior, al) + prior.aero.C_D_delta_e * de;
  r.C_D_trim = sim::drag_coefficient(r.aircraft, al) + r.aircraft.aero.C_D_delta_e * de;
  const double C_L = sim::lift_coefficient(r.aircraft, al) + r.aircraft.aero.C_L_delta_e * de;
  r.C_D_per_deg = C_L * kRadPerDeg / r.C_D_trim;
  const CoefficientEstimate* C_D_p = find_estimate(r, "C_D_p");
  const bool from_data = r.oswald.identified || (C_D_p != nullptr && C_D_p->identified);
  const double C_Lw = r.aircraft.aero.C_L_0 + r.aircraft.aero.C_L_alpha * al;  // the polar windows' lift model (polar_windows)
  const TrimDragBound& b = r.trim_drag_bound;
  r.C_D_trim_std_error = from_data && b.C_D_at_mean.identified
                             ? std::hypot(b.C_D_at_mean.std_error, (C_Lw * C_Lw - b.C_Lw_squared_mean) * b.K_std_error, b.kept_terms)
                             : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace tern::core::sysid
