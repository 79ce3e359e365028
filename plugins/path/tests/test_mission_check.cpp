// Where a mission's waypoints are (tern/path/mission_check.hpp): below home, too far, short legs,
// and the warnings for what is legal but suspicious. Each problem one line: source:line: field.
#include <doctest/doctest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "tern/path/mission_check.hpp"

using namespace tern::path;

namespace {

// The simulator's default origin (sim_aero sensor_params.hpp).
const tern::GeoPoint kOrigin{40.2463724, -111.6474138, 1387.0};

std::vector<MissionProblem> problems(const std::string& text, const MissionLimits& l = {}) {
  return check_mission(parse_mission_text(text, "m.yaml"), l);
}

std::vector<std::string> texts(const std::vector<MissionProblem>& ps, bool errors) {
  std::vector<std::string> out;
  for (const auto& p : ps)
    if (p.error == errors) out.push_back(p.text);
  return out;
}

MissionLimits with_turns(double R_min) {
  MissionLimits l;
  l.R_min = R_min;
  return l;
}

}  // namespace

TEST_CASE("mission check: the hourglass, in NED and in LLA about the simulator's origin, has no problem") {
  const std::string hourglass = "waypoints:\n  - [400, -250, -70]\n  - [-400, -50, -70]\n  - [-400, -250, -70]\n  - [400, -50, -70]\n";
  MissionLimits l = with_turns(50.0);
  CHECK(problems(hourglass, l).empty());
  l.origin = kOrigin;
  CHECK(problems("waypoints:\n  - {lla: [40.2499718, -111.6503560, 1457.0]}\n  - [-400, -50, -70]\n"
                 "  - {lla: [40.2427730, -111.6503560, 1457.0]}\n  - [400, -50, -70]\n",
                 l)
            .empty());
}

TEST_CASE("mission check: below the ground, in NED and in LLA, names file:line and the field") {
  MissionLimits l;
  l.origin = kOrigin;
  const auto ps = problems("waypoints:\n  - [0, 300, -70]\n  - [300, 300, 20]\n  - {lla: [40.2499718, -111.6503560, 1300]}\n", l);
  const auto errors = texts(ps, true);
  REQUIRE(errors.size() == 2);
  CHECK(errors[0] == "m.yaml:3: waypoints[1]: down = 20 m: 20.0 m below home, below the ground (NED: 70 m above home is down = -70)");
  CHECK(errors[1] == "m.yaml:4: waypoints[2]: altitude 1300 m MSL is 87.0 m below home (1387 m MSL): below the ground");
}

TEST_CASE("mission check: the lla flag forgotten: below the ground, and the coordinates draw a warning") {
  // a ROSplane file whose author meant latitude/longitude/altitude but left lla: False
  const auto ps = problems(
      "wp:\n  w: [400.0, -250.0, -70.0]\n  va_d: 17.0\n"
      "wp:\n  w: [40.2499718, -111.6503560, 1457.0]\n  lla: False\n  va_d: 17.0\n");
  const auto errors = texts(ps, true), warnings = texts(ps, false);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].find("m.yaml:4: wp 2: down = 1457 m: 1457.0 m below home, below the ground") == 0);
  REQUIRE(warnings.size() == 1);
  CHECK(warnings[0] ==
        "m.yaml:4: wp 2: [40.2499718, -111.650356, 1457] is NED (m) but looks like latitude, longitude, altitude: "
        "lla: true forgotten?");
  // metres with a decimal or three are not coordinates
  CHECK(problems("waypoints:\n  - [40.5, -111.25, -70]\n").empty());
}

TEST_CASE("mission check: a waypoint 22 km from home") {
  const auto errors = texts(problems("waypoints:\n  - [400, -250, -70]\n  - [-21996, 250, -70]\n"), true);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0] == "m.yaml:3: waypoints[1]: 21997.5 m from home, further than max_distance = 5000 m");
}

