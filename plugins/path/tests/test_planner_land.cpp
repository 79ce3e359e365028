// The path planner's land items (issue 46): a land item read from the mission goes out in the
// WaypointList with its fields (msg::Waypoint land_*), comes back in through a mission edit
// unchanged, and an added land item stays the mission's last.
#include <doctest/doctest.h>

#include <map>
#include <memory>
#include <string>

#include <yaml-cpp/yaml.h>

#include "../src/adapters.hpp"
#include "tern/testing/harness.hpp"

using namespace tern;
using namespace tern::path;

namespace {

constexpr Nanos kStep = 100'000'000;  // the planner at 10 Hz

/// A planner flying `mission` (a config's mission: section) or, with `file`, that mission file.
std::unique_ptr<testing::Harness> planner(const std::string& mission, const std::string& file = "") {
  testing::HarnessOptions o;
  o.instance = "planner";
  o.config_dir = TERN_PATH_TEST_DATA;
  o.mission = YAML::Load(mission);
  std::map<std::string, ParamValue> params;
  if (!file.empty()) params["mission_file"] = file;
  return std::make_unique<testing::Harness>(std::make_unique<PlannerPlugin>(), params, o);
}

msg::State with_origin() {
  msg::State s;
  s.valid = s.origin_valid = true;
  s.origin_lat = 40.2455;
  s.origin_lon = -111.6480;
  s.origin_alt = 1450.0;
  return s;
}

const msg::WaypointList& list_of(testing::Harness& p) { return p.output<msg::WaypointList>("waypoints"); }

msg::MissionEdit add(std::uint32_t id, const msg::Waypoint& w, bool set_current = false) {
  msg::MissionEdit e;
  e.id = id;
  e.op = msg::MissionEdit::add;
  e.waypoint = w;
  e.publish_now = true;
  e.set_current_wp = set_current;
  return e;
}

}  // namespace

TEST_CASE("planner: a land item out in the WaypointList with its fields, and back in through a mission edit unchanged") {
  auto p = planner(
      "waypoints:\n  - [600, -600, -70]\n"
      "  - {type: land, lla: [40.2455, -111.6480, 1452.0], heading: 2.3562, glide_slope: 0.07, flare_height: 3, decision_height: 10, "
      "Va_d: 14}");
  p->set_input("state", with_origin());
  p->step(kStep);
  REQUIRE(p->published("waypoints") == 1);
  const msg::Waypoint out = list_of(*p).items[1];
  CHECK(list_of(*p).count == 2);
  CHECK_FALSE(list_of(*p).loop);  // lands after one pass
  CHECK(out.type == msg::Waypoint::land);
  CHECK_FALSE(out.lla);  // the touchdown point in NED: 2 m above the origin
  CHECK(out.w.head<2>().norm() < 1e-6);
  CHECK(out.w.z() == doctest::Approx(-2.0).epsilon(1e-6));
  CHECK(out.chi_d == 2.3562);
  CHECK(out.land_glide_slope == 0.07);
  CHECK(out.land_flare_height == 3.0);
  CHECK(out.land_decision_height == 10.0);
  CHECK(out.Va_d == 14.0);
  p->set_input("mission_edit", add(1, out, true));  // land there now: the same item back
  p->step(2 * kStep);
  REQUIRE(p->published("waypoints") == 2);
  CHECK(list_of(*p).count == 1);
  CHECK(list_of(*p).immediate);
  const msg::Waypoint back = list_of(*p).items[0];
  CHECK(back.type == out.type);
  CHECK(back.w == out.w);
  CHECK(back.chi_d == out.chi_d);
  CHECK(back.Va_d == out.Va_d);
  CHECK(back.land_glide_slope == out.land_glide_slope);
  CHECK(back.land_flare_height == out.land_flare_height);
  CHECK(back.land_decision_height == out.land_decision_height);
}

TEST_CASE("planner: a land item added to a looping mission ends the loop; nothing after it, no bad land item") {
  auto p = planner("", "fixedwing_mission.yaml");  // ROSplane's hourglass: loops until changed
  p->step(kStep);
  REQUIRE(list_of(*p).loop);
  msg::Waypoint land;
  land.type = msg::Waypoint::land;
  land.chi_d = 2.3562;
  p->set_input("mission_edit", add(1, land));
  p->step(2 * kStep);
  REQUIRE(p->published("waypoints") == 2);
  CHECK(list_of(*p).count == 5);
  CHECK(list_of(*p).items[4].type == msg::Waypoint::land);
  CHECK_FALSE(list_of(*p).loop);  // else the landing would never come
  msg::Waypoint after;
  after.w = Eigen::Vector3d(0, 300, -70);
  p->set_input("mission_edit", add(2, after));  // refused: after the land item
  p->step(3 * kStep);
  CHECK(p->published("waypoints") == 2);
  CHECK(list_of(*p).count == 5);
  land.land_glide_slope = 5.0;  // degrees given as radians: refused
  p->set_input("mission_edit", add(3, land, true));
  p->step(4 * kStep);
  CHECK(p->published("waypoints") == 2);
  land.land_glide_slope = 0.0873;
  land.type = 9;  // no such item type: refused, not flown as a waypoint
  p->set_input("mission_edit", add(4, land, true));
  p->step(5 * kStep);
  CHECK(p->published("waypoints") == 2);
}

TEST_CASE("planner: set_current in a mission that loops before its landing rotates the loop, the land item stays last") {
  auto p = planner("loops: 2\nwaypoints: [[600, 0, -70], [0, 600, -70], [-600, 0, -70], {type: land, ned: [0, 0, 0], heading: 0}]");
  p->step(kStep);
  msg::MissionEdit e;
  e.id = 1;
  e.op = msg::MissionEdit::set_current;
  e.index = 1;
  p->set_input("mission_edit", e);
  p->step(2 * kStep);
  REQUIRE(list_of(*p).count == 4);
  CHECK(list_of(*p).loop);
  CHECK(list_of(*p).items[0].w == Eigen::Vector3d(0, 600, -70));
  CHECK(list_of(*p).items[1].w == Eigen::Vector3d(-600, 0, -70));
  CHECK(list_of(*p).items[2].w == Eigen::Vector3d(600, 0, -70));
  CHECK(list_of(*p).items[3].type == msg::Waypoint::land);
  e.id = 2;
  e.index = 3;  // to the land item: land now
  p->set_input("mission_edit", e);
  p->step(3 * kStep);
  REQUIRE(list_of(*p).count == 1);
  CHECK(list_of(*p).items[0].type == msg::Waypoint::land);
}
