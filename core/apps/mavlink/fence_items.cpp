// core/apps/mavlink/fence_items.cpp: FENCE and RALLY items <-> zones and rally points (fence_items.hpp).
#include "mavlink/fence_items.hpp"

#include <cmath>
#include <string>

namespace tern::core::mavlink {
namespace {

constexpr double kE7 = 1e7;                   // degE7 per degree
constexpr std::uint16_t kMaxVertices = 1000;  // a polygon's vertex count (the longest upload: MissionProtocol::kMaxItems)

bool is_polygon(std::uint16_t c) {
  return c == MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION || c == MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION;
}
bool is_inclusion(std::uint16_t c) { return c == MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION || c == MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION; }

bool whole(float v, double lo, double hi) { return v >= lo && v <= hi && std::floor(v) == v; }

/// (n, e) of the item's x, y about home (the altitude is not the fence's).
Eigen::Vector2d ne_of(const MissionItemInt& it, const GeoOrigin& home) {
  return home.to_ned(it.x / kE7, it.y / kE7, home.origin().alt).head<2>();
}

MissionItemInt located(std::uint16_t command, std::uint8_t type, const GeoOrigin& home, const Eigen::Vector3d& ned) {
  MissionItemInt it;
  it.command = command;
  it.frame = MAV_FRAME_GLOBAL_RELATIVE_ALT;
  it.autocontinue = 1;
  it.mission_type = type;
  const GeoPoint g = home.to_geodetic(ned);
  it.x = static_cast<std::int32_t>(std::llround(g.lat * kE7));
  it.y = static_cast<std::int32_t>(std::llround(g.lon * kE7));
  it.z = static_cast<float>(g.alt - home.origin().alt);
  return it;
}

}  // namespace

void check_fence_item(const MissionItemInt& it) {
  if (it.command == MAV_CMD_NAV_FENCE_RETURN_POINT)
    refuse_item(it, MAV_MISSION_UNSUPPORTED, "tern returns to the nearest rally point or home: upload a RALLY point instead");
  if (it.command < MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION || it.command > MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION)
    refuse_item(it, MAV_MISSION_UNSUPPORTED, "not a geofence item (NAV_FENCE_POLYGON_VERTEX_*, NAV_FENCE_CIRCLE_*)");
  check_position(it);
  if (is_polygon(it.command) && !whole(it.param1, 3, kMaxVertices))
    refuse_item(it, MAV_MISSION_INVALID_PARAM1, "vertex count " + item_number(it.param1) + ": a whole number, 3 to 1000");
  if (!is_polygon(it.command) && !(std::isfinite(it.param1) && it.param1 > 0.0f))
    refuse_item(it, MAV_MISSION_INVALID_PARAM1, "radius " + item_number(it.param1) + " m: > 0");
  if (is_inclusion(it.command) && !whole(it.param2, 0, 65535))
    refuse_item(it, MAV_MISSION_INVALID_PARAM2, "inclusion group " + item_number(it.param2) + ": a whole number >= 0");
}

void check_rally_item(const MissionItemInt& it) {
  if (it.command != MAV_CMD_NAV_RALLY_POINT) refuse_item(it, MAV_MISSION_UNSUPPORTED, "not a rally point (NAV_RALLY_POINT)");
  check_position(it);
  if (!std::isfinite(it.z)) refuse_item(it, MAV_MISSION_INVALID_PARAM7, "altitude " + item_number(it.z) + ": not a number");
}

std::vector<FenceZone> to_zones(const std::vector<MissionItemInt>& items, const GeoOrigin& home) {
  std::vector<FenceZone> zones;
  for (std::size_t i = 0; i < items.size();) {
    const MissionItemInt& first = items[i];
    FenceZone z;
    z.inclusion = is_inclusion(first.command);
    z.group = z.inclusion ? static_cast<std::uint32_t>(first.param2) : 0;
    if (!is_polygon(first.command)) {
      z.centre = ne_of(first, home);
      z.radius = first.param1;
      zones.push_back(z);
      ++i;
      continue;
    }
    const auto n = static_cast<std::size_t>(first.param1);
    for (std::size_t k = 0; k < n; ++k, ++i) {
      if (i >= items.size() || items[i].command != first.command || items[i].param1 != first.param1 ||
          (z.inclusion && items[i].param2 != first.param2))
        refuse_item(i < items.size() ? items[i] : first, MAV_MISSION_INVALID,
                    "the polygon begun at item " + std::to_string(first.seq) + " has " + std::to_string(n) + " vertices; item " +
                        std::to_string(i) + (i < items.size() ? " is not one of them" : " is missing"));
      z.polygon.push_back(ne_of(items[i], home));
    }
    zones.push_back(z);
  }
  if (!items.empty() && !inside_zones(zones, Eigen::Vector2d::Zero()))
    refuse_item(items.front(), MAV_MISSION_DENIED, "the fence leaves home outside: the return inside would leave it");
  return zones;
}

std::vector<Eigen::Vector3d> to_rally(const std::vector<MissionItemInt>& items, const GeoOrigin& home) {
  std::vector<Eigen::Vector3d> rally;
  for (const MissionItemInt& it : items) {
    const double alt = relative(it.frame) ? home.origin().alt + it.z : it.z;
    const Eigen::Vector3d ned = home.to_ned(it.x / kE7, it.y / kE7, alt);
    if (-ned.z() < 0.0)
      refuse_item(it, MAV_MISSION_INVALID_PARAM7, "altitude " + item_number(-ned.z()) + " m above home: a rally point is not below home");
    rally.emplace_back(ned.x(), ned.y(), -ned.z());
  }
  return rally;
}

std::vector<MissionItemInt> fence_items(const std::vector<FenceZone>& zones, const GeoOrigin& home) {
  std::vector<MissionItemInt> items;
  for (const FenceZone& z : zones) {
    if (z.polygon.empty()) {
      MissionItemInt it = located(z.inclusion ? MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION : MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION,
                                  MAV_MISSION_TYPE_FENCE, home, {z.centre.x(), z.centre.y(), 0.0});
      it.param1 = static_cast<float>(z.radius);
      it.param2 = z.inclusion ? static_cast<float>(z.group) : 0.0f;
      items.push_back(it);
      continue;
    }
    for (const Eigen::Vector2d& v : z.polygon) {
      MissionItemInt it = located(z.inclusion ? MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION : MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION,
                                  MAV_MISSION_TYPE_FENCE, home, {v.x(), v.y(), 0.0});
      it.param1 = static_cast<float>(z.polygon.size());
      it.param2 = z.inclusion ? static_cast<float>(z.group) : 0.0f;
      items.push_back(it);
    }
  }
  for (std::size_t i = 0; i < items.size(); ++i) items[i].seq = static_cast<std::uint16_t>(i);
  return items;
}

std::vector<MissionItemInt> rally_items(const std::vector<Eigen::Vector3d>& rally, const GeoOrigin& home) {
  std::vector<MissionItemInt> items;
  for (const Eigen::Vector3d& p : rally) {
    items.push_back(located(MAV_CMD_NAV_RALLY_POINT, MAV_MISSION_TYPE_RALLY, home, {p.x(), p.y(), -p.z()}));
    items.back().seq = static_cast<std::uint16_t>(items.size() - 1);
  }
  return items;
}

}  // namespace tern::core::mavlink