TEST_CASE("mission check: the distance limit is the caller's") {
  MissionLimits l;
  l.max_distance = 300.0;
  l.max_distance_name = "check.max_waypoint_distance";
  const auto errors = texts(problems("waypoints:\n  - [400, 0, -70]\n  - [0, 200, -70]\n", l), true);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0] == "m.yaml:2: waypoints[0]: 406.1 m from home, further than check.max_waypoint_distance = 300 m");
}

TEST_CASE("mission check: legs shorter than the turn radius, the closing leg of a loop, repeats") {
  MissionLimits l = with_turns(50.0);
  l.R_min_name = "manager.R_min";
  auto errors = texts(problems("waypoints:\n  - [0, 0, -70]\n  - [300, 0, -70]\n  - [300, 30, -70]\n", l), true);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0] ==
        "m.yaml:4: waypoints[2]: the leg from waypoints[1] is 30.0 m, shorter than the minimum turn radius manager.R_min = 50 m: "
        "no room to turn");
  // the loop's closing leg (last -> first)
  errors = texts(problems("waypoints:\n  - [0, 0, -70]\n  - [300, 0, -70]\n  - [10, 10, -70]\n", l), true);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].find("m.yaml:2: waypoints[0]: the leg from waypoints[2] is 14.1 m") == 0);
  // ... not when the mission does not loop
  CHECK(texts(problems("loop: false\nwaypoints:\n  - [0, 0, -70]\n  - [300, 0, -70]\n  - [10, 10, -70]\n", l), true).empty());
  // a repeat is skipped by the path manager: a warning
  const auto ps = problems("waypoints:\n  - [0, 0, -70]\n  - [300, 0, -70]\n  - [300, 0.5, -70]\n", l);
  CHECK(texts(ps, true).empty());
  REQUIRE(texts(ps, false).size() == 1);
  CHECK(texts(ps, false)[0] == "m.yaml:4: waypoints[2]: repeats waypoints[1] (0.5 m apart): the path manager skips it");
  // no turn radius known: legs are not checked
  CHECK(problems("waypoints:\n  - [0, 0, -70]\n  - [30, 0, -70]\n").empty());
}

TEST_CASE("mission check: warnings for waypoints outside the geofence, and for LLA without an origin") {
  MissionLimits l;
  l.fence_max_distance = 500.0;
  l.fence_max_altitude = 120.0;
  l.fence_min_altitude = 20.0;
  const auto ps = problems("waypoints:\n  - [600, 0, -70]\n  - [0, 300, -150]\n  - [0, -300, -10]\n", l);
  CHECK(texts(ps, true).empty());
  const auto w = texts(ps, false);
  REQUIRE(w.size() == 3);
  CHECK(w[0] ==
        "m.yaml:2: waypoints[0]: 600.0 m from home, beyond the geofence's max_distance 500 m: the geofence failsafe would take over");
  CHECK(w[1] == "m.yaml:3: waypoints[1]: altitude 150.0 m, above the geofence's max_altitude 120 m: the geofence failsafe would take over");
  CHECK(w[2] == "m.yaml:4: waypoints[2]: altitude 10.0 m, below the geofence's min_altitude 20 m: the geofence failsafe would take over");
  const auto no_origin = problems("waypoints:\n  - {lla: [40.2499718, -111.6503560, 1457.0]}\n  - [0, 300, -70]\n");
  REQUIRE(no_origin.size() == 1);
  CHECK_FALSE(no_origin[0].error);
  CHECK(no_origin[0].text.find("m.yaml: 1 latitude/longitude waypoint(s) not checked against home") == 0);
}

TEST_CASE("mission check: an unknown key keeps its parts for a suggestion") {
  try {
    parse_mission_text("wp:\n  w: [1, 2, 3]\n  use_chii: true\n", "m.yaml");
    FAIL("no error");
  } catch (const MissionError& e) {
    CHECK(e.where() == "m.yaml:3: wp 1: ");
    CHECK(e.unknown_key() == "use_chii");
    CHECK(std::find(e.expected_keys().begin(), e.expected_keys().end(), "use_chi") != e.expected_keys().end());
  }
}
