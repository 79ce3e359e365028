// core/apps/mavlink/mission_items.cpp: MAVLink mission items <-> tern's mission (mission_items.hpp).
#include "mavlink/mission_items.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "tern/math.hpp"

namespace tern::core::mavlink {
namespace {

constexpr double kE7 = 1e7;  // degE7 per degree

std::string num(double v) { return item_number(v); }

[[noreturn]] void refuse(const MissionItemInt& it, std::uint8_t result, const std::string& why) { refuse_item(it, result, why); }

/// NED of the item's position, about the origin; x = y = 0 (no position given): above `home` (NED,
/// where DO_SET_HOME put it) at z. A relative z is above home's altitude. z NaN (the altitude of the
/// item before, to_mission fills it in): down NaN.
Eigen::Vector3d ned_of(const MissionItemInt& it, const GeoOrigin& origin, const Eigen::Vector3d& home) {
  const bool keep = std::isnan(it.z);
  const double home_alt = origin.origin().alt - home.z();
  const double alt = keep ? home_alt : relative(it.frame) ? home_alt + it.z : it.z;
  Eigen::Vector3d p(home.x(), home.y(), origin.origin().alt - alt);
  if (it.x != 0 || it.y != 0) p = origin.to_ned(it.x / kE7, it.y / kE7, alt);
  if (keep) p.z() = std::nan("");
  return p;
}

/// Loiter radius and direction from param3 (LOITER_TO_ALT: param2; < 0: counter-clockwise; NaN: 0).
path::LoiterSpec loiter_of(const MissionItemInt& it) {
  path::LoiterSpec l;
  const float radius = it.command == MAV_CMD_NAV_LOITER_TO_ALT ? it.param2 : it.param3;
  const double r = std::isfinite(radius) ? radius : 0.0;
  l.radius = std::fabs(r);
  l.direction = std::signbit(r) ? -1 : 1;
  if (it.command == MAV_CMD_NAV_LOITER_TURNS) l.turns = it.param1;
  if (it.command == MAV_CMD_NAV_LOITER_TIME) l.time = it.param1;
  l.to_altitude = it.command == MAV_CMD_NAV_LOITER_TO_ALT;
  return l;
}

path::MissionWaypoint waypoint_of(const MissionItemInt& it, const GeoOrigin& origin, const Eigen::Vector3d& home, double Va_d,
                                  double Vg_min) {
  path::MissionWaypoint w;
  w.Va_d = Va_d;
  w.Vg_min = Vg_min;
  w.field = "mission item " + std::to_string(it.seq);
  switch (it.command) {
    case MAV_CMD_NAV_LOITER_UNLIM:
    case MAV_CMD_NAV_LOITER_TURNS:
    case MAV_CMD_NAV_LOITER_TIME:
    case MAV_CMD_NAV_LOITER_TO_ALT:
      w.type = path::ItemType::loiter;
      w.loiter = loiter_of(it);
      break;
    case MAV_CMD_NAV_RETURN_TO_LAUNCH:  // at the altitude of the item before (mission.hpp)
      w.w = Eigen::Vector3d(home.x(), home.y(), std::nan(""));
      w.type = home.head<2>().isZero() ? path::ItemType::return_home : path::ItemType::loiter;  // a home moved: loiter there
      return w;
    case MAV_CMD_NAV_LAND:
      w.type = path::ItemType::land;
      w.chi_d = std::isfinite(it.param4) ? it.param4 * kRadPerDeg : std::nan("");  // NaN: from the item before
      break;
    default: break;  // NAV_WAYPOINT, NAV_TAKEOFF
  }
  w.w = ned_of(it, origin, home);
  return w;
}

/// The home a DO_SET_HOME moves to (NED about the origin): param1 1, where the aircraft is when the
/// mission reaches it (the nav item flown before it; none yet: still on the ground at home, no
/// change); param1 0, the location it gives (a relative altitude is above the current home's).
Eigen::Vector3d home_of(const MissionItemInt& it, const GeoOrigin& origin, const Eigen::Vector3d& home, const path::Mission& m) {
  if (it.param1 == 1.0f) return m.waypoints.empty() ? home : m.waypoints.back().w;
  return ned_of(it, origin, home);
}

MissionItemInt item(std::uint16_t command, std::uint8_t frame) {
  MissionItemInt it;
  it.command = command;
  it.frame = frame;
  it.autocontinue = 1;
  return it;
}

/// DO_CHANGE_SPEED of `type` (0 airspeed, 1 ground speed); speed 0: -2 (the default).
MissionItemInt speed_item(float type, double speed) {
  MissionItemInt it = item(MAV_CMD_DO_CHANGE_SPEED, MAV_FRAME_MISSION);
  it.param1 = type;
  it.param2 = speed > 0.0 ? static_cast<float>(speed) : -2.0f;
  it.param3 = -1.0f;  // throttle: no change
  return it;
}

MissionItemInt nav_item(const path::MissionWaypoint& w, const GeoOrigin& home) {
  using path::ItemType;
  const path::LoiterSpec& l = w.loiter;
  std::uint16_t command = MAV_CMD_NAV_WAYPOINT;
  if (w.type == ItemType::loiter)
    command = l.time > 0.0    ? MAV_CMD_NAV_LOITER_TIME
              : l.turns > 0.0 ? MAV_CMD_NAV_LOITER_TURNS
              : l.to_altitude ? MAV_CMD_NAV_LOITER_TO_ALT
                              : MAV_CMD_NAV_LOITER_UNLIM;
  if (w.type == ItemType::return_home) command = MAV_CMD_NAV_RETURN_TO_LAUNCH;
  if (w.type == ItemType::land) command = MAV_CMD_NAV_LAND;
  MissionItemInt it = item(command, MAV_FRAME_GLOBAL_RELATIVE_ALT);
  const GeoPoint g = home.to_geodetic(w.w);
  it.x = static_cast<std::int32_t>(std::llround(g.lat * kE7));
  it.y = static_cast<std::int32_t>(std::llround(g.lon * kE7));
  it.z = static_cast<float>(g.alt - home.origin().alt);
  if (w.type == ItemType::loiter) {
    const float radius = l.direction < 0 ? -static_cast<float>(l.radius) : static_cast<float>(l.radius);  // -0: ccw at the default
    it.param1 = static_cast<float>(l.time > 0.0 ? l.time : l.turns);
    it.param3 = radius;
    if (command == MAV_CMD_NAV_LOITER_TO_ALT) {  // param1 (heading required) 0, param2 the radius
      it.param2 = radius;
      it.param1 = it.param3 = 0.0f;
    }
  }
  if (w.type == ItemType::return_home) it.x = it.y = 0;
  if (w.type == ItemType::land) it.param4 = static_cast<float>(w.chi_d * kDegPerRad);
  return it;
}

/// DO_JUMP to item `target` (seq), `repeat` times (-1: for ever).
MissionItemInt jump_item(std::size_t target, long repeat) {
  MissionItemInt it = item(MAV_CMD_DO_JUMP, MAV_FRAME_MISSION);
  it.param1 = static_cast<float>(target);
  it.param2 = static_cast<float>(repeat);
  return it;
}

}  // namespace

bool terrain(std::uint8_t frame) { return frame == MAV_FRAME_GLOBAL_TERRAIN_ALT || frame == MAV_FRAME_GLOBAL_TERRAIN_ALT_INT; }

bool relative(std::uint8_t frame) {
  return frame == MAV_FRAME_GLOBAL_RELATIVE_ALT || frame == MAV_FRAME_GLOBAL_RELATIVE_ALT_INT || terrain(frame);
}

std::string item_number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

void refuse_item(const MissionItemInt& it, std::uint8_t result, const std::string& why) {
  throw ItemError(result, "mission item " + std::to_string(it.seq) + " (" + command_name(it.command) + "): " + why);
}

void check_position(const MissionItemInt& it) {
  if (it.frame != MAV_FRAME_GLOBAL && it.frame != MAV_FRAME_GLOBAL_INT && !relative(it.frame))
    refuse(it, MAV_MISSION_UNSUPPORTED_FRAME,
           "frame " + std::to_string(it.frame) + ": tern takes GLOBAL(_INT), GLOBAL_RELATIVE_ALT(_INT) and GLOBAL_TERRAIN_ALT(_INT)");
  if (it.x < -90 * 10'000'000 || it.x > 90 * 10'000'000) refuse(it, MAV_MISSION_INVALID_PARAM5_X, "latitude " + num(it.x / kE7) + " deg");
  if (it.y < -180 * 10'000'000 || it.y > 180 * 10'000'000)
    refuse(it, MAV_MISSION_INVALID_PARAM6_Y, "longitude " + num(it.y / kE7) + " deg");
}

bool is_nav_item(std::uint16_t c) {
  return c == MAV_CMD_NAV_WAYPOINT || c == MAV_CMD_NAV_TAKEOFF || c == MAV_CMD_NAV_LOITER_UNLIM || c == MAV_CMD_NAV_LOITER_TURNS ||
         c == MAV_CMD_NAV_LOITER_TIME || c == MAV_CMD_NAV_LOITER_TO_ALT || c == MAV_CMD_NAV_RETURN_TO_LAUNCH || c == MAV_CMD_NAV_LAND;
}

std::string command_name(std::uint16_t c) {
  switch (c) {
    case MAV_CMD_NAV_WAYPOINT: return "NAV_WAYPOINT";
    case MAV_CMD_NAV_LOITER_UNLIM: return "NAV_LOITER_UNLIM";
    case MAV_CMD_NAV_LOITER_TURNS: return "NAV_LOITER_TURNS";
    case MAV_CMD_NAV_LOITER_TIME: return "NAV_LOITER_TIME";
    case MAV_CMD_NAV_LOITER_TO_ALT: return "NAV_LOITER_TO_ALT";
    case MAV_CMD_NAV_RETURN_TO_LAUNCH: return "NAV_RETURN_TO_LAUNCH";
    case MAV_CMD_NAV_LAND: return "NAV_LAND";
    case MAV_CMD_NAV_TAKEOFF: return "NAV_TAKEOFF";
    case MAV_CMD_DO_CHANGE_SPEED: return "DO_CHANGE_SPEED";
    case MAV_CMD_DO_LAND_START: return "DO_LAND_START";
    case MAV_CMD_DO_JUMP: return "DO_JUMP";
    case MAV_CMD_DO_SET_HOME: return "DO_SET_HOME";
    case MAV_CMD_NAV_FENCE_RETURN_POINT: return "NAV_FENCE_RETURN_POINT";
    case MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION: return "NAV_FENCE_POLYGON_VERTEX_INCLUSION";
    case MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION: return "NAV_FENCE_POLYGON_VERTEX_EXCLUSION";
    case MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION: return "NAV_FENCE_CIRCLE_INCLUSION";
    case MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION: return "NAV_FENCE_CIRCLE_EXCLUSION";
    case MAV_CMD_NAV_RALLY_POINT: return "NAV_RALLY_POINT";
    default: return "MAV_CMD " + std::to_string(c);
  }
}

void check_item(const MissionItemInt& it) {
  if (it.command == MAV_CMD_DO_CHANGE_SPEED) {
    if (it.param1 != 0.0f && it.param1 != 1.0f)
      refuse(it, MAV_MISSION_INVALID_PARAM1, "speed type " + num(it.param1) + ": tern flies airspeed (0) and a least ground speed (1)");
    if (it.param2 != -1.0f && it.param2 != -2.0f && !(std::isfinite(it.param2) && it.param2 > 0.0f))
      refuse(it, MAV_MISSION_INVALID_PARAM2, "speed " + num(it.param2) + " m/s: > 0, or -1 (no change), -2 (default)");
    return;
  }
  if (it.command == MAV_CMD_DO_LAND_START) return;
  if (it.command == MAV_CMD_DO_SET_HOME) {
    if (it.param1 != 0.0f && it.param1 != 1.0f)
      refuse(it, MAV_MISSION_INVALID_PARAM1, "use current " + num(it.param1) + ": 1 (where the aircraft is) or 0 (the location given)");
    if (it.param1 == 1.0f) return;
    check_position(it);
    if (it.x == 0 && it.y == 0) refuse(it, MAV_MISSION_INVALID_PARAM5_X, "the location given (param1 0) has no latitude and longitude");
    if (!std::isfinite(it.z)) refuse(it, MAV_MISSION_INVALID_PARAM7, "altitude " + num(it.z) + ": not a number");
    return;
  }
  if (it.command == MAV_CMD_DO_JUMP) {
    if (!(it.param1 >= 0.0f && it.param1 < 65536.0f && std::floor(it.param1) == it.param1))
      refuse(it, MAV_MISSION_INVALID_PARAM1, "jump to " + num(it.param1) + ": an item's seq (a whole number >= 0)");
    if (!(it.param2 >= -1.0f && it.param2 < 65536.0f && std::floor(it.param2) == it.param2))
      refuse(it, MAV_MISSION_INVALID_PARAM2, "repeat " + num(it.param2) + ": a whole number >= 0, or -1 (for ever)");
    return;
  }
  if (!is_nav_item(it.command)) refuse(it, MAV_MISSION_UNSUPPORTED, "not a mission item tern flies (docs/ground-station.md)");
  check_position(it);
  const bool keeps_altitude = it.command != MAV_CMD_NAV_TAKEOFF && it.command != MAV_CMD_NAV_LAND;  // NaN: the item before's
  if (!std::isfinite(it.z) && it.command != MAV_CMD_NAV_RETURN_TO_LAUNCH && !(std::isnan(it.z) && keeps_altitude))
    refuse(it, MAV_MISSION_INVALID_PARAM7, "altitude " + num(it.z) + ": not a number");
  if (it.command == MAV_CMD_NAV_LOITER_TO_ALT && it.param1 != 0.0f && it.param1 != 1.0f)  // MAV_BOOL
    refuse(it, MAV_MISSION_INVALID_PARAM1, "heading required " + num(it.param1) + ": 0 or 1");
  if (it.command == MAV_CMD_NAV_LOITER_TO_ALT && std::isinf(it.param2))
    refuse(it, MAV_MISSION_INVALID_PARAM2, "radius " + num(it.param2) + " m");
  if (it.command == MAV_CMD_NAV_WAYPOINT && std::isfinite(it.param1) && it.param1 != 0.0f)
    refuse(it, MAV_MISSION_INVALID_PARAM1, "hold " + num(it.param1) + " s: tern does not hold at a waypoint (use NAV_LOITER_TIME)");
  if ((it.command == MAV_CMD_NAV_LOITER_TURNS || it.command == MAV_CMD_NAV_LOITER_TIME) && !(std::isfinite(it.param1) && it.param1 > 0.0f))
    refuse(it, MAV_MISSION_INVALID_PARAM1,
           std::string(it.command == MAV_CMD_NAV_LOITER_TURNS ? "turns" : "time") + " must be > 0, got " + num(it.param1));
  if (it.command >= MAV_CMD_NAV_LOITER_UNLIM && it.command <= MAV_CMD_NAV_LOITER_TIME && std::isinf(it.param3))
    refuse(it, MAV_MISSION_INVALID_PARAM3, "radius " + num(it.param3) + " m");
  if (it.command == MAV_CMD_NAV_LAND && std::isinf(it.param4)) refuse(it, MAV_MISSION_INVALID_PARAM4, "heading " + num(it.param4) + " deg");
}

namespace {

/// Where a DO_JUMP at `i` sends the mission: its target's index, after checking that it exists; a
/// repeat of -1 is only taken as the last item back to the first nav item (then `loop`).
std::size_t jump_target(const std::vector<MissionItemInt>& items, std::size_t i, bool& loop) {
  const MissionItemInt& it = items[i];
  const auto target = static_cast<std::size_t>(it.param1);
  if (target >= items.size())
    refuse(it, MAV_MISSION_INVALID_PARAM1, "jump to item " + num(it.param1) + ": the mission has " + std::to_string(items.size()));
  if (it.param2 == -1.0f) {
    std::size_t first_nav = 0;
    while (first_nav < items.size() && !is_nav_item(items[first_nav].command)) ++first_nav;
    if (i + 1 != items.size() || target > first_nav)
      refuse(it, MAV_MISSION_INVALID_PARAM2,
             "repeat -1 (for ever): tern loops a whole mission only (a DO_JUMP as the last item, back to the first nav item)");
    loop = true;
  }
  return target;
}

/// The speeds DO_CHANGE_SPEED items set for the nav items after them.
struct Speeds {
  double Va_d = 0.0;    ///< type 0, airspeed (0: the path manager's default)
  double Vg_min = 0.0;  ///< type 1, least ground speed (0: none)
  void apply(const MissionItemInt& it) {
    double& v = it.param1 == 1.0f ? Vg_min : Va_d;
    if (it.param2 > 0.0f) v = it.param2;
    if (it.param2 == -2.0f) v = 0.0;
  }
};

/// What a nav item takes from the item flown before it: a land item without a heading the course
/// from it, a return_home or an item of altitude NaN its altitude. Throws ItemError when there is none.
void take_from_before(path::MissionWaypoint& w, const MissionItemInt& it, const path::Mission& m) {
  const bool none = m.waypoints.empty();
  if (w.type == path::ItemType::land && std::isnan(w.chi_d)) {
    if (none || m.waypoints.back().type == path::ItemType::return_home)
      refuse(it, MAV_MISSION_INVALID_PARAM4, "no heading (param4 NaN) and no position before it to take the course from");
    const Eigen::Vector3d d = w.w - m.waypoints.back().w;
    if (std::hypot(d.x(), d.y()) < 1.0) refuse(it, MAV_MISSION_INVALID_PARAM4, "no heading (param4 NaN) and the item before is above it");
    w.chi_d = std::atan2(d.y(), d.x());
  }
  if (!std::isnan(w.w.z())) return;
  if (none) refuse(it, MAV_MISSION_INVALID_PARAM7, "the first nav item: no altitude (NaN) and no item before it to keep the altitude of");
  w.w.z() = m.waypoints.back().w.z();
}

}  // namespace

path::Mission to_mission(const std::vector<MissionItemInt>& items, const GeoOrigin& origin, std::vector<std::uint16_t>* nav_seq) {
  path::Mission m;
  Eigen::Vector3d home = Eigen::Vector3d::Zero();  // NED about the origin; DO_SET_HOME moves it
  m.loop = false;
  m.source = "MAVLink upload";
  Speeds speeds;
  for (const MissionItemInt& it : items) check_item(it);
  std::vector<long> jumps_left(items.size(), 0);
  for (std::size_t i = 0; i < items.size(); ++i)
    if (items[i].command == MAV_CMD_DO_JUMP) jumps_left[i] = static_cast<long>(items[i].param2);
  // the items in the order they fly, each jump taken as often as it says (bounded: every step either
  // adds a waypoint, of which there are at most kMaxFlownWaypoints, or uses up a jump or an item)
  std::size_t steps = 0;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const MissionItemInt& it = items[i];
    if (++steps > 64 * (kMaxFlownWaypoints + items.size()))
      refuse(it, MAV_MISSION_NO_SPACE, "its DO_JUMPs go round more than the mission can hold");
    if (it.command == MAV_CMD_DO_JUMP) {
      const std::size_t target = jump_target(items, i, m.loop);
      if (m.loop || jumps_left[i] == 0) continue;
      --jumps_left[i];
      i = target - 1;  // the loop's ++i lands on the target (unsigned: 0 - 1 + 1 is 0)
      continue;
    }
    if (it.command == MAV_CMD_DO_CHANGE_SPEED) speeds.apply(it);
    if (it.command == MAV_CMD_DO_SET_HOME) home = home_of(it, origin, home, m);
    if (!is_nav_item(it.command)) continue;  // DO_CHANGE_SPEED, DO_SET_HOME; DO_LAND_START: a marker
    path::MissionWaypoint w = waypoint_of(it, origin, home, speeds.Va_d, speeds.Vg_min);
    take_from_before(w, it, m);
    if (m.waypoints.size() == kMaxFlownWaypoints)
      refuse(it, MAV_MISSION_NO_SPACE, "its DO_JUMPs unroll the mission past " + std::to_string(kMaxFlownWaypoints) + " waypoints");
    m.waypoints.push_back(w);
    if (nav_seq) nav_seq->push_back(it.seq);
  }
  return m;
}

