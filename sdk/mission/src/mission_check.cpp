// Where a mission's waypoints are. See tern/path/mission_check.hpp.
#include "tern/path/mission_check.hpp"

#include <algorithm>
#include <cmath>

#include "entry_text.hpp"
#include "land_check.hpp"
#include "number_text.hpp"

namespace tern::path {

namespace {

std::string m1(double v) { return number_text(v, 1); }
std::string g(double v) { return number_text(v); }

bool more_than_3_decimals(double x) {
  const double k = x * 1000.0;
  return std::fabs(k - std::round(k)) > 1e-6 * std::max(1.0, std::fabs(k));
}

bool looks_like_lat_lon(const MissionWaypoint& wp) {
  const double n = wp.w.x(), e = wp.w.y();
  return !wp.lla && wp.type != ItemType::return_home && std::fabs(n) <= 90.0 && std::fabs(e) <= 180.0 &&
         (more_than_3_decimals(n) || more_than_3_decimals(e));
}

/// The entry's NED position relative to home; none for an LLA entry without a known origin.
std::optional<Eigen::Vector3d> placed(const MissionWaypoint& wp, const MissionLimits& l) {
  if (!wp.lla) return wp.w;
  if (!l.origin) return std::nullopt;
  return lla_to_ned(wp.w, *l.origin);
}

void check_ground_and_distance(const std::string& where, const MissionWaypoint& wp, const Eigen::Vector3d& p, const MissionLimits& l,
                               std::vector<MissionProblem>& out) {
  const double h = -p.z();
  if (h < 0.0 && wp.type != ItemType::land) {  // a runway may lie below home: land_check.cpp (c)
    if (wp.lla)
      out.push_back({true, where + "altitude " + g(wp.w.z()) + " m MSL is " + m1(-h) + " m below home (" + g(l.origin->alt) +
                               " m MSL): below the ground"});
    else
      out.push_back({true, where + "down = " + g(p.z()) + " m: " + m1(p.z()) +
                               " m below home, below the ground (NED: 70 m above home is down = -70)"});
  }
  const double d = p.norm();
  if (d > l.max_distance)
    out.push_back({true, where + m1(d) + " m from home, further than " + l.max_distance_name + " = " + g(l.max_distance) + " m"});
}

void check_fence(const std::string& where, const MissionWaypoint& wp, const Eigen::Vector3d& p, const MissionLimits& l,
                 std::vector<MissionProblem>& out) {
  const double h = -p.z(), r = std::hypot(p.x(), p.y());
  const std::string then = ": the geofence failsafe would take over";
  if (l.fence_max_distance && r > *l.fence_max_distance)
    out.push_back({false, where + m1(r) + " m from home, beyond the geofence's max_distance " + g(*l.fence_max_distance) + " m" + then});
  if (l.fence_max_altitude && h > *l.fence_max_altitude)
    out.push_back({false, where + "altitude " + m1(h) + " m, above the geofence's max_altitude " + g(*l.fence_max_altitude) + " m" + then});
  if (l.fence_min_altitude && h < *l.fence_min_altitude && h >= 0.0 && wp.type != ItemType::land)  // the landing's: land_check.cpp (a)
    out.push_back({false, where + "altitude " + m1(h) + " m, below the geofence's min_altitude " + g(*l.fence_min_altitude) + " m" + then});
}

/// The leg from `a` to `b` (both plain waypoints).
void check_leg(const Mission& m, const MissionWaypoint& a, const Eigen::Vector3d& pa, const MissionWaypoint& b, const Eigen::Vector3d& pb,
               const MissionLimits& l, std::vector<MissionProblem>& out) {
  const double d = std::hypot(pb.x() - pa.x(), pb.y() - pa.y());
  const std::string from = a.field.empty() ? "the previous waypoint" : a.field;
  if (d < l.min_separation)
    out.push_back({false, entry_prefix(m, b) + "repeats " + from + " (" + m1(d) + " m apart): the path manager skips it"});
  else if (l.R_min && d < *l.R_min)
    out.push_back({true, entry_prefix(m, b) + "the leg from " + from + " is " + m1(d) + " m, shorter than the minimum turn radius " +
                             l.R_min_name + " = " + g(*l.R_min) + " m: no room to turn"});
}

void check_legs(const Mission& m, const PlacedItems& pos, const MissionLimits& l, std::vector<MissionProblem>& out) {
  const auto& w = m.waypoints;
  bool all_plain = true;
  for (std::size_t i = 0; i < w.size(); ++i) {
    all_plain = all_plain && w[i].type == ItemType::waypoint;
    if (i == 0 || w[i].type != ItemType::waypoint || w[i - 1].type != ItemType::waypoint || !pos[i] || !pos[i - 1]) continue;
    check_leg(m, w[i - 1], *pos[i - 1], w[i], *pos[i], l, out);
  }
  const std::size_t n = w.size();
  if (m.loop && all_plain && n >= 3 && pos[n - 1] && pos[0]) check_leg(m, w[n - 1], *pos[n - 1], w[0], *pos[0], l, out);
}

}  // namespace

std::vector<MissionProblem> check_mission(const Mission& m, const MissionLimits& l) {
  std::vector<MissionProblem> out;
  PlacedItems pos;
  std::size_t unplaced = 0;
  for (const auto& wp : m.waypoints) {
    const std::string where = entry_prefix(m, wp);
    if (looks_like_lat_lon(wp))
      out.push_back({false, where + "[" + g(wp.w.x()) + ", " + g(wp.w.y()) + ", " + g(wp.w.z()) +
                                "] is NED (m) but looks like latitude, longitude, altitude: lla: true forgotten?"});
    pos.push_back(placed(wp, l));
    if (!pos.back()) {
      ++unplaced;
      continue;
    }
    check_ground_and_distance(where, wp, *pos.back(), l, out);
    check_fence(where, wp, *pos.back(), l, out);
  }
  check_legs(m, pos, l, out);
  check_land(m, pos, l, out);
  if (unplaced > 0)
    out.push_back({false, m.source + ": " + std::to_string(unplaced) +
                              " latitude/longitude waypoint(s) not checked against home: the origin is not known before the first "
                              "GNSS fix (no simulator origin)"});
  return out;
}

}  // namespace tern::path
