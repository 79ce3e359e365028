// tern/path/mission_check.hpp: where a mission's waypoints are, checked before it is flown
// (reading it, mission.hpp, checks keys, types and latitude/longitude ranges). Plain C++, no
// host types: `tern check` and `tern fly` call it on what the path planner will read.
//
// Home is the NED origin (the estimate's origin); altitudes are m above it (-down).
// Errors (the mission cannot be what was meant):
//   - a waypoint below home: NED down > 0, or an LLA altitude below the origin's altitude;
//   - a waypoint further than `max_distance` from home (3-D): a latitude/longitude read as
//     metres (the `lla` flag forgotten) or a missing minus sign puts it kilometres away;
//   - a leg between two consecutive plain waypoints (and the closing leg of a looped mission of
//     plain waypoints) shorter than `R_min`, the path manager's minimum turn radius: no room for
//     the fillet or Dubins turn at its end (legs shorter than `min_separation` are repeats the
//     path manager skips: a warning).
// Warnings (legal, but suspicious):
//   - a NED waypoint whose north and east look like a latitude and a longitude (within
//     [-90, 90] and [-180, 180] with more than three decimals): `lla: true` forgotten?;
//   - a waypoint outside the geofence (beyond fence_max_distance horizontally, above
//     fence_max_altitude, below fence_min_altitude): the geofence failsafe would take over;
//   - LLA waypoints when the origin is not known (no simulator: it is the first GNSS fix):
//     they are not placed, so not checked against home or as legs.
// Each problem is one line, "source:line: field: what" (source: the file, line: the entry's).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "tern/path/mission.hpp"

namespace tern::path {

struct MissionLimits {
  double max_distance = 5000.0;                    ///< m from home, 3-D (> 0)
  std::string max_distance_name = "max_distance";  ///< the setting's name, for messages
  std::optional<double> R_min;                     ///< m, the minimum turn radius; none: legs are not checked
  std::string R_min_name = "R_min";
  double min_separation = 1.0;                                   ///< m: closer consecutive waypoints are repeats (horizontal)
  std::optional<GeoPoint> origin;                                ///< home as latitude/longitude/altitude; none: LLA not placed
  std::optional<double> fence_max_distance;                      ///< m, horizontal from home
  std::optional<double> fence_min_altitude, fence_max_altitude;  ///< m above home
};

struct MissionProblem {
  bool error = true;  ///< false: a warning
  std::string text;   ///< "source:line: field: what"
};

/// The problems of `m` (empty: none), in waypoint order.
std::vector<MissionProblem> check_mission(const Mission& m, const MissionLimits& limits);

}  // namespace tern::path
