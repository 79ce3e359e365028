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

// ---- land items (issue 46): the approach the path manager will fly ------------------------------

namespace {
// The default mission's landing: the hourglass, then a land item at home into the wind (heading
// 135 deg: the final comes from the south-east); its final approach is 800 m from 70 m at 5 deg.
const std::string kLandingHourglass =
    "loops: 5\nwaypoints:\n  - [400, -250, -70]\n  - [-400, -50, -70]\n  - [-400, -250, -70]\n  - [400, -50, -70]\n"
    "  - {type: land, ned: [0, 0, 0], heading: 2.3562, flare_height: 3}\n";

// One waypoint `before` (NED), then a land item at home with `land` (its keys after the position).
std::string landing(const std::string& before, const std::string& land) {
  return "waypoints:\n  - " + before + "\n  - {type: land, " + land + "}\n";
}

std::vector<std::string> notes(const std::vector<MissionProblem>& ps) {
  std::vector<std::string> out;
  for (const auto& p : ps)
    if (p.note) out.push_back(p.text);
  return out;
}
}  // namespace

TEST_CASE("mission check: the default mission's landing (a downwind leg, then a 153-deg turn onto the final) has no problem") {
  MissionLimits l = with_turns(50.0);
  l.fence_max_distance = 1000.0;
  l.fence_max_altitude = 120.0;
  CHECK(problems(kLandingHourglass, l).empty());
  l.origin = kOrigin;  // the same about a known origin
  CHECK(problems(kLandingHourglass, l).empty());
}

TEST_CASE("mission check (a): the final's entry point beyond the geofence; the floor crossed on the final is a note") {
  MissionLimits l = with_turns(50.0);
  l.fence_max_distance = 700.0;
  auto ps = problems(kLandingHourglass, l);
  REQUIRE(ps.size() == 1);
  CHECK_FALSE(ps[0].error);
  CHECK_FALSE(ps[0].note);
  CHECK(ps[0].text ==
        "m.yaml:7: waypoints[4]: the final approach's entry point (565.5, -565.5) is 799.8 m from home, beyond the geofence's "
        "max_distance 700 m: the geofence failsafe would take over on the way to it");
  l.fence_max_distance.reset();
  l.fence_min_altitude = 20.0;  // the touchdown point itself draws no floor warning
  ps = problems(kLandingHourglass, l);
  REQUIRE(ps.size() == 1);
  CHECK(ps[0].note);
  CHECK(ps[0].text ==
        "m.yaml:7: waypoints[4]: the glide path descends below the geofence's min_altitude 20 m in its last 228.5 m: expected (the "
        "geofence floor is off from the final approach until the aircraft is above it again)");
  // entered below the floor (raised from 10 m to 24 m): a warning, the floor's breach comes before the final
  l.fence_min_altitude = 30.0;
  ps = problems(landing("[-600, 0, -10]", "ned: [0, 0, 0], heading: 0"), l);
  const auto w = texts(ps, false);
  CHECK(notes(ps).empty());
  CHECK(std::find(w.begin(), w.end(),
                  "m.yaml:3: waypoints[1]: the final approach begins 24.0 m above home, below the geofence's min_altitude 30 m: the "
                  "geofence failsafe would take over on the way to its entry point") != w.end());
}

TEST_CASE("mission check (b): no room for the turn onto the final") {
  const MissionLimits l = with_turns(50.0);
  // from 30 m the final is 343 m long: its entry point (-342.8, 0) is 66 m from the item before
  auto w = texts(problems(landing("[-300, 50, -30]", "ned: [0, 0, 0], heading: 0, decision_height: 9"), l), false);
  REQUIRE(w.size() == 1);
  CHECK(w[0] ==
        "m.yaml:3: waypoints[1]: the final approach's entry point is 65.8 m from waypoints[0], less than 2 R_min = 100 m: no room for "
        "the turn onto the final (the path to it loops around)");
  // the item before on the centreline between the entry point and the runway: flown out along the final, turned back onto it
  w = texts(problems(landing("[-100, 20, -30]", "ned: [0, 0, 0], heading: 0, decision_height: 9"), l), false);
  REQUIRE(w.size() == 1);
  CHECK(w[0] ==
        "m.yaml:3: waypoints[1]: the final reverses the course from waypoints[0] to its entry point (a 175 deg turn onto heading 0 rad) "
        "with waypoints[0] 20.0 m beside the final's extended centreline, less than 2 R_min = 100 m: the turn onto the final swings out "
        "across it (is the heading the direction of landing?)");
  // the heading the wrong way round: the item before lined up on the approach, the entry point beyond the runway
  w = texts(problems(landing("[-600, 0, -30]", "ned: [0, 0, 0], heading: 3.1416, decision_height: 9"), l), false);
  REQUIRE(w.size() == 1);
  CHECK(w[0].find("a 180 deg turn onto heading 3.1416 rad") != std::string::npos);
  // lined up (the item before on the centreline beyond the entry point), or abeam it 2 R_min out: nothing
  CHECK(problems(landing("[-600, 0, -30]", "ned: [0, 0, 0], heading: 0, decision_height: 9"), l).empty());
  CHECK(problems(landing("[-100, 100, -30]", "ned: [0, 0, 0], heading: 0, decision_height: 9"), l).empty());
  // no turn radius known: not checked
  CHECK(problems(landing("[-100, 20, -30]", "ned: [0, 0, 0], heading: 0, decision_height: 9")).empty());
}

