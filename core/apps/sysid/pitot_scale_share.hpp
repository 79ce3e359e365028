// core/apps/sysid/pitot_scale_share.hpp: what the pitot scale's uncertainty adds to the force and
// moment coefficients' bounds.
#pragma once

#include <vector>

#include "sysid/identify.hpp"

namespace tern::core::sysid {

/// Every force and moment coefficient is measured against the dynamic pressure, k^2 qbar_pitot
/// (instrumentation.hpp), and the rate derivatives' regressors p^, q^, r^ against the airspeed, k
/// Va_pitot: a scale off by dk moves a flow-angle, control or trim term by -2 dk / k of itself and a
/// rate derivative (C_*_p, C_*_q, C_*_r) by -dk / k, all at once (a consider covariance, Klein and
/// Morelli, *Aircraft System Identification*, 2006, sec. 10.2: a sensor's scale factor carried into
/// the parameters fitted beside it). Each identified coefficient's standard error grows, in
/// quadrature, by that share at dk = the scale's standard error (`relative` = sigma_k / k, > 0:
/// estimated from the wind triangle, or stated with --pitot-scale). The drag's terms (C_D_*) carry it
/// already, through the polar fitted again at k + sigma_k (identify_drag.hpp). Before this, an
/// independent simulator's Anaconda flight (bench/book_sim.py, seed 2, the true file as the prior)
/// came back with k 1.020 +- 0.008 against 1.000 and C_ell_delta_a -5.5 % at 8 of its bounds.
void consider_pitot_scale(std::vector<CoefficientEstimate>& coefficients, double relative);

}  // namespace tern::core::sysid
