// core/apps/sysid/identify_lateral.cpp: the side force, the rolling and the yawing moments (identify_lateral.hpp).
#include "sysid/identify_lateral.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sysid/model_instruments.hpp"

namespace tern::core::sysid {

namespace {

/// The instruments of the lateral rates in a closed-loop flight: the lateral model's p^ and r^ for
/// the excitation (put_model_instrument), or none.
struct RateInstruments {
  const Col* p_hat = nullptr;
  const Col* r_hat = nullptr;
};

/// The lateral terms of one axis (C_Y, C_ell or C_n: members in the order beta, p, r, delta_a, delta_r);
/// with `closed_loop`, each command instrumented by its excitation's part where it has one, and the
/// rates by `rates`.
std::vector<Term> lateral_terms(const Context& c, const std::string& axis, const std::array<Member, 5>& m, const Col& beta,
                                const Signals& x, const Col* beta_instrument = nullptr, bool closed_loop = false,
                                RateInstruments rates = {}) {
  const AeroSamples& a = c.a;
  const Col* da = closed_loop ? excitation_part(c, a.delta_a) : nullptr;
  const Col* dr = closed_loop ? excitation_part(c, a.delta_r) : nullptr;
  return {{axis + "_beta", m[0], &beta, x.beta, beta_instrument},
          {axis + "_p", m[1], &a.p_hat, x.p, rates.p_hat},
          {axis + "_r", m[2], &a.r_hat, x.r, rates.r_hat},
          {axis + "_delta_a", m[3], &a.delta_a, x.delta_a, da},
          {axis + "_delta_r", m[4], &a.delta_r, x.delta_r, dr}};
}

/// beta where the side force says it was, once C_Y is known (identify.hpp, step 2); with
/// `from_force` false, the estimator's.
Col beta_from_side_force(const Context& c, bool from_force) {
  const AeroSamples& a = c.a;
  if (!from_force) return a.beta;
  const M& m = c.coef;
  Col beta(a.size());
  for (std::size_t k = 0; k < a.size(); ++k)
    beta[k] =
        (a.C_Y[k] - m.C_Y_0 - m.C_Y_p * a.p_hat[k] - m.C_Y_r * a.r_hat[k] - m.C_Y_delta_a * a.delta_a[k] - m.C_Y_delta_r * a.delta_r[k]) /
        m.C_Y_beta;
  return beta;
}

}  // namespace

Col lateral(Context& c, const Col& alpha, bool accel) {
  const AeroSamples& a = c.a;
  const Col beta_model(a.size(), 0.0);  // a key: its spectrum is put in the frequency domain
  std::string why;
  const bool side_iv = put_model_instrument(c, Modelled::beta, beta_model, why);
  if (!side_iv) c.result.notes.push_back(fmt::format("side force: beta not instrumented: {}", why));
  Signals x = signals(a, alpha, a.beta);
  std::vector<Term> side = lateral_terms(c, "C_Y", {&M::C_Y_beta, &M::C_Y_p, &M::C_Y_r, &M::C_Y_delta_a, &M::C_Y_delta_r}, a.beta, x,
                                         side_iv ? &beta_model : nullptr, side_iv);
  if (side_iv)  // the model's sideslip is itself a mix of the rates' responses: beside it p^ and r^ take up its error
    for (Term& t : side)
      if (t.name == "C_Y_p" || t.name == "C_Y_r")
        t.excitation = {t.excitation.signal, true, std::numeric_limits<double>::infinity(),
                        "held: the instrumented sideslip leaves the side force's rate terms undetermined (small on a symmetric airframe)"};
  band_fit(c, "side force", a.C_Y, side);
  c.spectra.forget(&beta_model);
  bias_fit(c, "C_Y_0", &M::C_Y_0, a.C_Y, side);
  Col beta = beta_from_side_force(c, accel);
  x = signals(a, alpha, beta);
  const Col* beta_iv = accel ? &a.beta : nullptr;
  // In closed loop the rates answer the sensors' noise through the controller, as the commands do
  // (the yaw damper feeds r straight back to the rudder): in the yawing moment they and the commands
  // are instrumented by the lateral model's response to the excitation. The rolling moment keeps its
  // own: its signal is some five times larger beside the same noise, and there those instruments
  // cost more precision than they remove bias (bench seeds 1-5: C_ell_delta_a 5 -> 12 %).
  const Col p_model(a.size(), 0.0), r_model(a.size(), 0.0);  // keys: their spectra are put in the frequency domain
  const bool closed = excitation_part(c, a.delta_a) != nullptr || excitation_part(c, a.delta_r) != nullptr;
  const bool rates_iv =
      closed && put_model_instrument(c, Modelled::p_hat, p_model, why) && put_model_instrument(c, Modelled::r_hat, r_model, why);
  if (closed && !rates_iv) c.result.notes.push_back(fmt::format("yaw: the rates not instrumented: {}", why));
  const RateInstruments rates = rates_iv ? RateInstruments{&p_model, &r_model} : RateInstruments{};
  const std::vector<Term> roll =
      lateral_terms(c, "C_ell", {&M::C_ell_beta, &M::C_ell_p, &M::C_ell_r, &M::C_ell_delta_a, &M::C_ell_delta_r}, beta, x, beta_iv);
  band_fit(c, "roll", a.C_ell, roll);
  bias_fit(c, "C_ell_0", &M::C_ell_0, a.C_ell, roll);
  const std::vector<Term> yaw =
      lateral_terms(c, "C_n", {&M::C_n_beta, &M::C_n_p, &M::C_n_r, &M::C_n_delta_a, &M::C_n_delta_r}, beta, x, beta_iv, rates_iv, rates);
  band_fit(c, "yaw", a.C_n, yaw);
  bias_fit(c, "C_n_0", &M::C_n_0, a.C_n, yaw);
  c.spectra.forget(&p_model);
  c.spectra.forget(&r_model);
  return beta;
}

void consider_sideslip_scale(Context& c) {
  const CoefficientEstimate* C_Y_beta = find_estimate(c.result, "C_Y_beta");
  if (C_Y_beta == nullptr) return;
  const double relative =
      C_Y_beta->identified && C_Y_beta->estimate != 0.0 ? C_Y_beta->std_error / std::abs(C_Y_beta->estimate) : kPriorUncertainty;
  for (CoefficientEstimate& e : c.result.coefficients)
    if (e.identified && (e.name == "C_ell_beta" || e.name == "C_n_beta")) e.std_error = std::hypot(e.std_error, relative * e.estimate);
  if (C_Y_beta->identified) return;
  c.result.notes.push_back(
      fmt::format("C_ell_beta, C_n_beta: beta from the side force rests on the prior's C_Y_beta (not identified); "
                  "their bounds carry its uncertainty ({:g} of the estimate)",
                  kPriorUncertainty));
}

void consider_side_force_terms(SysidResult& r) {
  const CoefficientEstimate* C_Y_beta = find_estimate(r, "C_Y_beta");
  if (C_Y_beta == nullptr || C_Y_beta->estimate == 0.0) return;
  for (const char* suffix : {"_delta_a", "_delta_r", "_p", "_r"}) {
    const CoefficientEstimate* force = find_estimate(r, std::string("C_Y") + suffix);
    if (force == nullptr) continue;
    const double sigma = force->identified ? force->std_error : kPriorUncertainty * std::abs(force->estimate);
    if (sigma == 0.0) continue;
    std::vector<std::string> carried;
    for (const char* axis : {"C_ell", "C_n"}) {
      const CoefficientEstimate* slope = find_estimate(r, std::string(axis) + "_beta");
      CoefficientEstimate* e = find_estimate(r, axis + std::string(suffix));
      if (slope == nullptr || e == nullptr || !e->identified) continue;
      e->std_error = std::hypot(e->std_error, slope->estimate / C_Y_beta->estimate * sigma);
      if (!force->identified) carried.push_back(e->name);
    }
    if (!force->identified && !carried.empty())
      r.notes.push_back(
          fmt::format("{}: beta from the side force rests on the prior's {} (not identified); their bounds carry "
                      "its uncertainty ({:g} of it) through C_ell_beta and C_n_beta",
                      fmt::join(carried, ", "), force->name, kPriorUncertainty));
  }
}

}  // namespace tern::core::sysid
