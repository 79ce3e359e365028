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
/// C_ell_x by kappa (Jx / Jz) C_n_x). With |kappa| up to o.gyro_cross_axis that shift is added
/// to each identified coefficient's bound. (On the bench's seed 4, flown with the realistic IMU's
/// cross-axis sensitivity and misalignment switched off, C_n_r's error went from 20 % to 5 %.)
void consider_gyro_coupling(Context& c);

}  // namespace tern::core::sysid
