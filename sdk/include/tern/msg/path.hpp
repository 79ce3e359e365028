// tern/msg/path.hpp: waypoints (topic `waypoints`) and the current path (topic `current_path`).
// Mirrors ROSplane's Waypoint and CurrentPath messages.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include <Eigen/Core>

#include "tern/time.hpp"

namespace tern::msg {

/// One mission item (ROSplane's Waypoint, plus a type: tern's loiter and return_home items).
///   waypoint      fly to w (ROSplane's meaning of every entry)
///   loiter        orbit w: radius loiter_radius, direction loiter_direction; leave after
///                 loiter_time s or loiter_turns turns on the orbit, whichever comes first
///                 (both 0: loiter until the mission changes); with loiter_to_altitude,
///                 also once the aircraft is at w's altitude (MAVLink NAV_LOITER_TO_ALT)
///   return_home   orbit home (the origin, n = e = 0) at altitude -w.z(), radius and direction
///                 as a loiter, until the mission changes; w's n and e are ignored
///   land          land: w is the touchdown point, chi_d the runway heading (tern/path/item.hpp
///                 LandSpec: glide slope, flare and decision heights)
/// ROSplane's message has no type: the DDS bridge sends every item as a plain waypoint.
struct Waypoint {
  static constexpr std::string_view type_name = "tern/Waypoint";
  enum Type : std::uint8_t { waypoint = 0, loiter = 1, return_home = 2, land = 3 };
  Eigen::Vector3d w = Eigen::Vector3d::Zero();  ///< NED position (m) relative to the origin, or (lat deg, lon deg, alt m MSL) when lla
  bool lla = false;                             ///< w is latitude, longitude, altitude
  double chi_d = 0.0;                           ///< desired course at the waypoint, rad (used when use_chi)
  bool use_chi = false;                         ///< fly a Dubins path honouring chi_d, else a fillet
  double Va_d = 0.0;                            ///< desired airspeed, m/s
  double Vg_min = 0.0;                          ///< least ground speed, m/s (0: none): raises the airspeed in a headwind
  std::uint8_t type = waypoint;                 ///< Type: waypoint (0), loiter (1), return_home (2), land (3)
  double loiter_radius = 0.0;                   ///< orbit radius, m, >= 0 (0: the path manager's turn radius)
  std::int8_t loiter_direction = 1;             ///< 1 clockwise, -1 counter-clockwise (seen from above)
  double loiter_time = 0.0;                     ///< loiter: s on the orbit before going on, >= 0 (0: no limit)
  double loiter_turns = 0.0;                    ///< loiter: turns on the orbit before going on, >= 0 (0: no limit)
  bool loiter_to_altitude = false;              ///< loiter: go on once at w's altitude (path manager's altitude_band)
  double land_glide_slope = 0.0873;             ///< land: glide-path angle, rad, (0, 0.35]
  double land_flare_height = 4.0;               ///< land: flare begins this high above the touchdown point, m, > 0
  double land_decision_height = 12.0;           ///< land: stabilised-approach check below this height, m, > flare height
  template <class V>
  static constexpr void describe(V& v) {
    v(&Waypoint::w, "w", "m|deg", "0,1,2");
    v(&Waypoint::lla, "lla", "bool");
    v(&Waypoint::chi_d, "chi_d", "rad");
    v(&Waypoint::use_chi, "use_chi", "bool");
    v(&Waypoint::Va_d, "Va_d", "m/s");
    v(&Waypoint::type, "type", "enum");
    v(&Waypoint::loiter_radius, "loiter_radius", "m");
    v(&Waypoint::loiter_direction, "loiter_direction", "");
    v(&Waypoint::loiter_time, "loiter_time", "s");
    v(&Waypoint::loiter_turns, "loiter_turns", "");
    v(&Waypoint::land_glide_slope, "land_glide_slope", "rad");
    v(&Waypoint::land_flare_height, "land_flare_height", "m");
    v(&Waypoint::land_decision_height, "land_decision_height", "m");
    v(&Waypoint::Vg_min, "Vg_min", "m/s");
    v(&Waypoint::loiter_to_altitude, "loiter_to_altitude", "bool");
  }
};

/// The whole mission as the planner hands it to the path manager, topic `waypoints`.
/// Positions are NED (lla waypoints are converted by the planner once the origin is known).
struct WaypointList {
  static constexpr std::string_view type_name = "tern/WaypointList";
  static constexpr std::size_t kCapacity = 64;
  Nanos stamp = 0;
  std::uint32_t revision = 0;  ///< increases on every edit of the mission
  std::uint32_t count = 0;     ///< valid entries in items, <= kCapacity
  bool loop = true;            ///< after the last waypoint, start again at the first
  /// With loop: fly the items (before a final land item) this many times, then the land item
  /// (none: orbit the last); 0: loop until the mission changes (a final land item never comes).
  std::uint32_t loops = 0;
  /// The path manager flies this list from now on (a failsafe, or a mission edit with
  /// set_current), instead of at its next waypoint decision.
  bool immediate = false;
  std::array<Waypoint, kCapacity> items{};
  template <class V>
  static constexpr void describe(V& v) {
    v(&WaypointList::stamp, "stamp", "ns");
    v(&WaypointList::revision, "revision", "");
    v(&WaypointList::count, "count", "");
    v(&WaypointList::loop, "loop", "bool");
    v(&WaypointList::loops, "loops", "");
    v(&WaypointList::immediate, "immediate", "bool");
    v(&WaypointList::items, "items", "");
  }
};

/// The path segment to follow now, topic `current_path` (ROSplane's CurrentPath).
struct CurrentPath {
  static constexpr std::string_view type_name = "tern/CurrentPath";
  enum Type : std::uint8_t { orbit = 0, line = 1 };
  Nanos stamp = 0;
  std::uint8_t path_type = line;                 ///< orbit (0) or line (1)
  double Va_d = 0.0;                             ///< desired airspeed, m/s
  Eigen::Vector3d r = Eigen::Vector3d::Zero();   ///< a point on the line, NED, m
  Eigen::Vector3d q = Eigen::Vector3d::UnitX();  ///< unit direction of the line, NED
  Eigen::Vector3d c = Eigen::Vector3d::Zero();   ///< orbit centre, NED, m
  double rho = 0.0;                              ///< orbit radius, m
  std::int8_t lambda = 1;                        ///< orbit direction: 1 clockwise, -1 counter-clockwise
  std::int32_t waypoint_index = -1;              ///< index of the waypoint being flown to, -1 if none
  /// The line is a land item's final approach: r is the glide path's aim point (on the ground, in
  /// the estimate's frame: the item's touchdown point moved back along the runway by the flare's
  /// float, tern/path/landing.hpp aim_offset), q points down the glide path along the runway heading.
  bool landing = false;
  double flare_height = 0.0;     ///< landing: flare begins this high above r, m
  double decision_height = 0.0;  ///< landing: stabilised-approach check below this height above r, m
  std::uint8_t attempt = 0;      ///< landing: approaches flown so far including this one (1: the first)
  template <class V>
  static constexpr void describe(V& v) {
    v(&CurrentPath::stamp, "stamp", "ns");
    v(&CurrentPath::path_type, "path_type", "enum");
    v(&CurrentPath::Va_d, "Va_d", "m/s");
    v(&CurrentPath::r, "r", "m", "n,e,d");
    v(&CurrentPath::q, "q", "", "n,e,d");
    v(&CurrentPath::c, "c", "m", "n,e,d");
    v(&CurrentPath::rho, "rho", "m");
    v(&CurrentPath::lambda, "lambda", "");
    v(&CurrentPath::waypoint_index, "waypoint_index", "");
    v(&CurrentPath::landing, "landing", "bool");
    v(&CurrentPath::flare_height, "flare_height", "m");
    v(&CurrentPath::decision_height, "decision_height", "m");
    v(&CurrentPath::attempt, "attempt", "");
  }
};

}  // namespace tern::msg
