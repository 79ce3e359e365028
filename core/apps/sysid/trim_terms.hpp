// core/apps/sysid/trim_terms.hpp: what the slopes' uncertainty adds to the trim terms' bounds.
#pragma once

#include "sysid/equation_error.hpp"

namespace tern::core::sysid {

/// The trim terms C_Y_0, C_ell_0, C_m_0 and C_n_0 are the force or moment at zero flow angles,
/// rates and deflections: an extrapolation from the flight, where each regressor x_j sits near its
/// mean over the trim windows, m_j. A slope off by d_j moves the term by -d_j m_j (bias_fit takes
/// the windows' mean residual with the slopes held): bias_fit's bound (the spread of the windows'
/// means) leaves that out, and the output error's, from the rates' residuals, held it too narrowly.
/// Each identified trim term's standard error grows, in quadrature, by sum_j (s_j m_j)^2, with s_j
/// the slope's standard error, or kPriorUncertainty of its prior where the prior was kept (a
/// consider covariance, as consider_lift_terms). C_ell_0 holds besides kPriorUncertainty of the
/// mean propeller torque coefficient Q_p / (qbar S b): the torque is added back from the prior's
/// propeller (aero_samples.hpp), which sysid never identifies. Before this, bench/results' sysid
/// benches held the truth inside 3 bounds for 7 of 41 C_n_0 and 8 of 37 C_ell_0 estimates, with
/// bounds of 1-4e-5 (a rudder trim known to 0.01 deg).
/// alpha and beta: the flow angles the moments were fitted with (identify.cpp).
void consider_slopes_in_trim_terms(Context& c, const Col& alpha, const Col& beta);

}  // namespace tern::core::sysid
