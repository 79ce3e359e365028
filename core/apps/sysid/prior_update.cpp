// core/apps/sysid/prior_update.cpp: held terms moved with an identified derivative of the same surface (prior_update.hpp).
#include "sysid/prior_update.hpp"

#include <fmt/format.h>

#include "sysid/equation_error.hpp"

namespace tern::core::sysid {

ScaledPrior scaled_prior(const SysidResult& judged, const Aircraft& prior) {
  ScaledPrior s{prior, {}};
  for (const HeldPair& p : kHeldPairs) {
    const CoefficientEstimate* held = find_estimate(judged, p.held);
    const CoefficientEstimate* ref = find_estimate(judged, p.reference);
    if (held == nullptr || ref == nullptr || !ref->identified || ref->prior == 0.0) continue;
    const double ratio = ref->estimate / ref->prior;
    if (!(ratio >= kMinRatio && ratio <= kMaxRatio)) continue;
    s.prior.aero.*p.member = prior.aero.*p.member * ratio;
    s.scaled.push_back({p.held, p.reference, ratio, prior.aero.*p.member,
                        fmt::format("scaled with {} (x{:.3f}, its identified value over its prior: {}) to {:.4g}", p.reference, ratio,
                                    p.shared, s.prior.aero.*p.member)});
  }
  return s;
}

void restore_prior(SysidResult& r) {
  for (const HeldScaling& h : r.held_scaled) {
    CoefficientEstimate* e = find_estimate(r, h.held);
    if (e == nullptr) continue;
    e->prior = h.given;
    if (e->identified) continue;
    // the lines identify() and the verdicts wrote: "NAME: why; the prior X kept", X the moved value
    for (std::string& n : r.notes)
      if (const std::size_t at = n.rfind("; the prior ");
          n.rfind(e->name + ": ", 0) == 0 && at != std::string::npos && n.ends_with(" kept"))
        n = n.substr(0, at) + "; " + h.note;
    e->note += "; " + h.note;
  }
}

}  // namespace tern::core::sysid
