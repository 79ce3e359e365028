// FENCE and RALLY items <-> geofence zones and rally points (core/apps/mavlink/fence_items.hpp).
#include <doctest/doctest.h>

#include <cmath>

#include "mavlink/fence_items.hpp"

using namespace tern::core;
using namespace tern::core::mavlink;
using tern::GeoOrigin;
using tern::GeoPoint;

namespace {

const GeoPoint kHome{47.3977, 8.5456, 488.0};  // m MSL

MissionItemInt at(std::uint16_t seq, std::uint16_t command, double north, double east, float p1, float p2 = 0.0f) {
  const GeoPoint g = GeoOrigin(kHome).to_geodetic(Eigen::Vector3d(north, east, 0.0));
  MissionItemInt it;
  it.seq = seq;
  it.command = command;
  it.frame = MAV_FRAME_GLOBAL_INT;  // as QGroundControl writes fence items
  it.mission_type = MAV_MISSION_TYPE_FENCE;
  it.x = static_cast<std::int32_t>(std::llround(g.lat * 1e7));
  it.y = static_cast<std::int32_t>(std::llround(g.lon * 1e7));
  it.param1 = p1;
  it.param2 = p2;
  return it;
}

std::uint8_t refusal(const std::vector<MissionItemInt>& items) {
  try {
    for (const auto& it : items) check_fence_item(it);
    to_zones(items, GeoOrigin(kHome));
  } catch (const ItemError& e) {
    return e.result();
  }
  return MAV_MISSION_ACCEPTED;
}

}  // namespace

TEST_CASE("a FENCE upload: an inclusion polygon, an exclusion circle; back to the same items") {
  const auto V = MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION;
  std::vector<MissionItemInt> items{at(0, V, 500, -500, 4), at(1, V, 500, 500, 4), at(2, V, -500, 500, 4), at(3, V, -500, -500, 4),
                                    at(4, MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION, 200, 200, 50)};
  for (const auto& it : items) check_fence_item(it);
  const auto zones = to_zones(items, GeoOrigin(kHome));
  REQUIRE(zones.size() == 2);
  CHECK(zones[0].inclusion);
  REQUIRE(zones[0].polygon.size() == 4);
  CHECK(zones[0].polygon[1].x() == doctest::Approx(500.0).epsilon(1e-4));
  CHECK(zones[0].polygon[1].y() == doctest::Approx(500.0).epsilon(1e-4));
  CHECK_FALSE(zones[1].inclusion);
  CHECK(zones[1].radius == 50.0);
  CHECK(inside_zones(zones, {0, 0}));
  CHECK_FALSE(inside_zones(zones, {210, 190}));  // in the hole
  CHECK_FALSE(inside_zones(zones, {600, 0}));    // out of the polygon
  const auto back = fence_items(zones, GeoOrigin(kHome));
  REQUIRE(back.size() == items.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    CHECK(back[i].seq == i);
    CHECK(back[i].command == items[i].command);
    CHECK(back[i].mission_type == MAV_MISSION_TYPE_FENCE);
    CHECK(std::abs(back[i].x - items[i].x) <= 1);
    CHECK(std::abs(back[i].y - items[i].y) <= 1);
    CHECK(back[i].param1 == items[i].param1);
  }
}

TEST_CASE("FENCE refusals: a polygon cut short or mixed, a return point, home outside, bad parameters") {
  const auto V = MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION;
  CHECK(refusal({at(0, V, 500, -500, 4), at(1, V, 500, 500, 4), at(2, V, -500, 500, 4)}) == MAV_MISSION_INVALID);     // 3 of 4
  CHECK(refusal({at(0, V, 500, -500, 3), at(1, V, 500, 500, 3), at(2, V, -500, 500, 3, 1)}) == MAV_MISSION_INVALID);  // two groups
  CHECK(refusal({at(0, V, 500, -500, 2), at(1, V, 500, 500, 2)}) == MAV_MISSION_INVALID_PARAM1);
  CHECK(refusal({at(0, V, 1000, 1000, 3), at(1, V, 1000, 1100, 3), at(2, V, 1100, 1100, 3)}) == MAV_MISSION_DENIED);  // home outside
  CHECK(refusal({at(0, MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, 0, 0, std::nanf(""))}) == MAV_MISSION_INVALID_PARAM1);
  CHECK(refusal({at(0, MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, 0, 0, 300, 0.5f)}) == MAV_MISSION_INVALID_PARAM2);
  CHECK(refusal({at(0, MAV_CMD_NAV_FENCE_RETURN_POINT, 0, 0, 0)}) == MAV_MISSION_UNSUPPORTED);
  CHECK(refusal({at(0, MAV_CMD_NAV_WAYPOINT, 0, 0, 0)}) == MAV_MISSION_UNSUPPORTED);
  MissionItemInt odd_frame = at(0, MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, 0, 0, 300);
  odd_frame.frame = 1;  // LOCAL_NED
  CHECK(refusal({odd_frame}) == MAV_MISSION_UNSUPPORTED_FRAME);
  CHECK(refusal({}) == MAV_MISSION_ACCEPTED);  // an empty fence: no zone
}

TEST_CASE("RALLY: points above home, relative or MSL, and back") {
  MissionItemInt rel = at(0, MAV_CMD_NAV_RALLY_POINT, 300, 100, 0);
  rel.frame = MAV_FRAME_GLOBAL_RELATIVE_ALT_INT;
  rel.z = 60.0f;
  MissionItemInt msl = at(1, MAV_CMD_NAV_RALLY_POINT, -200, 0, 0);
  msl.z = 488.0f + 80.0f;
  check_rally_item(rel);
  check_rally_item(msl);
  const auto rally = to_rally({rel, msl}, GeoOrigin(kHome));
  REQUIRE(rally.size() == 2);
  CHECK(rally[0].x() == doctest::Approx(300.0).epsilon(1e-4));
  CHECK(rally[0].z() == doctest::Approx(60.0).epsilon(1e-3));
  CHECK(rally[1].z() == doctest::Approx(80.0).epsilon(1e-3));
  const auto back = rally_items(rally, GeoOrigin(kHome));
  REQUIRE(back.size() == 2);
  CHECK(back[1].mission_type == MAV_MISSION_TYPE_RALLY);
  CHECK(back[1].z == doctest::Approx(80.0f).epsilon(1e-3));
  MissionItemInt below = rel;
  below.z = -20.0f;
  CHECK_THROWS_AS(to_rally({below}, GeoOrigin(kHome)), ItemError);
  MissionItemInt nan_alt = rel;
  nan_alt.z = std::nanf("");
  CHECK_THROWS_AS(check_rally_item(nan_alt), ItemError);
  CHECK_THROWS_AS(check_rally_item(at(0, MAV_CMD_NAV_WAYPOINT, 0, 0, 0)), ItemError);
}
