// core/apps/sysid/identify_moments.hpp: the moments' steps of the identification (identify.hpp,
// steps 3 and 4): the pitching moment in the band, the output-error refinement of the rotational
// axes, and the gyros' roll-yaw coupling in the bounds.
#pragma once

#include "sysid/equation_error.hpp"

namespace tern::core::sysid {

/// The pitching moment in the band, alpha from the lift instrumented by the reconstruction's (step 3).
void pitching_moment(Context& c, const Col& alpha, bool accel);

/// The output-error refinement (output_error.hpp) of one group of axes: the coefficients of the
/// axes' moments the equation error identified, from their estimates; the others held.
void refine(Context& c, const RateData& d, RateAxes axes);

/// The gyros' roll-yaw coupling as a consider covariance. A yaw gyro that reads r + kappa p puts
/// kappa Jz p' into the measured yawing moment; p' is the rolling moment over Jx, so every C_n_x
/// comes out as C_n_x + kappa (Jz / Jx) C_ell_x, whatever the method: the model explains the
/// contamination with its own terms, and nothing in the moments tells the two apart (likewise
/// C_ell_x by kappa (Jx / Jz) C_n_x). The same gyros' rates are also the regressors: with p read
/// as p + kappa r, the rolling moment's C_ell_p p is fitted as C_ell_p p_read - kappa C_ell_p r, and
/// C_ell_r comes out as C_ell_r - kappa C_ell_p (C_n_r as C_n_r - kappa C_n_p); with r read as
/// r + kappa p, C_ell_p and C_n_p move by kappa C_ell_r and kappa C_n_r. With |kappa| up to
/// o.gyro_cross_axis both shifts are added to each identified coefficient's bound, in quadrature.
/// (On the bench's seed 4, flown with the realistic IMU's cross-axis sensitivity and misalignment
/// switched off, C_n_r's error went from 20 % to 5 %; on seed 3 C_ell_r's from +16.7 % to +8.2 %
/// without the cross-axis sensitivity and +4.6 % without the misalignment, where the moment's
/// share alone put 0.4 % of it in the bound and the regressors' puts 4 %.)
void consider_gyro_coupling(Context& c);

}  // namespace tern::core::sysid
