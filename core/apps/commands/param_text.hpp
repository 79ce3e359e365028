// core/apps/commands/param_text.hpp: a parameter's range and description as `tern params` and
// `tern plugins` print them.
#pragma once

#include <string>

#include <tern/param.hpp>

namespace tern::core {

/// "[min, max]" (" xN" for an array of N), "a|b|c" for a text with choices, "path", or "".
std::string range_text(const ParamBase& p);
/// The description, marked " [start-only]" when it is read only when a flight starts.
std::string description_text(const ParamBase& p);

}  // namespace tern::core
