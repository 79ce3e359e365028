// QGroundControl's .plan files <-> MAVLink items (core/apps/mavlink/plan_file.hpp), on QGroundControl's
// own fixed-wing test plans (tests/data/qgc_plans) and on plans with a fence, rally points, a
// DO_JUMP and a landing pattern.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "mavlink/fence_items.hpp"
#include "mavlink/mission_items.hpp"
#include "mavlink/plan_file.hpp"

using namespace tern::core;
using namespace tern::core::mavlink;
using tern::GeoOrigin;

namespace {

const std::string kPlans = std::string(TERN_SOURCE_DIR) + "/tests/data/qgc_plans/";

std::string error_of(const std::string& text) {
  try {
    parse_plan(text, "x.plan");
  } catch (const PlanError& e) {
    return e.what();
  }
  return "";
}

const char* kFencePlan = R"({"fileType": "Plan", "version": 1,
  "mission": {"plannedHomePosition": [47.397, 8.5455, 488], "items": [
    {"type": "SimpleItem", "command": 22, "frame": 3, "doJumpId": 1, "params": [0, 0, 0, null, 47.398, 8.5455, 60]},
    {"type": "SimpleItem", "command": 16, "frame": 3, "doJumpId": 2, "params": [0, 0, 0, null, 47.400, 8.5455, 60]},
    {"type": "SimpleItem", "command": 16, "frame": 3, "doJumpId": 3, "params": [0, 0, 0, null, 47.400, 8.5500, 60]},
    {"type": "SimpleItem", "command": 177, "frame": 2, "doJumpId": 4, "params": [2, 1, 0, 0, 0, 0, 0]},
    {"type": "ComplexItem", "complexItemType": "fwLandingPattern", "landCoordinate": [47.397, 8.5455, 0],
     "landingApproachCoordinate": [47.392, 8.5455, 40], "loiterRadius": 75, "loiterClockwise": false,
     "useLoiterToAlt": true, "altitudesAreRelative": true, "version": 2}]},
  "geoFence": {"version": 2, "circles": [{"inclusion": false, "circle": {"center": [47.399, 8.560], "radius": 80}, "version": 1}],
    "polygons": [{"inclusion": true, "version": 1, "polygon": [[47.41, 8.53], [47.41, 8.57], [47.38, 8.57], [47.38, 8.53]]}]},
  "rallyPoints": {"version": 2, "points": [[47.401, 8.5455, 70]]}})";

}  // namespace

TEST_CASE("QGroundControl's fixed-wing test plans are read and convert as an upload does, every item flown") {
  for (const char* name : {"PX4SITL-ArduPlane.plan", "ArduPilotSITL-ArduPlane.plan", "TerrainTest-ArduPlane.plan"}) {
    INFO(name);
    const Plan p = read_plan(kPlans + name);
    REQUIRE(p.mission.size() == 10);
    CHECK(p.fence.empty());
    CHECK(p.rally.empty());
    CHECK(p.cruise_speed == 15.0);
    for (std::size_t i = 0; i < p.mission.size(); ++i) CHECK(p.mission[i].seq == i);
    CHECK(std::isnan(p.mission[3].z));  // the LOITER_TURNS QGroundControl left without an altitude
    const GeoOrigin home(p.home);
    const tern::path::Mission m = to_mission(p.mission, home);
    REQUIRE(m.waypoints.size() == 9);                                      // all but the DO_CHANGE_SPEED
    CHECK(m.waypoints[3].w.z() == doctest::Approx(m.waypoints[2].w.z()));  // NaN: the altitude of the item before (200 m)
    // NED down about home: 200 m above it, less the earth's curvature 3 km away (0.7 m)
    CHECK(m.waypoints[2].w.z() == doctest::Approx(-200.0).epsilon(0.01));
    CHECK(m.waypoints[4].w.z() == doctest::Approx(-100.0).epsilon(0.01));  // terrain frame: above home's flat ground
    CHECK(m.waypoints[5].loiter.to_altitude);
    CHECK(m.waypoints[5].loiter.direction == -1);
    CHECK(m.waypoints[6].Vg_min == 18.0);
    CHECK(m.waypoints[8].type == tern::path::ItemType::land);
  }
}

