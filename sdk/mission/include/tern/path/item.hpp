// tern/path/item.hpp: what a mission item asks the aircraft to do at its position: pass it
// (ROSplane's only kind), loiter there, or return home and loiter. Plain C++, no host types;
// msg::Waypoint carries the same fields (type, loiter_*).
#pragma once

namespace tern::path {

enum class ItemType {
  waypoint,     ///< fly to it and on (fillet, line or Dubins: path manager)
  loiter,       ///< orbit it; go on after `time` s or `turns` turns on the orbit (both 0: stay)
  return_home,  ///< orbit home (NED n = e = 0) at the item's altitude until the mission changes
};

/// The orbit of a loiter or return_home item.
struct LoiterSpec {
  double radius = 0.0;  ///< m, >= 0; 0: the path manager's turn radius (R_min, or wider for turn_bank)
  int direction = 1;    ///< 1 clockwise, -1 counter-clockwise, seen from above (B&M's lambda)
  double time = 0.0;    ///< s on the orbit before going on, >= 0; 0: no time limit
  double turns = 0.0;   ///< turns on the orbit before going on, >= 0; 0: no turn limit
};

/// "waypoint", "loiter" or "return_home".
inline const char* item_type_name(ItemType t) {
  switch (t) {
    case ItemType::loiter: return "loiter";
    case ItemType::return_home: return "return_home";
    case ItemType::waypoint: break;
  }
  return "waypoint";
}

}  // namespace tern::path
