// core/apps/mavlink/fence_items.hpp: MAVLink's FENCE and RALLY mission items <-> tern's geofence
// zones and rally points (config/failsafe_config.hpp; docs/ground-station.md, "Geofence and rally
// points"). Pure functions, no link or host: tests/test_fence_items.cpp drives them.
//
// Source: https://mavlink.io/en/services/geofence.html and .../mission.html#rally_points;
// common.xml (de1e078a) MAV_CMD 5001-5004 and 5100. Positions are degE7 in MISSION_ITEM_INT, in
// any global frame (GLOBAL(_INT), GLOBAL_RELATIVE_ALT(_INT)); NED about `home`, the estimate's
// origin, through tern::GeoOrigin.
//   NAV_FENCE_POLYGON_VERTEX_INCLUSION (5001)  a vertex; param1 the polygon's vertex count (>= 3,
//   NAV_FENCE_POLYGON_VERTEX_EXCLUSION (5002)  the same for its consecutive vertices), param2
//                                               (inclusion) its group. z is not used.
//   NAV_FENCE_CIRCLE_INCLUSION (5003)          a circle about x, y; param1 radius m > 0, param2
//   NAV_FENCE_CIRCLE_EXCLUSION (5004)          (inclusion) its group. z is not used.
//   NAV_RALLY_POINT (5100)                     a return destination at x, y, z (z above home in a
//                                               relative frame, else MSL; >= 0 above home).
// Refused (ItemError naming the item): NAV_FENCE_RETURN_POINT (5000; tern returns to the nearest
// rally point or home, as common.xml advises when rally points are supported), a polygon whose
// vertices disagree on the count or group or stop short, a fence that leaves home outside (a
// return inside would leave it, as the config's check says), non-finite values.
// Downloads give the same items back, in GLOBAL_RELATIVE_ALT (z 0 for fence items).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "config/failsafe_config.hpp"
#include "mavlink/mission_items.hpp"
#include "mavlink/mission_messages.hpp"
#include "tern/geodesy.hpp"

namespace tern::core::mavlink {

/// Checks one FENCE item as it arrives (command, frame, parameters, position). Throws ItemError.
void check_fence_item(const MissionItemInt& item);
/// Checks one RALLY item as it arrives. Throws ItemError.
void check_rally_item(const MissionItemInt& item);

/// The zones of a whole FENCE upload (items in seq order, each passing check_fence_item), about
/// `home`. Throws ItemError (a polygon cut short, home outside).
std::vector<FenceZone> to_zones(const std::vector<MissionItemInt>& items, const GeoOrigin& home);
/// The rally points (n, e, altitude above home; m) of a whole RALLY upload, about `home`.
std::vector<Eigen::Vector3d> to_rally(const std::vector<MissionItemInt>& items, const GeoOrigin& home);

/// The FENCE items of `zones` (NED about `home`), seq from 0, mission_type FENCE.
std::vector<MissionItemInt> fence_items(const std::vector<FenceZone>& zones, const GeoOrigin& home);
/// The RALLY items of `rally`, seq from 0, mission_type RALLY.
std::vector<MissionItemInt> rally_items(const std::vector<Eigen::Vector3d>& rally, const GeoOrigin& home);

}  // namespace tern::core::mavlink
