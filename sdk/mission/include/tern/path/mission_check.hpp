// tern/path/mission_check.hpp: where a mission's waypoints are, checked before it is flown
// (reading it, mission.hpp, checks keys, types and latitude/longitude ranges). Plain C++, no
// host types: `tern check` and `tern fly` call it on what the path planner will read.
//
// Home is the NED origin (the estimate's origin); altitudes are m above it (-down).
// Errors (the mission cannot be what was meant):
//   - a waypoint below home: NED down > 0, or an LLA altitude below the origin's altitude (not a
//     land item's touchdown point: (c) below);
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
//     fence_max_altitude, below fence_min_altitude; a land item's touchdown point: not the
//     floor, (a) below): the geofence failsafe would take over;
//   - LLA waypoints when the origin is not known (no simulator: it is the first GNSS fix):
//     they are not placed, so not checked against home or as legs.
// A land item (item.hpp: the last item; its position the touchdown point, its heading the
// runway's) is checked against the approach the path manager will fly (tern/path/landing.hpp):
// the final approach is the straight glide path down the runway heading to the touchdown point,
// entered where it meets the altitude of the item before (raised to kMinEntryHeights decision
// heights above the touchdown point when lower), its length L = entry height / tan(glide_slope).
// Warnings:
//   (a) the entry point beyond the geofence's max_distance (the touchdown point is checked as
//       any item; the glide path between them is a straight line, so no point of it is further
//       from home than its two ends). The geofence's min_altitude is a note, not a warning: the
//       landing descends through the floor by design, and the geofence failsafe disarms the floor
//       on the final approach and in the flare until the aircraft is above it again, after a
//       go-around (failsafe.hpp; PX4's geofence likewise leaves the landing out);
//   (b) no room for the turn onto the final: the entry point closer than 2 R_min to the item
//       before, or the final reversing the course from the item before to the entry point (a
//       turn of more than kMaxFinalTurn) with the item before less than 2 R_min beside the
//       final's extended centreline (a reversal onto a line needs one turn's diameter of offset:
//       with less, the path to the entry point swings out across the final; with the item on the
//       centreline, the heading may be the wrong way round). A reversal with that much offset
//       (a downwind leg, as the default mission's) is a normal circuit and draws nothing;
//   (c) a touchdown point more than kTouchdownHomeTolerance above or below home (a land item
//       is not below the ground: the runway may lie below the takeoff point). The landing
//       takes the runway to be at the altitude given; most fields are at home's;
//   (d) a final approach longer than kMaxFinalLength, or beginning less than
//       kMinApproachHeights decision heights above the touchdown point (a land item first in the
//       mission: no item before it to take the approach altitude from).
// Each problem is one line, "source:line: field: what" (source: the file, line: the entry's).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "tern/math.hpp"
#include "tern/path/mission.hpp"

namespace tern::path {

/// (b) A turn onto the final of more than this (rad, 90 deg) reverses the course from the item
/// before: the aircraft flies away from the runway to reach the entry point.
inline constexpr double kMaxFinalTurn = kPi / 2.0;
/// (c) m: the estimate's own height drift over a flight (~0.5-0.7 m, issue 46) is below it; a
/// larger touchdown altitude is a choice worth confirming.
inline constexpr double kTouchdownHomeTolerance = 1.0;
/// (d) m: the glide path assumes flat ground at the runway's altitude all the way to the entry
/// point; beyond 2 km (133 s at 15 m/s) that is rarely true, the aircraft is out of sight of a
/// safety pilot at the field, and crosswind drift has long to act. Lower the item before the
/// land item or steepen the glide slope.
inline constexpr double kMaxFinalLength = 2000.0;
/// (d) Decision heights: an approach entered lower has less than 2 decision heights of glide
/// path above the decision height (2 DH / tan(glide_slope): 274 m, ~18 s at 15 m/s with the
/// defaults) to settle after the turn onto the final before the stabilised-approach gate.
inline constexpr double kMinApproachHeights = 3.0;

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
  bool error = true;  ///< false: a warning (or a note)
  std::string text;   ///< "source:line: field: what"
  bool note = false;  ///< with error false: expected by design, said for the record (not a warning)
};

/// The problems of `m` (empty: none), in waypoint order.
std::vector<MissionProblem> check_mission(const Mission& m, const MissionLimits& limits);

}  // namespace tern::path
