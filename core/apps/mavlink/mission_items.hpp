// core/apps/mavlink/mission_items.hpp: MAVLink mission items <-> tern's mission (docs/ground-station.md,
// "Missions"). Pure functions, no link or host: the unit test (tests/test_mission_items.cpp) drives them.
//
// An upload (MISSION_ITEM_INT, seq 0..n-1) becomes a tern mission (tern/path/mission.hpp) in NED
// about `home`, the estimate's origin (lat/lon/alt MSL -> NED with tern::GeoOrigin, GeographicLib's
// exact local frame, as the planner converts `lla` items):
//   NAV_WAYPOINT (16)        waypoint. param1 (hold, s) must be 0 (a hold is LOITER_TIME);
//                            param2-4 (acceptance and pass radius, yaw) are not flown: the path
//                            manager's fillets and Dubins paths decide.
//   NAV_TAKEOFF (22)         waypoint at its position (x = y = 0: above home at z). The phase
//                            machine flies the takeoff and climb itself; the item is where the
//                            aircraft goes after it. param1 (pitch) and param4 (yaw) not flown.
//   NAV_LOITER_UNLIM (17)    loiter until the mission changes; param3: radius m (< 0: counter-
//   NAV_LOITER_TURNS (18)    clockwise; 0 or NaN: the path manager's turn radius), param1: turns > 0
//   NAV_LOITER_TIME (19)     or time s > 0.
//   NAV_LOITER_TO_ALT (31)   loiter until at z (within the path manager's altitude_band), then on:
//                            param2 radius as param3 above; param1 (heading required) 0 or 1: the
//                            path to the next item starts where the orbit is left and turns onto it.
//   NAV_RETURN_TO_LAUNCH (20) return_home at the altitude of the item before (tern's return_home).
//   NAV_LAND (21)            land with the touchdown point at its position (x = y = 0: home) and
//                            runway heading param4 (deg; NaN: the course from the item before);
//                            glide slope, flare and decision heights are tern's defaults (item.hpp).
//   DO_CHANGE_SPEED (178)    param1 0 (airspeed), param2 m/s > 0 (-1: no change, -2: the path
//                            manager's default): the Va_d of the nav items after it. param1 1
//                            (ground speed): their Vg_min, the least ground speed, as ArduPlane flies
//                            it (MIN_GNDSPD): the path manager raises the airspeed in a headwind.
//                            (-2: none). param3 (throttle) is not flown.
//   DO_LAND_START (189)      a marker (where a landing sequence begins, as QGroundControl's landing
//                            pattern sends it): no waypoint; MAV_CMD_DO_LAND_START flies the land item.
//   DO_SET_HOME (179)        moves home, for the items after it (as ArduPlane and PX4 fly it: home is
//                            where the aircraft returns and lands): param1 1, to where the aircraft
//                            is when the mission reaches it (the nav item before it; none: no
//                            change), param1 0, to the location it gives (frames as nav items,
//                            latitude and longitude required). After it NAV_RETURN_TO_LAUNCH is a
//                            LOITER_UNLIM over the new home, an item at x = y = 0 (takeoff, land)
//                            is at the new home, and a relative altitude is above the new home's.
//                            The frame's origin (the estimate's) does not move; nor do the failsafes'
//                            returns, which go to the origin or a rally point. param2-4 not used.
//   DO_JUMP (177)            param1: the item (seq) to go on from, param2: how many times (the jump
//                            is taken that many times, then the mission goes on past it; counts are
//                            never reset, as PX4 and ArduPilot count them). The upload is unrolled
//                            into the waypoints it flies (at most kMaxFlownWaypoints); -1 (for ever)
//                            only as the last item back to the first nav item: the mission loops.
// z NaN (QGroundControl's "above terrain" item whose terrain height it could not fetch, PX4's "the
// current altitude"): the altitude of the nav item flown before it (NAV_WAYPOINT, loiters,
// RETURN_TO_LAUNCH); not for NAV_TAKEOFF and NAV_LAND, nor for the first nav item.
// Frames: nav items GLOBAL (0) / GLOBAL_INT (5): z m MSL; GLOBAL_RELATIVE_ALT (3) /
// GLOBAL_RELATIVE_ALT_INT (6): z m above home; GLOBAL_TERRAIN_ALT (10) / _INT (11): z m above the
// terrain, flown as above home (tern has no terrain model: flat ground at home's altitude, as the
// simulator's world; the upload says so in a STATUSTEXT); x, y degE7 (in MISSION_ITEM_INT every
// global frame carries degE7). DO_CHANGE_SPEED, DO_LAND_START and DO_SET_HOME with param1 1 take
// any frame (QGroundControl sends MISSION, 2). An uploaded mission flies once (loop: false), as PX4
// and ArduPilot fly a GCS's mission, unless a final DO_JUMP for ever loops it.
//
// A download of the planner's list (msg::WaypointList, NED) gives the items back in
// GLOBAL_RELATIVE_ALT: waypoint -> NAV_WAYPOINT, loiter -> LOITER_TIME / LOITER_TURNS /
// LOITER_TO_ALT / LOITER_UNLIM, return_home -> NAV_RETURN_TO_LAUNCH, land -> NAV_LAND, and a DO_CHANGE_SPEED before
// each item whose Va_d (type 0) or Vg_min (type 1) differs from the one before (the list's loop and a waypoint's chi_d have no
// item: not listed).
//
// Errors: ItemError (a std::runtime_error) with the MAV_MISSION_RESULT for the MISSION_ACK and one
// line naming the item ("mission item 3 (NAV_LOITER_TURNS): param1 turns must be > 0, got -1").
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "mavlink/mission_messages.hpp"
#include "tern/geodesy.hpp"
#include "tern/msg/path.hpp"
#include "tern/path/mission.hpp"

