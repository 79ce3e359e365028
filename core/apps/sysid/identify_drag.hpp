// core/apps/sysid/identify_drag.hpp: the drag's step of the identification (identify.hpp, step 1):
// the polar and the accelerometer's x bias from the trim windows, and the drag at the flight's trim.
#pragma once

#include "sysid/equation_error.hpp"

namespace tern::core::sysid {

/// The polar and the accelerometer's x bias from the trim (instrumentation.hpp). `at_k_plus_sigma`:
/// the samples with the pitot scale one standard error higher (nullptr when k was not identified),
/// whose shift of every estimate is added to its standard error; the lift then scales by
/// (k / (k + sigma))^2 (`C_L_scale`).
/// Needs r's trim point (trim_point) for the kept terms' consider term.
void drag(Context& c, const Col& alpha, const Aircraft& prior, const AeroSamples* at_k_plus_sigma, double C_L_scale);

/// Where the drag at trim is taken: the flight's mean alpha and elevator (r.trim_alpha, trim_delta_e).
void trim_point(SysidResult& r, const Col& alpha, const AeroSamples& a);

/// The drag coefficient at r's trim point, of the prior and of r.aircraft (call it again once the
/// verdicts have made r.aircraft the file as written: sysid_output.hpp's keep_loadable), and the
/// lift's degree of alpha in its units (r.C_D_trim_prior, C_D_trim, C_D_per_deg). Its standard error
/// C_D_trim_std_error (NaN where the polar is the prior's) adds three parts:
///  * the trim windows' bound on the polar at their mean C_Lw^2, carried to the trim's C_Lw^2 along
///    the slope's bound;
///  * in both, the pitot scale's standard error (r.trim_drag_bound.pitot_shift at the windows' mean): the
///    thrust the drag is measured against follows the airspeed (the book's Aerosonde at 23 m/s:
///    1.9 N per m/s, some 0.2 N of its 1-N drag per percent of scale; docs/system-identification.md);
///  * what the kept C_D_q, C_D_delta_e's prior uncertainty moves it by (r.trim_drag_bound.kept_terms).
void drag_at_trim(SysidResult& r, const Aircraft& prior);

}  // namespace tern::core::sysid
