// core/apps/sysid/identify_lateral.hpp: the lateral step of the identification (identify.hpp,
// steps 2 and 3): the side force, beta from it, the rolling and yawing moments.
#pragma once

#include "sysid/equation_error.hpp"

namespace tern::core::sysid {

/// The lateral axes (steps 2-3): the side force with beta instrumented by the lateral model's
/// sideslip (the model of c.coef as it stands: the prior's lateral coefficients), beta from the side
/// force, then the rolling and yawing moments with it (instrumented by the reconstruction's).
/// Returns that beta. (A second pass with the instrument from the first pass's coefficients, the
/// iterated instrument, moved C_Y_beta by 1-4 % on seeds 1, 2 and 4 of the bench, not toward the
/// truth on all: not taken.)
Col lateral(Context& c, const Col& alpha, bool accel);

/// beta from the side force carries C_Y_beta's scale, and every beta derivative of the moments
/// (C_ell_beta, C_n_beta) with it, which no residual shows: their bounds carry C_Y_beta's relative
/// uncertainty, in quadrature (a consider covariance). Where the side force identified C_Y_beta,
/// its standard error over its estimate: `make fly`'s flight (no manoeuvres, light turbulence)
/// identified the Anaconda's C_Y_beta 77 % large at 2.3 of its bounds, and C_n_beta and C_ell_beta
/// came out 76 % and 60 % off, at 5.5 and 3.4 of theirs. Where it did not, the prior's (x0.6 ..
/// x1.5), kPriorUncertainty of the estimate (the rule of max_relative_error then keeps their prior,
/// with the verdict's note); without it a flight without manoeuvres gave C_ell_beta 45 % and
/// C_n_beta 38 % off the truth, each outside three of its bounds.
void consider_sideslip_scale(Context& c);

/// beta from the side force also carries the side force's other terms: a C_Y_delta_r off by d
/// puts -d / C_Y_beta delta_r into beta, and the moments' fits give C_ell_delta_r (C_n_delta_r)
/// off by C_ell_beta (C_n_beta) d / C_Y_beta, correlated with the rudder as it is; no residual shows
/// it. So C_*_delta_a, C_*_delta_r, C_*_p and C_*_r carry |C_*_beta / C_Y_beta| times the
/// uncertainty of C_Y_delta_a, C_Y_delta_r, C_Y_p, C_Y_r, in quadrature (a consider covariance):
/// its standard error where identified, kPriorUncertainty of the prior where kept (0 for a term
/// held at 0). bench/book_sim.py's Aerosonde, seed 1, the x0.6 prior: C_Y_delta_r kept at 0.114
/// (truth 0.19) moved C_ell_delta_r from 0.0024 to -0.0074 at 15 of its bounds and C_n_delta_r by
/// -9 % at 4 (predicted by the formula: -0.0077 and -8 %).
void consider_side_force_terms(SysidResult& r);

}  // namespace tern::core::sysid
