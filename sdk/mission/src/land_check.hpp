// A mission's land item checked against the approach the path manager will fly. See
// tern/path/mission_check.hpp, (a) to (d).
#pragma once

#include <optional>
#include <vector>

#include "tern/path/mission_check.hpp"

namespace tern::path {

/// The NED positions (m, from home) of m's items, none for an LLA item without a known origin.
using PlacedItems = std::vector<std::optional<Eigen::Vector3d>>;

/// Appends the problems of m's final land item (none without one, or when it is not placed).
void check_land(const Mission& m, const PlacedItems& pos, const MissionLimits& limits, std::vector<MissionProblem>& out);

}  // namespace tern::path
