// core/apps/sysid/prior_update.cpp: held terms moved with an identified derivative of the same surface (prior_update.hpp).
#include "sysid/prior_update.hpp"

#include <cmath>
#include <map>

#include <fmt/format.h>

namespace tern::core::sysid {

namespace {

using M = AeroCoefficients;

double M::*member_of(const std::string& name) {
  static const std::map<std::string, double M::*> table = {{"C_L_delta_e", &M::C_L_delta_e},
                                                           {"C_L_q", &M::C_L_q},
                                                           {"C_Y_delta_a", &M::C_Y_delta_a},
                                                           {"C_n_delta_a", &M::C_n_delta_a},
                                                           {"C_ell_delta_r", &M::C_ell_delta_r}};
  const auto it = table.find(name);
  return it == table.end() ? nullptr : it->second;
}

const CoefficientEstimate* find(const SysidResult& r, const std::string& name) {
  for (const CoefficientEstimate& e : r.coefficients)
    if (e.name == name) return &e;
  return nullptr;
}

}  // namespace

ScaledPrior scaled_prior(const SysidResult& judged, const Aircraft& prior) {
  ScaledPrior s{prior, {}};
  for (const HeldPair& p : kHeldPairs) {
    const CoefficientEstimate* held = find(judged, p.held);
    const CoefficientEstimate* ref = find(judged, p.reference);
    if (held == nullptr || held->identified || ref == nullptr || !ref->identified || ref->prior == 0.0) continue;
    const double ratio = ref->estimate / ref->prior;
    if (!(ratio >= kMinRatio && ratio <= kMaxRatio)) continue;
    double M::*m = member_of(p.held);
    s.prior.aero.*m = prior.aero.*m * ratio;
    s.scaled.push_back({p.held, p.reference, ratio, prior.aero.*m,
                        fmt::format("scaled with {} (x{:.3f}, its identified value over its prior: {}) to {:.4g}", p.reference, ratio,
                                    p.shared, s.prior.aero.*m)});
  }
  return s;
}

void restore_prior(SysidResult& r) {
  for (const HeldScaling& h : r.held_scaled)
    for (CoefficientEstimate& e : r.coefficients) {
      if (e.name != h.held) continue;
      e.prior = h.given;
      if (e.identified) continue;
      // the lines identify() and the verdicts wrote: "NAME: why; the prior X kept", X the moved value
      for (std::string& n : r.notes)
        if (const std::size_t at = n.rfind("; the prior ");
            n.rfind(e.name + ": ", 0) == 0 && at != std::string::npos && n.ends_with(" kept"))
          n = n.substr(0, at) + "; " + h.note;
      e.note += "; " + h.note;
    }
}

}  // namespace tern::core::sysid