std::vector<MissionItemInt> to_items(const path::Mission& m, const GeoOrigin& home) {
  std::vector<MissionItemInt> out;
  double Va_d = 0.0, Vg_min = 0.0;
  std::optional<std::size_t> first_nav;
  const auto& wps = m.waypoints;
  const bool lands = !wps.empty() && wps.back().type == path::ItemType::land;
  for (std::size_t i = 0; i < wps.size(); ++i) {
    const path::MissionWaypoint& w = wps[i];
    if (lands && i + 1 == wps.size() && m.loop && m.loops > 1 && first_nav) out.push_back(jump_item(*first_nav, m.loops - 1));
    if (w.Va_d != Va_d) out.push_back(speed_item(0.0f, w.Va_d));
    if (w.Vg_min != Vg_min) out.push_back(speed_item(1.0f, w.Vg_min));
    Va_d = w.Va_d;
    Vg_min = w.Vg_min;
    if (!first_nav) first_nav = out.size();
    out.push_back(nav_item(w, home));
  }
  if (!lands && m.loop && first_nav) out.push_back(jump_item(*first_nav, m.loops > 0 ? m.loops - 1 : -1));
  for (std::size_t k = 0; k < out.size(); ++k) out[k].seq = static_cast<std::uint16_t>(k);
  return out;
}

