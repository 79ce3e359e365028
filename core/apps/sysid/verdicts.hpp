// core/apps/sysid/verdicts.hpp: the honest verdicts of `tern sysid` (issue 76, item 5;
// docs/system-identification.md, step 7): what the identification adopts, checked once more at the
// end against the documented rule, whichever step produced it.
//  * A coefficient whose own regression explains less than the mean (R^2 < 0 on its axis and
//    domain: lift, drag, side force, roll, pitch, yaw; trim, band or output error), or whose
//    standard error exceeds `max_relative_error` of its estimate (at the default 0.5: an estimate
//    within two standard errors of 0, said "indistinguishable from 0"), or whose sign physics forbids
//    (C_L_alpha, C_L_q, C_D_p > 0; C_m_q, C_ell_p, C_n_r < 0 on every fixed wing), keeps the prior, with
//    one note.
//  * The Oswald factor likewise (the drag's trim fit, its own bound), and it falls with the lift's
//    trim terms, on whose C_L the polar's slope rests. Where C_D_p is not adopted, the Oswald factor
//    is the slope's fitted again with C_D_p at the prior (SysidResult::oswald_C_D_p_held): the
//    joint fit's slope beside the prior's C_D_p would move the drag at trim by the C_D_p dropped.
//  * An axis the log left without any identified coefficient (for the drag, the Oswald factor
//    counts) says so once, with the first reason, and, unless one of its fits explains R^2 >= 0.5
//    of the data (the flight excited it), the manoeuvre that excites it
//    (configs/missions/sysid.yaml flies each).
// The estimates the later steps computed from a rejected one are not redone: the note says which
// coefficients the file keeps from the prior, and sysid.json keeps every figure.
#pragma once

#include <string>

#include "sysid/identify.hpp"

namespace tern::core::sysid {

/// Applies the rule (header) to `r` in place: coefficients and the Oswald factor back to the prior
/// with their notes (r.aircraft.e too; its coefficients follow from r.coefficients when
/// keep_loadable, sysid_output.hpp, builds the file), one note per rejection and per unexcited axis.
void apply_verdicts(SysidResult& r, const Aircraft& prior, const SysidOptions& o);

/// Why physics forbids `estimate` for coefficient `name` on a fixed wing in its linear range (its
/// sign: C_L_alpha, C_L_q and C_D_p positive; C_m_q, C_ell_p and C_n_r negative; by the sensor
/// log's definitions of its commands C_ell_delta_a positive, C_m_delta_e and C_n_delta_r negative;
/// zero included), or "" when it does not (every other coefficient, any sign).
std::string forbidden_sign(const std::string& name, double estimate);

/// "identified N of M coefficients" (M: every coefficient the result reports).
std::string identified_summary(const SysidResult& r);

}  // namespace tern::core::sysid
