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

}  // namespace tern::core::sysid