std::vector<MissionItemInt> to_items(const msg::WaypointList& list, const GeoOrigin& home) {
  path::Mission m = to_mission(list);
  m.loop = false;  // the list's loop has no item (a GCS's upload flies once)
  return to_items(m, home);
}

path::Mission to_mission(const msg::WaypointList& list) {
  path::Mission m;
  m.loop = list.loop;
  m.loops = static_cast<int>(list.loops);
  m.source = "the planner's list";
  for (std::uint32_t i = 0; i < list.count && i < list.items.size(); ++i) {
    const msg::Waypoint& w = list.items[i];
    path::MissionWaypoint out;
    out.w = w.w;
    out.chi_d = w.chi_d;
    out.use_chi = w.use_chi;
    out.Va_d = w.Va_d;
    out.Vg_min = w.Vg_min;
    out.type = static_cast<path::ItemType>(std::min<std::uint8_t>(w.type, msg::Waypoint::land));  // the same order
    out.loiter = {w.loiter_radius, w.loiter_direction, w.loiter_time, w.loiter_turns, w.loiter_to_altitude};
    out.land = {w.land_glide_slope, w.land_flare_height, w.land_decision_height};
    m.waypoints.push_back(out);
  }
  return m;
}

std::string mission_text(const path::Mission& m) {
  std::string t = std::string("loop: ") + (m.loop ? "true" : "false") + "\n";
  if (m.loops > 0) t += "loops: " + std::to_string(m.loops) + "\n";
  t += "waypoints:\n";
  for (const path::MissionWaypoint& w : m.waypoints) {
    t += "  - {type: " + std::string(path::item_type_name(w.type));
    if (w.type == path::ItemType::return_home)
      t += ", altitude: " + num(-w.w.z());
    else
      t += ", ned: [" + num(w.w.x()) + ", " + num(w.w.y()) + ", " + num(w.w.z()) + "]";
    if (w.Va_d > 0.0) t += ", Va_d: " + num(w.Va_d);
    if (w.Vg_min > 0.0) t += ", Vg_min: " + num(w.Vg_min);
    if (w.type == path::ItemType::loiter || w.type == path::ItemType::return_home) {
      t += ", radius: " + num(w.loiter.radius) + ", direction: " + (w.loiter.direction < 0 ? "ccw" : "cw");
      if (w.loiter.time > 0.0) t += ", time: " + num(w.loiter.time);
      if (w.loiter.turns > 0.0) t += ", turns: " + num(w.loiter.turns);
      if (w.loiter.to_altitude) t += ", to_altitude: true";
    }
    if (w.type == path::ItemType::waypoint && w.use_chi) t += ", chi_d: " + num(w.chi_d) + ", use_chi: true";
    if (w.type == path::ItemType::land)
      t += ", heading: " + num(w.chi_d) + ", glide_slope: " + num(w.land.glide_slope) + ", flare_height: " + num(w.land.flare_height) +
           ", decision_height: " + num(w.land.decision_height);
    t += "}\n";
  }
  return t;
}

}  // namespace tern::core::mavlink
