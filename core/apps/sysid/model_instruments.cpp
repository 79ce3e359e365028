// core/apps/sysid/model_instruments.cpp: the linear model's instruments (model_instruments.hpp).
#include "sysid/model_instruments.hpp"

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
  for (std::size_t i = 0; i < c.L.segments.size(); ++i) {
    const auto [b, e] = c.L.segments[i];
    double Va = 0.0;
    for (std::size_t k = b; k < e; ++k) Va += c.a.Va[k] / static_cast<double>(e - b);
    const auto [first, n] = c.spectra.segment_rows()[i];
    const Col f = c.spectra.segment_frequencies(i);
    try {
      const tern::aero::LinearModel m = tern::aero::linearize(model, {Va});
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
  return true;
}

}  // namespace tern::core::sysid