TEST_CASE("mission check (c): a touchdown point away from home's altitude, above or below (not an error)") {
  MissionLimits l;
  auto ps = problems(landing("[-800, 0, -70]", "ned: [0, 0, -5], heading: 0"), l);
  REQUIRE(ps.size() == 1);
  CHECK_FALSE(ps[0].error);
  CHECK(ps[0].text ==
        "m.yaml:3: waypoints[1]: touchdown point 5.0 m above home (down = -5): the landing takes the runway to be there; most fields "
        "are at home's altitude");
  ps = problems(landing("[-800, 0, -70]", "ned: [0, 0, 3], heading: 0"), l);
  REQUIRE(ps.size() == 1);
  CHECK_FALSE(ps[0].error);
  CHECK(ps[0].text.find("touchdown point 3.0 m below home (down = 3)") != std::string::npos);
  CHECK(problems(landing("[-800, 0, -70]", "ned: [0, 0, 0.8], heading: 0"), l).empty());  // within the estimate's own drift
  l.origin = kOrigin;
  ps = problems(landing("[-800, 0, -70]", "lla: [40.2463724, -111.6474138, 1397.0], heading: 0"), l);
  REQUIRE(ps.size() == 1);
  CHECK(ps[0].text ==
        "m.yaml:3: waypoints[1]: altitude 1397 m MSL is 10.0 m above home (1387 m MSL): the landing takes the runway to be there; most "
        "fields are at home's altitude");
}

TEST_CASE("mission check (d): a final longer than 2 km, or begun lower than 3 decision heights") {
  auto w = texts(problems(landing("[-2500, 0, -200]", "ned: [0, 0, 0], heading: 0")), false);
  REQUIRE(w.size() == 1);
  CHECK(w[0] ==
        "m.yaml:3: waypoints[1]: the final approach is 2285.1 m long (200.0 m at glide_slope 0.0873 rad), longer than 2000 m of ground "
        "assumed flat at the runway's altitude: lower waypoints[0] or steepen the glide slope");
  CHECK(problems(landing("[-2500, 0, -200]", "ned: [0, 0, 0], heading: 0, glide_slope: 0.105")).empty());  // 6 deg: 1896 m
  w = texts(problems(landing("[-600, 0, -30]", "ned: [0, 0, 0], heading: 0")), false);
  REQUIRE(w.size() == 1);
  CHECK(w[0] ==
        "m.yaml:3: waypoints[1]: the final approach begins at the altitude of waypoints[0], 30.0 m above the touchdown point, less than 3 "
        "decision heights (36 m): 205.7 m of glide path above the decision height to settle after the turn onto the final");
  w = texts(problems(landing("[-600, 0, -15]", "ned: [0, 0, 0], heading: 0")), false);
  REQUIRE(w.size() == 1);
  CHECK(w[0].find("15.0 m above the touchdown point, less than 3 decision heights (36 m): the path manager raises it to 24.0 m: 137.1 m") !=
        std::string::npos);
  w = texts(problems("waypoints:\n  - {type: land, ned: [0, 0, 0], heading: 0}\n"), false);
  REQUIRE(w.size() == 1);
  CHECK(w[0] ==
        "m.yaml:2: waypoints[0]: no item before the land item: its final approach begins 24.0 m above the touchdown point (2 decision "
        "heights), wherever the aircraft is: put a waypoint at the approach altitude before it");
}
