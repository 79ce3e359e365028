// core/apps/sysid/model_instruments.hpp: the band's instruments made by the linear model
// (sideslip_instrument.hpp) for the identification's steps (identify.hpp), and the excitation's
// part of a command in a closed-loop flight.
#pragma once

#include <string>

#include "sysid/equation_error.hpp"

namespace tern::core::sysid {

/// What a model instrument stands for (sideslip_instrument.hpp): a flow angle, or a nondimensional
/// lateral rate.
enum class Modelled { alpha, beta, p_hat, r_hat };

/// The excitation's part of `command` (one of c.a's delta_*) where the log has one that moved
/// about its trim by more than the excitation test's 0.3 deg (throttle: 0.01); else nullptr. In a
/// closed-loop flight the controller's share of a command answers the gusts, which are the
/// regressions' error: only the excitation's share is independent of them (Soderstrom and Stoica,
/// *System Identification*, ch. 10: systems operating in closed loop).
const Col* excitation_part(const Context& c, const Col& command);

/// The instrument for alpha (the lift's), beta (the side force's) or p^ and r^ (the rolling and
/// yawing moments'), put into the spectra under `key` (sideslip_instrument.hpp): each stretch's
/// response of the linear model to its commands (elevator and throttle, or aileron and rudder),
/// linearised at the stretch's mean airspeed with the coefficients known so far. The model is
/// driven by the excitation's part of the commands where the log has it (excitation_part), by the
/// whole commands otherwise. False (no instrument) when that model does not trim, with the reason
/// in `why`.
bool put_model_instrument(Context& c, Modelled what, const Col& key, std::string& why);

}  // namespace tern::core::sysid