TEST_CASE("a plan with a fence, rally points, a DO_JUMP and a landing pattern; written and read back equal") {
  const Plan p = parse_plan(kFencePlan, "fence.plan");
  REQUIRE(p.mission.size() == 7);  // 4 simple items, the landing pattern's 3
  CHECK(p.mission[3].command == MAV_CMD_DO_JUMP);
  CHECK(p.mission[3].param1 == 1.0f);  // doJumpId 2 is seq 1
  CHECK(p.mission[4].command == MAV_CMD_DO_LAND_START);
  CHECK(p.mission[5].command == MAV_CMD_NAV_LOITER_TO_ALT);
  CHECK(p.mission[5].param2 == -75.0f);
  CHECK(p.mission[6].command == MAV_CMD_NAV_LAND);
  REQUIRE(p.fence.size() == 5);
  CHECK(p.fence[0].param1 == 4.0f);
  CHECK(p.fence[4].command == MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION);
  REQUIRE(p.rally.size() == 1);
  const GeoOrigin home(p.home);
  const tern::path::Mission m = to_mission(p.mission, home);
  CHECK(m.waypoints.size() == 1 + 2 + 2 + 2);  // takeoff, the jumped pair twice, the loiter down and the land item
  CHECK(to_zones(p.fence, home).size() == 2);
  CHECK(to_rally(p.rally, home)[0].z() == doctest::Approx(70.0).epsilon(1e-3));
  const Plan back = parse_plan(plan_json(p), "back.plan");
  REQUIRE(back.mission.size() == p.mission.size());
  for (std::size_t i = 0; i < p.mission.size(); ++i) {
    INFO(i);
    CHECK(back.mission[i].command == p.mission[i].command);
    CHECK(back.mission[i].x == p.mission[i].x);
    CHECK(back.mission[i].y == p.mission[i].y);
    CHECK((back.mission[i].z == p.mission[i].z || (std::isnan(back.mission[i].z) && std::isnan(p.mission[i].z))));
    CHECK((back.mission[i].param1 == p.mission[i].param1 || (std::isnan(back.mission[i].param1) && std::isnan(p.mission[i].param1))));
    CHECK(back.mission[i].param2 == p.mission[i].param2);
  }
  REQUIRE(back.fence.size() == p.fence.size());
  for (std::size_t i = 0; i < p.fence.size(); ++i) CHECK((back.fence[i].command == p.fence[i].command && back.fence[i].x == p.fence[i].x));
  CHECK(back.rally.size() == 1);
  CHECK(back.home.lat == p.home.lat);
}

TEST_CASE("a plan that is not one is refused in one line naming the field") {
  CHECK(error_of("{").find("x.plan: not JSON") == 0);
  // a number past a double (found by fuzz_plan_file: nlohmann's out_of_range, not a parse_error)
  CHECK(error_of(R"({"fileType": "Plan", "version": 33e3333})").find("x.plan: not JSON") == 0);
  CHECK(error_of(R"({"fileType": "Mission"})") == "x.plan: fileType: not a QGroundControl plan (expected \"fileType\": \"Plan\")");
  CHECK(error_of(R"({"fileType": "Plan"})") == "x.plan: mission: missing");
  const std::string bad_param =
      R"({"fileType": "Plan", "mission": {"plannedHomePosition": [47, 8, 400], "items": [{"type": "SimpleItem", "command": 16,
      "frame": 3, "params": [0, 0, 0, 0, "north", 8, 50]}]}})";
  CHECK(error_of(bad_param) == "x.plan: mission.items[0].params[4]: expected a number or null, got \"north\"");
  const std::string bad_jump =
      R"({"fileType": "Plan", "mission": {"plannedHomePosition": [47, 8, 400], "items": [{"type": "SimpleItem", "command": 177,
      "frame": 2, "doJumpId": 1, "params": [9, 1, 0, 0, 0, 0, 0]}]}})";
  CHECK(error_of(bad_jump).find("x.plan: mission.items: DO_JUMP (item 0) to doJumpId 9") == 0);
  const std::string huge_id =  // found by fuzz_plan_file: the id was converted to long past its range
      R"({"fileType": "Plan", "mission": {"plannedHomePosition": [47, 8, 400], "items": [{"type": "SimpleItem", "command": 16,
      "frame": 3, "doJumpId": 1.8e158, "params": [0, 0, 0, 0, 47.01, 8, 50]}]}})";
  CHECK(error_of(huge_id) == "x.plan: mission.items[0].doJumpId: expected a whole number >= 0, got 1.8e+158");
  const std::string far =
      R"({"fileType": "Plan", "mission": {"plannedHomePosition": [47, 8, 400], "items": [{"type": "SimpleItem", "command": 16,
      "frame": 3, "params": [0, 0, 0, 0, 1e300, 8, 50]}]}})";
  CHECK(error_of(far).find("x.plan: mission.items[0].params[4]: expected degrees") == 0);
  const std::string wide =  // a MISSION-frame item's param5 travels as MISSION_ITEM_INT's int32 x
      R"({"fileType": "Plan", "mission": {"plannedHomePosition": [47, 8, 400], "items": [{"type": "SimpleItem", "command": 178,
      "frame": 2, "params": [0, 15, -1, 0, 1e300, 0, 0]}]}})";
  CHECK(error_of(wide) ==
        "x.plan: mission.items[0].params[4]: 1.0000000000000001e+300: MISSION_ITEM_INT carries this parameter as an int32");
  CHECK(error_of(R"({"fileType": "Plan", "mission": {"plannedHomePosition": [47, 8], "items": []}})") ==
        "x.plan: mission.plannedHomePosition: expected [lat, lon, alt]");
}
