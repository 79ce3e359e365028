// core/apps/sysid/identify_moments.hpp: the moments' steps of the identification (identify.hpp,
// steps 3 and 4): the pitching moment in the band, the output-error refinement of the rotational
// axes, and the gyros' roll-yaw coupling in the bounds.
#pragma once

#include <array>

#include "sysid/equation_error.hpp"

namespace tern::core::sysid {

/// The pitching moment in the band, alpha from the lift instrumented by the reconstruction's (step 3).
void pitching_moment(Context& c, const Col& alpha, bool accel);

/// The moments' dominant derivatives (each axis's stiffness, damping and control power; Klein and
/// Morelli sec. 9.1), which the output error tries again when the band left them undetermined
/// (retried_by_output_error). The cross derivatives stay where the band left them: retried as well
/// on 20 logs (tern's own and its foreign rewrites, bench/foreign_log.py), they took C_n_r and
/// C_n_beta 2-6 % of the truth nearer it on most, but C_ell_delta_r (prior 0.0014) came out -0.010
/// to -0.013 against +0.0024, the yaw rate's fit (tern validate) went 5 % worse on two logs of
/// three, and refitted without C_ell_delta_r the gains went with it.
inline constexpr std::array<const char*, 9> kDominant = {"C_m_alpha",     "C_m_q",    "C_m_delta_e", "C_ell_beta", "C_ell_p",
                                                         "C_ell_delta_a", "C_n_beta", "C_n_r",       "C_n_delta_r"};

/// Whether the band left e, a dominant derivative, undetermined by its bound alone (excited, not
/// collinear; its note kPoorlyDetermined): refine then frees it in the output error, on the whole
/// record's simulated rates, from the prior. In calm air (bench/book_sim.py --turbulence none) the
/// yaw band's pieces disagreed on C_n_r by 55 % of it and the prior, 40 % off, was kept; retried,
/// C_n_r came out within 1 %.
bool retried_by_output_error(const CoefficientEstimate& e);

/// Whether the output error determines a retried term: its bound se within max_relative_error of
/// the estimate theta and of the size its prior expects (|prior|, as least_determined measures a
/// band's terms: an estimate thrown far from any value looks well determined against itself; with
/// the cross derivatives retried, C_ell_delta_r, prior 0.0014, passed against itself at -0.010 to
/// -0.013 +- 0.004, the truth +0.0024 outside 3 bounds on two logs of ten).
bool retry_determined(double max_relative_error, const CoefficientEstimate& e, double theta, double se);

/// The output-error refinement (output_error.hpp) of one group of axes: the coefficients of the
/// axes' moments the equation error identified, from their estimates, and the dominant ones it left
/// poorly determined (retried_by_output_error), from the prior: those the output error determines
/// (retry_determined) are adopted; the others go back to the prior and the rest are fitted again
/// without them. The others held.
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
