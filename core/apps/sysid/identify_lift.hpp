// core/apps/sysid/identify_lift.hpp: the lift's step of the identification (identify.hpp, steps
// 1 and 2): C_L_0 and C_L_alpha from the trim, C_L_q and C_L_delta_e from the band, alpha from
// the accelerometers' lift, and what the lift's kept terms add to the pitching moment's bounds.
#pragma once

#include "sysid/equation_error.hpp"

namespace tern::core::sysid {

/// Lift. The pitch-rate and elevator terms in the band, beside the reconstructed alpha instrumented
/// by the longitudinal model's; C_L_0 and C_L_alpha from the trim windows' means by instrumental
/// variables (lift_trim_fit), with those terms. The band's own fit is the check: if alpha explains
/// less than kMinLiftBandFit of the lift in the band, or the band's C_L_alpha disagrees with the
/// trim's (beyond 3 of its standard errors and 5 %), the band's terms are not taken.
void lift(Context& c, const Excitation& alpha, const Excitation& q, const Excitation& delta_e);

/// alpha where the accelerometers' lift says it was (identify.hpp, step 2). The lift is the body
/// force turned through alpha itself: the estimator's first, then twice the lift's own.
Col alpha_from_lift(const Context& c);

/// The lift's alpha carries the lift's pitch-rate and elevator terms: alpha = (C_L - C_L_0 - C_L_q q^
/// - C_L_delta_e delta_e) / C_L_alpha, so the pitching moment's fit takes C_m_q as b + (C_m_alpha /
/// C_L_alpha) C_L_q and C_m_delta_e likewise. Where those lift terms kept their prior, the prior's
/// uncertainty (kPriorUncertainty) is added to C_m_q's and C_m_delta_e's bounds (a consider
/// covariance). That alpha carries C_L_alpha's scale, and C_m_alpha with it: C_m_alpha's bound
/// carries C_L_alpha's relative uncertainty (its standard error over its estimate, or
/// kPriorUncertainty where it kept its prior). `make fly`'s flight (the Anaconda without
/// manoeuvres, the true prior) kept C_L_alpha's prior and gave C_m_alpha -1.75 +- 0.025 against
/// the truth's -2.74.
void consider_lift_terms(Context& c);

}  // namespace tern::core::sysid
