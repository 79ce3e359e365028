// core/apps/sysid/identify.cpp: the equation-error identification (identify.hpp).
#include "sysid/identify.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "sysid/equation_error.hpp"
#include "sysid/identify_drag.hpp"
#include "sysid/identify_lateral.hpp"
#include "sysid/identify_lift.hpp"
#include "sysid/identify_moments.hpp"
#include "sysid/instrumentation.hpp"
#include "sysid/pitot_scale_share.hpp"
#include "sysid/trim_terms.hpp"
#include "tern/aero/model.hpp"

namespace tern::core::sysid {

namespace {
/// The true airspeed over the pitot's beyond which (or below whose inverse) the scale is not a
/// calibration but a unit: a pitot-static probe reads within some 10-20 % of the true airspeed
/// (position error, a blocked or misaligned port); a pressure in hPa gives 10.
constexpr double kMaxPlausiblePitotScale = 1.5;

/// Each axis's measured and predicted coefficient over the longest stretch.
std::vector<AxisSeries> axis_series(const AeroSamples& a, const Layout& L, const AeroCoefficients& m, const Aircraft& ac, const Col& alpha,
                                    const Col& beta) {
  std::pair<std::size_t, std::size_t> longest = L.segments.front();
  for (const auto& s : L.segments)
    if (s.second - s.first > longest.second - longest.first) longest = s;
  std::vector<AxisSeries> out;
  for (const char* axis : {"C_L", "C_D", "C_Y", "C_ell", "C_m", "C_n"}) out.push_back({axis, {}, {}, {}});
  for (std::size_t k = longest.first; k < longest.second; ++k) {
    const double al = alpha[k], be = beta[k], ph = a.p_hat[k], qh = a.q_hat[k], rh = a.r_hat[k];
    const double da = a.delta_a[k], de = a.delta_e[k], dr = a.delta_r[k];
    const double predicted[6] = {
        m.C_L_0 + m.C_L_alpha * al + m.C_L_q * qh + m.C_L_delta_e * de,
        sim::drag_coefficient(ac, al) + m.C_D_q * qh + m.C_D_delta_e * de,
        m.C_Y_0 + m.C_Y_beta * be + m.C_Y_p * ph + m.C_Y_r * rh + m.C_Y_delta_a * da + m.C_Y_delta_r * dr,
        m.C_ell_0 + m.C_ell_beta * be + m.C_ell_p * ph + m.C_ell_r * rh + m.C_ell_delta_a * da + m.C_ell_delta_r * dr,
        m.C_m_0 + m.C_m_alpha * al + m.C_m_q * qh + m.C_m_delta_e * de,
        m.C_n_0 + m.C_n_beta * be + m.C_n_p * ph + m.C_n_r * rh + m.C_n_delta_a * da + m.C_n_delta_r * dr};
    const double measured[6] = {a.C_L[k], a.C_D[k], a.C_Y[k], a.C_ell[k], a.C_m[k], a.C_n[k]};
    for (std::size_t i = 0; i < 6; ++i) {
      out[i].t.push_back(a.t[k]);
      out[i].measured.push_back(measured[i]);
      out[i].predicted.push_back(predicted[i]);
    }
  }
  return out;
}

}  // namespace

SysidResult identify(const FlightSeries& series, const Aircraft& prior, const SysidOptions& o) {
  if (aero_samples(series, prior, o.airborne).size() < 2)
    throw std::runtime_error(
        fmt::format("no airborne samples (airborne: {}; then Va above {:g} of its median, |alpha|, |beta| below {:g} rad)",
                    airborne_mask(series, o.airborne.ground).rule, o.airborne.min_Va_ratio, o.airborne.max_flow_angle));
  const std::vector<std::size_t> rows = aero_samples(series, prior, o.airborne).source;
  const AirspeedScale scale = std::isnan(o.pitot_scale)
                                  ? airspeed_scale(series, rows, prior.rho, o.max_correlation)
                                  : stated_airspeed_scale(series, rows, prior.rho, o.pitot_scale, o.pitot_scale_std_error);
  const double k = scale.k.estimate;  // 1 where the wind triangle could not tell it
  const AeroSamples a = aero_samples(series, prior, o.airborne, k);
  const Layout L = layout_of(a, o.trim_window_s, o.min_segment_s);
  if (L.segments.empty())
    throw std::runtime_error(
        fmt::format("no airborne stretch of {} s or more (the longest flight without a gap is shorter)", o.min_segment_s));
  {
    const Signals x = signals(a, a.alpha, a.beta);
    auto moved = [&](const Excitation& e) { return rms(detrended(*e.signal, L)) > e.threshold; };
    if (!moved(x.delta_a) && !moved(x.delta_e) && !moved(x.delta_r))
      throw std::runtime_error(
          "no excitation: aileron, elevator and rudder never moved more than 0.3 deg about their trim (fly configs/missions/sysid.yaml, "
          "docs/system-identification.md)");
  }
  SysidResult r;
  r.notes = series.notes;
  r.aircraft = prior;
  r.pitot_scale = scale.k;
  r.wind_n = scale.w_n, r.wind_e = scale.w_e;
  if (!scale.k.identified && std::isnan(o.pitot_scale))
    r.notes.push_back(fmt::format("pitot scale: not identifiable: {}; 1 taken", scale.k.note));
  if (scale.k.identified && (k > kMaxPlausiblePitotScale || k < 1.0 / kMaxPlausiblePitotScale))
    r.notes.push_back(
        fmt::format("pitot scale {:.3g} (the true airspeed over the pitot's): no pitot is that far off, they read within "
                    "some 10-20 %; the pressure logged is {:.3g} of what it should be: hPa or mbar logged as Pa? "
                    "(docs/sensor-log.md, diff_pressure)",
                    k, 1.0 / (k * k)));
  r.samples = a.size(), r.segments = L.segments.size();
  for (const auto& [b, e] : L.segments) r.airborne_s += a.t[e - 1] - a.t[b];
  AeroCoefficients coef = prior.aero;
  Context c{a, L, o, Spectra(a, L, o.band_lo_hz, o.band_hi_hz), coef, prior.aero, r};
  const Signals x0 = signals(a, a.alpha, a.beta);
  lift(c, x0.alpha, x0.q, x0.delta_e);
  const bool accel = o.flow_angles == FlowAngles::accelerometer;
  const Col alpha = accel ? alpha_from_lift(c) : a.alpha;
  trim_point(r, alpha, a);        // the drag's consider terms are taken there
  if (scale.k.std_error > 0.0) {  // estimated, or stated with its bound
    const double k_hi = k + scale.k.std_error;
    const AeroSamples a_hi = aero_samples(series, prior, o.airborne, k_hi);
    drag(c, alpha, prior, &a_hi, (k / k_hi) * (k / k_hi));
  } else {
    drag(c, alpha, prior, nullptr, 1.0);
  }
  pitching_moment(c, alpha, accel);
  const Col beta = lateral(c, alpha, accel);
  for (auto& e : r.coefficients) e.equation_error = e.estimate, e.equation_error_std_error = e.std_error;
  if (o.output_error.enabled) {
    RateData d = rate_data(a, alpha, beta, L.segments, prior, o.output_error.window_s);
    if (accel) {  // the flow angles from the forces carry the commands' force terms (beta_from_side_force, alpha_from_lift)
      d.beta_per_delta_a = -coef.C_Y_delta_a / coef.C_Y_beta, d.beta_per_delta_r = -coef.C_Y_delta_r / coef.C_Y_beta;
      d.alpha_per_delta_e = -coef.C_L_delta_e / coef.C_L_alpha;
    }
    refine(c, d, RateAxes::pitch);
    refine(c, d, RateAxes::lateral);
  }
  if (accel) consider_lift_terms(c), consider_sideslip_scale(c), consider_side_force_terms(r);
  consider_gyro_coupling(c);
  consider_slopes_in_trim_terms(c, alpha, beta);
  consider_pitot_scale(r.coefficients, scale.k.std_error / k);  // 0 without a pitot scale's bound
  r.aircraft.aero = coef;
  drag_at_trim(r, prior);
  r.series = axis_series(a, L, coef, r.aircraft, alpha, beta);
  for (const auto& e : r.coefficients)
    if (!e.identified) r.notes.push_back(fmt::format("{}: not identifiable: {}; the prior {:.4g} kept", e.name, e.note, e.prior));
  return r;
}

}  // namespace tern::core::sysid
