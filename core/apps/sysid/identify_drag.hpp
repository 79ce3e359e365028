// core/apps/sysid/identify_drag.hpp: the drag's step of the identification (identify.hpp, step 1):
// the polar and the accelerometer's x bias from the trim windows, and the drag at the flight's trim.
#pragma once

#include "sysid/equation_error.hpp"

namespace tern::core::sysid {

/// The polar and the accelerometer's x bias from the trim (instrumentation.hpp). `at_k_plus_sigma`:
/// the samples with the pitot scale one standard error higher (nullptr when k was not identified),
/// whose shift of every estimate is added to its standard error; the lift then scales by
/// (k / (k + sigma))^2 (`C_L_scale`).
void drag(Context& c, const Col& alpha, const Aircraft& prior, const AeroSamples* at_k_plus_sigma, double C_L_scale);

/// The drag coefficient at the flight's mean alpha and elevator, of the prior and of the
/// identified model, and the lift's degree of alpha in its units (r.C_D_trim_prior, C_D_trim, C_D_per_deg).
void drag_at_trim(SysidResult& r, const Aircraft& prior, const Col& alpha, const AeroSamples& a);

}  // namespace tern::core::sysid
