// core/apps/sysid/model_instruments.cpp: the linear model's instruments (model_instruments.hpp).
#include "sysid/model_instruments.hpp"

#include <cmath>
#include <tuple>

#include <fmt/format.h>

#include "sysid/sideslip_instrument.hpp"
#include "tern/math.hpp"

namespace tern::core::sysid {

const Col* excitation_part(const Context& c, const Col& command) {
  const AeroSamples& a = c.a;
  const std::tuple<const Col*, const Col*, double> parts[] = {{&a.delta_a, &a.exc_delta_a, 0.3 * kRadPerDeg},
                                                              {&a.delta_e, &a.exc_delta_e, 0.3 * kRadPerDeg},
                                                              {&a.delta_r, &a.exc_delta_r, 0.3 * kRadPerDeg},
                                                              {&a.delta_t, &a.exc_delta_t, 0.01}};
  for (const auto& [cmd, part, threshold] : parts)
    if (cmd == &command) return !part->empty() && rms(detrended(*part, c.L)) > threshold ? part : nullptr;
  return nullptr;
}

namespace {

/// rad: the flight-path angles tried, in this order, when the model does not trim level at a
/// stretch's airspeed: up to 10 deg of descent or climb, 2 deg apart.
constexpr double kGammaStep = 2.0 * kRadPerDeg;
constexpr int kGammaSteps = 5;

/// The linear model at airspeed Va: level if it trims there, else on the nearest flight path that
/// does (gamma_out, rad). A prior whose drag is 1.5 times the aircraft's needs more than full
/// throttle to hold the fastest stretches level; the instrument needs the model's alpha and pitch
/// response, which a few degrees of descent hardly change (lift W cos gamma), not a throttle the
/// motor has. Throws the level trim's error when none trims.
tern::aero::LinearModel linearize_near_level(const Aircraft& model, double Va, double& gamma_out) {
  tern::sim::TrimRequest r;
  r.Va = Va;
  try {
    gamma_out = 0.0;
    return tern::aero::linearize(model, r);
  } catch (const std::exception&) {  // rethrown below when no flight path trims
    for (int k = 1; k <= kGammaSteps; ++k)
      for (const double sign : {-1.0, 1.0}) {
        r.gamma = sign * k * kGammaStep;
        try {
          gamma_out = r.gamma;
          return tern::aero::linearize(model, r);
        } catch (const std::exception&) {
        }
      }
    throw;
  }
}

const char* name_of(Modelled what) {
  switch (what) {
    case Modelled::alpha: return "alpha";
    case Modelled::beta: return "beta";
    case Modelled::p_hat: return "p^";
    case Modelled::r_hat: return "r^";
  }
  return "?";
}

}  // namespace

bool put_model_instrument(Context& c, Modelled what, const Col& key, std::string& why) {
  const bool lateral = what != Modelled::alpha;
  const Col& u1 = lateral ? c.a.delta_a : c.a.delta_e;
  const Col& u2 = lateral ? c.a.delta_r : c.a.delta_t;
  const bool excited = excitation_part(c, u1) != nullptr || excitation_part(c, u2) != nullptr;
  const Col& x1 = excited ? (lateral ? c.a.exc_delta_a : c.a.exc_delta_e) : u1;
  const Col& x2 = excited ? (lateral ? c.a.exc_delta_r : c.a.exc_delta_t) : u2;
  const Eigen::VectorXcd& U1 = c.spectra.of(x1);
  const Eigen::VectorXcd& U2 = c.spectra.of(x2);
  Eigen::VectorXcd Z(U1.size());
  Aircraft model = c.result.aircraft;
  model.aero = c.coef;
  double steepest = 0.0, steepest_Va = 0.0;  // the flight path furthest from level the model trimmed on
  for (std::size_t i = 0; i < c.L.segments.size(); ++i) {
    const auto [b, e] = c.L.segments[i];
    double Va = 0.0;
    for (std::size_t k = b; k < e; ++k) Va += c.a.Va[k] / static_cast<double>(e - b);
    const auto [first, n] = c.spectra.segment_rows()[i];
    const Col f = c.spectra.segment_frequencies(i);
    try {
      double gamma = 0.0;
      const tern::aero::LinearModel m = linearize_near_level(model, Va, gamma);
      if (std::fabs(gamma) > std::fabs(steepest)) steepest = gamma, steepest_Va = Va;
      const auto u1 = U1.segment(first, n), u2 = U2.segment(first, n);
      const double half_span = 0.5 * model.b;
      switch (what) {
        case Modelled::alpha: Z.segment(first, n) = modelled_alpha(m, f, u1, u2); break;
        case Modelled::beta: Z.segment(first, n) = modelled_sideslip(m, f, u1, u2); break;
        case Modelled::p_hat: Z.segment(first, n) = half_span * modelled_roll_rate(m, f, u1, u2); break;
        case Modelled::r_hat: Z.segment(first, n) = half_span * modelled_yaw_rate(m, f, u1, u2); break;
      }
    } catch (const std::exception& ex) {
      why = fmt::format("the linear model does not trim at {:.1f} m/s ({})", Va, ex.what());
      return false;
    }
  }
  c.spectra.put(&key, std::move(Z));
  if (steepest != 0.0)
    c.result.notes.push_back(
        fmt::format("{}'s instrument: the linear model does not trim level at {:.1f} m/s with its throttle in "
                    "[0, 1]; linearised on a flight path of {:+.0f} deg there (and nearer level elsewhere)",
                    name_of(what), steepest_Va, steepest / kRadPerDeg));
  return true;
}

}  // namespace tern::core::sysid
