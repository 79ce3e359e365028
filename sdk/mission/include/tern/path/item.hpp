// tern/path/item.hpp: what a mission item asks the aircraft to do at its position: pass it
// (ROSplane's only kind), loiter there (for a time, turns or until an altitude), return home and loiter, or land there. Plain C++, no
// host types; msg::Waypoint carries the same fields (type, loiter_*, land_*).
#pragma once

namespace tern::path {

enum class ItemType {
  waypoint,     ///< fly to it and on (fillet, line or Dubins: path manager)
  loiter,       ///< orbit it; go on after `time` s or `turns` turns on the orbit (both 0: stay)
  return_home,  ///< orbit home (NED n = e = 0) at the item's altitude until the mission changes
  land,         ///< land with the touchdown point at the item's position (LandSpec); the last item
};

/// The orbit of a loiter or return_home item.
struct LoiterSpec {
  double radius = 0.0;  ///< m, >= 0; 0: the path manager's turn radius (R_min, or wider for turn_bank)
  int direction = 1;    ///< 1 clockwise, -1 counter-clockwise, seen from above (B&M's lambda)
  double time = 0.0;    ///< s on the orbit before going on, >= 0; 0: no time limit
  double turns = 0.0;   ///< turns on the orbit before going on, >= 0; 0: no turn limit
  /// Go on once the aircraft has reached the item's altitude on the orbit (within the path
  /// manager's `altitude_band`): MAVLink's NAV_LOITER_TO_ALT, a climb or descent in circles.
  bool to_altitude = false;
};

/// The approach and flare of a land item. The item's position is the touchdown (aim) point, NED
/// or LLA (its altitude: the runway's, usually 0 = home); its chi_d is the runway heading: the
/// course flown on the final approach and the rollout (rad, the direction the aircraft lands
/// towards). The final approach is a straight glide path down to the touchdown point along
/// that heading (PX4's and ArduPlane's straight-in approach); it begins where the glide path
/// meets the altitude of the item before the land item.
struct LandSpec {
  /// Glide-path angle below the horizon, rad, in (0, kMaxGlideSlope = 0.35]. 0.087 (5 deg): PX4's FW_LND_ANG
  /// default; small aircraft fly 3-8 deg.
  double glide_slope = 0.0873;
  /// Height above the touchdown point at which the flare begins, m, > 0 (PX4 FW_LND_FLALT's
  /// role; the flare law then takes the sink rate down to the touchdown sink rate).
  double flare_height = 4.0;
  /// Decision height above the touchdown point, m, > flare_height: below it the approach must
  /// be stabilised (cross-track, glide-path and airspeed within the phase machine's limits),
  /// else the aircraft goes around (ArduPlane's LAND_ABORT_..., PX4's abort criteria).
  double decision_height = 12.0;
};

/// The steepest glide slope a land item takes, rad (20 deg): steeper than any small fixed wing's
/// approach (3-8 deg) and past what a flare from flare_height can round out; a larger value is
/// most likely degrees given as radians.
inline constexpr double kMaxGlideSlope = 0.35;

/// The final approach begins at least this many decision heights above the touchdown point: an
/// item before the land item lower than that raises the approach (the path manager warns), else
/// there would be no stabilised glide path above the decision height.
inline constexpr double kMinEntryHeights = 2.0;

/// "waypoint", "loiter", "return_home" or "land".
inline const char* item_type_name(ItemType t) {
  switch (t) {
    case ItemType::loiter: return "loiter";
    case ItemType::return_home: return "return_home";
    case ItemType::land: return "land";
    case ItemType::waypoint: break;
  }
  return "waypoint";
}

}  // namespace tern::path
