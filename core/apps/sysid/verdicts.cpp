// core/apps/sysid/verdicts.cpp: the honest verdicts of `tern sysid` (verdicts.hpp).
#include "sysid/verdicts.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string_view>

#include <fmt/format.h>

namespace tern::core::sysid {

namespace {

/// Coefficients whose sign physics fixes on every fixed wing in its linear range (Etkin and Reid,
/// *Dynamics of Flight*, 3rd ed., ch. 5; Beard and McLain ch. 4): an estimate of the other sign
/// is a fit that failed, however small its standard error. The three control derivatives' signs
/// are the sensor log's definitions of its commands (docs/sensor-log.md, actuators: the uavbook's
/// sec. 4.2): one of the other sign is a log whose surface is the other way round, as PX4's and
/// ArduPilot's normalised commands are for two axes.
struct Signed {
  const char* name;
  double sign;
  const char* why;
};
constexpr std::array<Signed, 9> kSigned{{
    {"C_L_alpha", 1.0, "lift grows with alpha below the stall"},
    {"C_D_p", 1.0, "the parasitic drag opposes the flow"},
    {"C_L_q", 1.0, "a pitch rate raises the tail's angle of attack"},
    {"C_m_q", -1.0, "pitch damping"},
    {"C_ell_p", -1.0, "roll damping"},
    {"C_n_r", -1.0, "yaw damping"},
    {"C_ell_delta_a", 1.0, "delta_a > 0 rolls right (docs/sensor-log.md: the log's aileron may be the other way round)"},
    {"C_m_delta_e", -1.0, "delta_e > 0 pitches the nose down (docs/sensor-log.md: the log's elevator may be the other way round)"},
    {"C_n_delta_r", -1.0, "delta_r > 0 yaws the nose left (docs/sensor-log.md: the log's rudder may be the other way round)"},
}};

/// An axis of the regressions: the prefix of its coefficients' names, its fits' axis names, and
/// the manoeuvre that excites it.
struct Axis {
  const char* prefix;
  const char* fit;         ///< AxisFit::axis of the trim and band fits
  const char* output_fit;  ///< AxisFit::axis of the output-error fit ("" when none)
  const char* manoeuvre;
};

constexpr std::array<Axis, 6> kAxes{{
    {"C_L_", "lift", "", "straight legs at several airspeeds, and an elevator doublet or chirp"},
    {"C_D_", "drag", "", "straight legs at several airspeeds"},
    {"C_Y_", "side force", "", "a rudder doublet"},
    {"C_ell_", "roll", "roll rate", "an aileron 3-2-1-1 or multisine"},
    {"C_m_", "pitch", "pitch rate", "an elevator doublet or chirp"},
    {"C_n_", "yaw", "yaw rate", "a rudder doublet"},
}};

const Axis* axis_of(const std::string& name) {
  for (const Axis& a : kAxes)
    if (name.rfind(a.prefix, 0) == 0) return &a;
  return nullptr;
}

/// Standard errors within which an estimate cannot be told from 0 (the two-sided 95 % bound).
constexpr double kZeroBound = 2.0;

/// A fit's generalized R^2 at or above which its axis counts as excited: the flight moved what the
/// axis models, so coefficients it leaves unadopted are not for want of a manoeuvre.
constexpr double kExcitedRSquared = 0.5;

/// The fit a coefficient came from (its axis, in its method's domain), or nullptr.
const AxisFit* fit_of(const SysidResult& r, const CoefficientEstimate& c) {
  const Axis* a = axis_of(c.name);
  if (!a) return nullptr;
  const std::string axis = c.method == "output error" ? a->output_fit : a->fit;
  for (const AxisFit& f : r.fits)
    if (f.axis == axis && f.domain == c.method) return &f;
  return nullptr;
}

/// Why `c` fails the rule, or "" when it holds.
std::string failure(const SysidResult& r, const CoefficientEstimate& c, double max_relative_error) {
  if (std::string sign = forbidden_sign(c.name, c.estimate); !sign.empty()) return sign;
  if (const AxisFit* f = fit_of(r, c); f && !(f->r_squared_generalized >= 0.0))
    return fmt::format("its {} fit ({}) explains less than the mean: R^2 {:.2f}", f->axis, f->domain, f->r_squared_generalized);
  if (!(c.std_error <= max_relative_error * std::abs(c.estimate))) {
    if (std::abs(c.estimate) <= kZeroBound * c.std_error)
      return fmt::format("indistinguishable from 0: {:.2g} +- {:.2g} (a relative bound cannot hold at 0)", c.estimate, c.std_error);
    return fmt::format("its standard error {:.2g} exceeds {:g} of the estimate {:.4g}", c.std_error, max_relative_error, c.estimate);
  }
  return "";
}

void reject_oswald(SysidResult& r, const Aircraft& prior, const std::string& why) {
  r.oswald.identified = false, r.oswald.note = why, r.oswald.estimate = prior.e, r.oswald.std_error = 0.0;
  r.aircraft.e = prior.e;
  r.notes.push_back(fmt::format("e (Oswald factor): not adopted: {}; the prior {:.3f} kept", why, prior.e));
}

/// C_D_p back at the prior: the Oswald factor from the slope fitted through it (SysidResult::
/// oswald_C_D_p_held), not the joint fit's, which leaned on the C_D_p dropped.
void hold_polar_at_prior_C_D_p(SysidResult& r, const Aircraft& prior) {
  if (!r.oswald.identified) return;
  const NuisanceEstimate held = r.oswald_C_D_p_held;
  if (!held.identified) return reject_oswald(r, prior, "with C_D_p at the prior, " + held.note);
  r.notes.push_back(
      fmt::format("e (Oswald factor): {:.3f} +- {:.2g} from the polar's slope fitted again with C_D_p at the prior "
                  "(beside the C_D_p not adopted, the joint fit's {:.3f} would move the drag at trim)",
                  held.estimate, held.std_error, r.oswald.estimate));
  r.oswald = held;
  r.aircraft.e = held.estimate;
}

void check_oswald(SysidResult& r, const Aircraft& prior, double max_relative_error, bool lift_rejected) {
  if (!r.oswald.identified) return;
  const auto drag = std::find_if(r.fits.begin(), r.fits.end(), [](const AxisFit& f) { return f.axis == "drag" && f.domain == "trim"; });
  if (lift_rejected)
    reject_oswald(r, prior, "the polar's slope rests on the lift's trim terms, which were not adopted");
  else if (drag != r.fits.end() && !(drag->r_squared_generalized >= 0.0))
    reject_oswald(r, prior, fmt::format("the drag's trim fit explains less than the mean: R^2 {:.2f}", drag->r_squared_generalized));
  else if (!(r.oswald.std_error <= max_relative_error * std::abs(r.oswald.estimate)))
    reject_oswald(r, prior,
                  fmt::format("its standard error {:.2g} exceeds {:g} of the estimate {:.3f}", r.oswald.std_error, max_relative_error,
                              r.oswald.estimate));
}

/// The best generalized R^2 of the axis's fits (trim, band, output error), or -inf without one.
double best_fit(const SysidResult& r, const Axis& a) {
  double best = -std::numeric_limits<double>::infinity();
  for (const AxisFit& f : r.fits)
    if (f.axis == a.fit || (*a.output_fit && f.axis == a.output_fit)) best = std::max(best, f.r_squared_generalized);
  return best;
}

void note_unexcited_axes(SysidResult& r) {
  for (const Axis& a : kAxes) {
    const CoefficientEstimate* first = nullptr;
    // the drag polar's slope is the drag axis's too (the Oswald factor, from the drag's trim fit)
    bool any = a.fit == std::string_view("drag") && r.oswald.identified;
    for (const auto& c : r.coefficients) {
      if (c.name.rfind(a.prefix, 0) != 0) continue;
      any = any || c.identified;
      if (!first && !c.identified) first = &c;
    }
    if (any || !first) continue;
    const double fit = best_fit(r, a);
    if (fit >= kExcitedRSquared)
      r.notes.push_back(fmt::format("{}: nothing identified ({}: {}), though the flight excited it (its fit explains R^2 {:.2f})", a.fit,
                                    first->name, first->note, fit));
    else
      r.notes.push_back(fmt::format("{}: nothing identified ({}: {}); fly {} (configs/missions/sysid.yaml flies each)", a.fit, first->name,
                                    first->note, a.manoeuvre));
  }
}

}  // namespace

std::string forbidden_sign(const std::string& name, double estimate) {
  for (const Signed& s : kSigned)
    if (name == s.name && !(s.sign * estimate > 0.0))
      return fmt::format("its sign: {:.4g}, where {} makes it {}", estimate, s.why, s.sign > 0 ? "positive" : "negative");
  return "";
}

void apply_verdicts(SysidResult& r, const Aircraft& prior, const SysidOptions& o) {
  bool lift_rejected = false, C_D_p_rejected = false;
  for (auto& c : r.coefficients) {
    if (!c.identified) continue;
    const std::string why = failure(r, c, o.max_relative_error);
    if (why.empty()) continue;
    lift_rejected = lift_rejected || (c.method == "trim" && c.name.rfind("C_L_", 0) == 0);
    C_D_p_rejected = C_D_p_rejected || c.name == "C_D_p";
    c.note = "not adopted: " + why;
    c.estimate = c.prior, c.std_error = 0.0, c.identified = false;
    r.notes.push_back(fmt::format("{}: {}; the prior {:.4g} kept", c.name, c.note, c.prior));
  }
  if (C_D_p_rejected) hold_polar_at_prior_C_D_p(r, prior);
  check_oswald(r, prior, o.max_relative_error, lift_rejected);
  note_unexcited_axes(r);
}

std::string identified_summary(const SysidResult& r) {
  const auto n = std::count_if(r.coefficients.begin(), r.coefficients.end(), [](const CoefficientEstimate& c) { return c.identified; });
  return fmt::format("identified {} of {} coefficients (the rest keep the prior, each with its reason)", n, r.coefficients.size());
}

}  // namespace tern::core::sysid