namespace tern::core::mavlink {

class ItemError : public std::runtime_error {
 public:
  ItemError(std::uint8_t result, const std::string& what) : std::runtime_error(what), result_(result) {}
  std::uint8_t result() const { return result_; }  ///< MAV_MISSION_RESULT

 private:
  std::uint8_t result_;
};

/// "NAV_WAYPOINT", ..., or the number of a command tern does not take ("MAV_CMD 183").
std::string command_name(std::uint16_t command);

/// The item's frame gives z above the terrain (GLOBAL_TERRAIN_ALT, _INT).
bool terrain(std::uint8_t frame);
/// The item's frame gives z above home (GLOBAL_RELATIVE_ALT, _INT), or above the terrain, which
/// tern takes as flat at home's altitude (it has no terrain model; the simulator's ground is flat).
bool relative(std::uint8_t frame);
/// A parameter's value as the refusals print it (every digit of a float; nan, inf).
std::string item_number(double v);
/// Throws ItemError(result, "mission item <seq> (<command>): <why>").
[[noreturn]] void refuse_item(const MissionItemInt& item, std::uint8_t result, const std::string& why);
/// Checks a positioned item's frame (GLOBAL(_INT), GLOBAL_RELATIVE_ALT(_INT), GLOBAL_TERRAIN_ALT(_INT)),
/// latitude and longitude ranges. Throws ItemError.
void check_position(const MissionItemInt& item);

/// A nav item: one that becomes a waypoint (not DO_CHANGE_SPEED, DO_SET_HOME, DO_LAND_START or DO_JUMP).
bool is_nav_item(std::uint16_t command);

/// Checks one item as it arrives (command, frame, parameters, position ranges). Throws ItemError.
void check_item(const MissionItemInt& item);

/// The most waypoints an upload may unroll into through its DO_JUMPs.
inline constexpr std::size_t kMaxFlownWaypoints = 1000;

/// The tern mission of a whole upload (items in seq order, each passing check_item), NED about
/// `home`, the estimate's origin (which a DO_SET_HOME item does not move).
/// `nav_seq` (optional) receives the seq of the item each waypoint came from. Throws ItemError.
path::Mission to_mission(const std::vector<MissionItemInt>& items, const GeoOrigin& home, std::vector<std::uint16_t>* nav_seq = nullptr);

/// The items of the planner's list (NED about `home`), seq from 0; its loop has no item.
std::vector<MissionItemInt> to_items(const msg::WaypointList& list, const GeoOrigin& home);

/// The items of a NED mission (lla entries converted), seq from 0, its loops as DO_JUMP: `loops`
/// before a final land item (repeat loops - 1, back to the first nav item), a mission that loops
/// without landing a last DO_JUMP (repeat loops - 1, or -1 for ever), as to_mission reads them back.
std::vector<MissionItemInt> to_items(const path::Mission& m, const GeoOrigin& home);

/// The planner's list as a tern mission (NED, its loop and loops kept), e.g. to load it again.
path::Mission to_mission(const msg::WaypointList& list);

/// A tern waypoint file (tern/path/mission.hpp's format: loop, loops, waypoints with ned) holding
/// `m`, whose waypoints are NED; path::parse_mission_text reads it back to the same mission.
std::string mission_text(const path::Mission& m);

}  // namespace tern::core::mavlink
