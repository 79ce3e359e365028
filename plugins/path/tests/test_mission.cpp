// Mission reading: ROSplane files, inline sections, tern files, LLA -> NED, bad input.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <GeographicLib/LocalCartesian.hpp>
#include <yaml-cpp/yaml.h>

#include "tern/path/mission.hpp"

using namespace tern::path;
using doctest::Approx;

namespace {
const std::filesystem::path kData = TERN_PATH_TEST_DATA;

std::string error_of(const std::string& yaml, const std::filesystem::path& base = kData) {
  try {
    parse_mission_section(YAML::Load(yaml), base);
  } catch (const MissionError& e) {
    return e.what();
  }
  return "no error";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }
}  // namespace

TEST_CASE("mission: the ROSplane mission file yields its four waypoints in order") {
  const Mission m = load_mission_file(kData / "fixedwing_mission.yaml");
  REQUIRE(m.waypoints.size() == 4);
  const double n[4] = {400, -400, -400, 400}, e[4] = {-250, -50, -250, -50};
  for (int i = 0; i < 4; ++i) {
    CAPTURE(i);
    CHECK(m.waypoints[i].w.x() == n[i]);
    CHECK(m.waypoints[i].w.y() == e[i]);
    CHECK(m.waypoints[i].w.z() == -70.0);
    CHECK(m.waypoints[i].chi_d == 1.1518);
    CHECK_FALSE(m.waypoints[i].use_chi);
    CHECK_FALSE(m.waypoints[i].lla);
    CHECK(m.waypoints[i].Va_d == 17.0);
  }
  CHECK(m.loop);
  // The same through the config section, with a path relative to the config directory.
  const Mission s = parse_mission_section(YAML::Load("file: fixedwing_mission.yaml\nloop: false"), kData);
  CHECK(s.waypoints.size() == 4);
  CHECK_FALSE(s.loop);
}

TEST_CASE("mission: ROSplane format errors name the file, line and field") {
  const std::string bad = "wp:\n  w: [1.0, 2.0, -70.0]\n  va_d: 17.0\nwp:\n  w: [1.0, abc, -70.0]\n";
  try {
    parse_mission_text(bad, "m.yaml");
    FAIL("no error");
  } catch (const MissionError& e) {
    CHECK(std::string(e.what()) == "m.yaml:5: wp 2.w[1]: 'abc' is not a number");
  }
  CHECK_THROWS_WITH_AS(parse_mission_text("wp:\n  w: [1, 2, 3]\nfoo: 1\n", "m.yaml"),
                       "m.yaml:3: unexpected top-level entry 'foo: 1' in a ROSplane mission file (only wp: entries)", MissionError);
  CHECK_THROWS_WITH_AS(parse_mission_text("wp:\n  w: [1, 2, 3]\n  chi: 1\n", "m.yaml"),
                       "m.yaml:3: wp 1: unknown key 'chi' (expected ned, w, lla, chi_d, use_chi, Va_d, va_d, type, radius, direction, "
                       "time, turns, to_altitude, Vg_min, altitude, heading, glide_slope, flare_height, decision_height)",
                       MissionError);
}

TEST_CASE("mission: a mixed LLA/NED mission resolves to the NED that GeographicLib gives") {
  const auto section = YAML::Load(R"(
loop: false
Va_d: 16
waypoints:
  - [100, 200, -50]
  - {lla: [40.2466, -111.6470, 1480.5], Va_d: 18}
  - {ned: [-100, 50, -60], chi_d: 0.5, use_chi: true}
  - {w: [40.2440, -111.6500, 1470.0], lla: true}
)");
  const Mission m = parse_mission_section(section, kData);
  REQUIRE(m.waypoints.size() == 4);
  CHECK(m.has_lla());
  CHECK_FALSE(m.loop);
  CHECK(m.waypoints[0].Va_d == 16.0);
  CHECK(m.waypoints[1].Va_d == 18.0);
  CHECK(m.waypoints[2].use_chi);
  CHECK(m.waypoints[3].lla);
  const tern::GeoPoint o{40.2455, -111.6480, 1450.0};
  const auto ned = resolve_to_ned(m.waypoints, o);
  const GeographicLib::LocalCartesian lc(o.lat, o.lon, o.alt);
  for (int i : {1, 3}) {
    double x, y, z;
    lc.Forward(m.waypoints[i].w.x(), m.waypoints[i].w.y(), m.waypoints[i].w.z(), x, y, z);
    CHECK(ned[i].w.x() == Approx(y).epsilon(1e-12));
    CHECK(ned[i].w.y() == Approx(x).epsilon(1e-12));
    CHECK(ned[i].w.z() == Approx(-z).epsilon(1e-12));
    CHECK_FALSE(ned[i].lla);
  }
  // Independent sanity check: 0.0011 deg of latitude is about 122 m north, 30.5 m up.
  CHECK(ned[1].w.x() == Approx(122.1).epsilon(2e-3));
  CHECK(ned[1].w.z() == Approx(-30.5).epsilon(1e-2));
  CHECK(ned[0].w == m.waypoints[0].w);  // NED entries unchanged
  CHECK(ned[2].w == m.waypoints[2].w);
}

TEST_CASE("mission: a tern waypoint file") {
  const auto file = std::filesystem::temp_directory_path() / "tern_path_test_mission.yaml";
  {
    std::ofstream f(file);
    f << "loop: true\nwaypoints:\n  - {ned: [0, 300, -60], Va_d: 15}\n  - [300, 300, -60]\n";
  }
  const Mission m = load_mission_file(file);
  REQUIRE(m.waypoints.size() == 2);
  CHECK(m.waypoints[1].w == Eigen::Vector3d(300, 300, -60));
  CHECK(m.source == file.string());
  std::filesystem::remove(file);
  CHECK(parse_mission_section(YAML::Node(), kData).waypoints.empty());
}

TEST_CASE("mission: bad input gives one clear line naming the field and value") {
  CHECK(contains(error_of("waypoints:\n  - {ned: [1, 2]}"), "waypoints[0].ned: expected a list of 3 numbers"));
  CHECK(contains(error_of("waypoints:\n  - {lla: [95, 2, 3]}"), "waypoints[0]: latitude 95 deg is outside [-90, 90]"));
  CHECK(contains(error_of("waypoints:\n  - {lla: [45, 200, 3]}"), "longitude 200 deg is outside [-180, 180]"));
  CHECK(contains(error_of("waypoints:\n  - {ned: [1, 2, .nan]}"), "waypoints[0].ned[2]: value .nan is not finite"));
  CHECK(contains(error_of("waypoints:\n  - {ned: [1, 2, 3], Va_d: -3}"), "Va_d -3 m/s must be >= 0"));
  CHECK(contains(error_of("waypoints:\n  - {chi_d: 1}"), "waypoints[0]: no position"));
  CHECK(contains(error_of("waypoints:\n  - {ned: [1, 2, 3], w: [1, 2, 3]}"), "more than one position"));
  CHECK(contains(error_of("waypoints:\n  - {ned: [1, 2, 3], use_chi: maybe}"), "waypoints[0].use_chi: 'maybe' is not true or false"));
  CHECK(contains(error_of("waypoints:\n  - {ned: [1, 2, 3], speed: 3}"), "unknown key 'speed'"));
  // a key given twice (yaml-cpp would read the first): in a waypoint, in the mission's map, in a ROSplane wp
  CHECK(contains(error_of("waypoints:\n  - {ned: [1, 2, 3], va_d: 15,\n     va_d: 25}"),
                 ":3: waypoints[0]: key 'va_d' given twice (first at line 2): one of the two would be ignored"));
  CHECK(contains(error_of("loops: 2\nwaypoints: [[1, 2, -3]]\nloops: 3"), ":3: key 'loops' given twice (first at line 1)"));
  CHECK_THROWS_WITH_AS(parse_mission_text("wp:\n  w: [1, 2, 3]\n  va_d: 15\n  va_d: 25\n", "m.yaml"),
                       "m.yaml:4: wp 1: key 'va_d' given twice (first at line 3): one of the two would be ignored", MissionError);
  CHECK(contains(error_of("waypoint: []"), ":1: unknown key 'waypoint'"));
  CHECK(contains(error_of("file: nowhere.yaml"), "nowhere.yaml: cannot read the mission file"));
  CHECK(contains(error_of("loops: 2.5\nwaypoints: [[1, 2, -3]]"), "loops: 2.5 is not a whole number of loops in [1, 1000]"));
  CHECK(contains(error_of("loops: 0\nwaypoints: [[1, 2, -3]]"), "loops: 0 is not a whole number"));
  CHECK(contains(error_of("waypoints: 3"), "waypoints: expected a list"));
  CHECK_THROWS_AS(parse_mission_text("waypoints: [ {ned: [1, 2, 3]", "broken.yaml"), MissionError);
  CHECK_THROWS_AS(lla_to_ned(Eigen::Vector3d(91, 0, 0), tern::GeoPoint{}), MissionError);
}

TEST_CASE("mission: loiter and return_home items (issue 18), in a section and in a ROSplane file") {
  const Mission m = parse_mission_section(YAML::Load(R"(
waypoints:
  - [300, 0, -70]
  - {type: loiter, ned: [300, 300, -80], radius: 60, direction: ccw, turns: 2, time: 90}
  - {type: return_home}
  - {type: return_home, altitude: 100, radius: 90}
)"),
                                          kData);
  REQUIRE(m.waypoints.size() == 4);
  CHECK(m.waypoints[0].type == ItemType::waypoint);
  const auto& l = m.waypoints[1];
  CHECK(l.type == ItemType::loiter);
  CHECK(l.w == Eigen::Vector3d(300, 300, -80));
  CHECK(l.loiter.radius == 60.0);
  CHECK(l.loiter.direction == -1);
  CHECK(l.loiter.turns == 2.0);
  CHECK(l.loiter.time == 90.0);
  CHECK(m.waypoints[2].type == ItemType::return_home);
  CHECK(m.waypoints[2].w == Eigen::Vector3d(0, 0, -80));  // the altitude of the item before it
  CHECK(m.waypoints[3].w == Eigen::Vector3d(0, 0, -100));
  CHECK(m.waypoints[3].loiter.radius == 90.0);
  CHECK(m.waypoints[3].loiter.direction == 1);
  const Mission r = parse_mission_text(
      "wp:\n  w: [100, 0, -50]\nwp:\n  w: [100, 100, -50]\n  type: loiter\n  time: 30\nwp:\n  type: return_home\n", "ros.yaml");
  REQUIRE(r.waypoints.size() == 3);
  CHECK(r.waypoints[1].type == ItemType::loiter);
  CHECK(r.waypoints[1].loiter.time == 30.0);
  CHECK(r.waypoints[2].w == Eigen::Vector3d(0, 0, -50));
}

TEST_CASE("mission: bad loiter and return_home items give one line naming the item and value") {
  CHECK(contains(error_of("waypoints: [{type: orbit, ned: [0, 0, -50]}]"), "waypoints[0].type: 'orbit' is not a mission item type"));
  CHECK(contains(error_of("waypoints: [{type: loiter, ned: [0, 0, -50], radius: -5}]"), "waypoints[0].radius: -5 m is negative"));
  CHECK(contains(error_of("waypoints: [{type: loiter, ned: [0, 0, -50], direction: left}]"),
                 "waypoints[0].direction: 'left' is not an orbit direction (expected cw or ccw)"));
  CHECK(contains(error_of("waypoints: [{ned: [0, 0, -50], radius: 60}]"), "are for loiter and return_home items"));
  CHECK(contains(error_of("waypoints: [{type: return_home}]"), "no altitude, and no item before it"));
  CHECK(contains(error_of("waypoints: [{type: return_home, ned: [5, 5, -50]}]"), "return_home takes no position"));
  CHECK(contains(error_of("waypoints: [[0, 0, -50], {type: return_home, turns: 2}]"), "return_home loiters until the mission changes"));
  CHECK(contains(error_of("waypoints: [{type: loiter, ned: [0, 0, -50], use_chi: true}]"), "takes no chi_d or use_chi"));
  CHECK(contains(error_of("waypoints: [{type: loiter, ned: [0, 0, -50], altitude: 60}]"), "altitude is for return_home items"));
}

TEST_CASE("mission: a file's route flown `loops` times, then the section's own items (a land item)") {
  const Mission m = parse_mission_section(
      YAML::Load("file: fixedwing_mission.yaml\nloops: 5\nwaypoints:\n  - {type: land, ned: [0, 0, 0], heading: 2.3562}"), kData);
  REQUIRE(m.waypoints.size() == 5);
  CHECK(m.loop);
  CHECK(m.loops == 5);
  CHECK(m.waypoints[0].w == Eigen::Vector3d(400, -250, -70));  // the file's first
  CHECK(m.waypoints[4].type == ItemType::land);
  CHECK(m.waypoints[4].chi_d == doctest::Approx(2.3562));
  CHECK(m.waypoints[4].w == Eigen::Vector3d::Zero());
}

TEST_CASE("mission: a land item: touchdown point, runway heading, glide slope, flare and decision heights") {
  const Mission m = parse_mission_section(YAML::Load(R"(
Va_d: 17
waypoints:
  - [600, -600, -70]
  - {type: land, ned: [0, 0, 0], heading: 2.3562, glide_slope: 0.07, flare_height: 3, decision_height: 10, Va_d: 14}
)"),
                                          kData);
  REQUIRE(m.waypoints.size() == 2);
  const MissionWaypoint& l = m.waypoints[1];
  CHECK(l.type == ItemType::land);
  CHECK(l.w == Eigen::Vector3d::Zero());
  CHECK(l.chi_d == 2.3562);
  CHECK_FALSE(l.use_chi);
  CHECK(l.land.glide_slope == 0.07);
  CHECK(l.land.flare_height == 3.0);
  CHECK(l.land.decision_height == 10.0);
  CHECK(l.Va_d == 14.0);
  CHECK_FALSE(m.loop);  // a mission that lands flies its items once (no loops given)
  // the defaults of LandSpec (item.hpp) when only the heading is given; an LLA touchdown point
  const Mission d = parse_mission_section(
      YAML::Load("waypoints:\n  - [600, -600, -70]\n  - {type: land, lla: [40.2455, -111.6480, 1450.0], heading: -1.5}"), kData);
  const MissionWaypoint& ll = d.waypoints[1];
  CHECK(ll.lla);
  CHECK(ll.w == Eigen::Vector3d(40.2455, -111.6480, 1450.0));
  CHECK(ll.chi_d == -1.5);
  CHECK(ll.land.glide_slope == LandSpec{}.glide_slope);
  CHECK(ll.land.flare_height == LandSpec{}.flare_height);
  CHECK(ll.land.decision_height == LandSpec{}.decision_height);
  CHECK(resolve_to_ned(d.waypoints, tern::GeoPoint{40.2455, -111.6480, 1450.0})[1].w.norm() < 1e-9);  // at the origin
}

TEST_CASE("mission: a land item in a ROSplane file takes chi_d as its heading (use_chi: False, lla: False as ROSplane writes)") {
  const Mission m = parse_mission_text(
      "wp:\n  w: [600.0, -600.0, -70.0]\n  va_d: 17.0\n"
      "wp:\n  type: land\n  w: [10.0, -5.0, 0.0]\n  chi_d: 2.3562\n  lla: False\n  use_chi: False\n  va_d: 15.0\n  flare_height: 2.5\n",
      "ros.yaml");
  REQUIRE(m.waypoints.size() == 2);
  CHECK(m.waypoints[1].type == ItemType::land);
  CHECK(m.waypoints[1].chi_d == 2.3562);
  CHECK(m.waypoints[1].w == Eigen::Vector3d(10, -5, 0));
  CHECK(m.waypoints[1].land.flare_height == 2.5);
  CHECK(m.waypoints[1].line == 4);
  CHECK_FALSE(m.loop);
}

TEST_CASE("mission: loops before a landing: loops: N flies the items N times, loop: true alone is refused") {
  const Mission m = parse_mission_section(YAML::Load("loops: 3\nwaypoints: [[600, -600, -70], [0, 600, -70], "
                                                     "{type: land, ned: [0, 0, 0], heading: 0}]"),
                                          kData);
  CHECK(m.loop);
  CHECK(m.loops == 3);
  CHECK_FALSE(
      parse_mission_section(YAML::Load("loop: false\nwaypoints: [[600, 0, -70], {type: land, ned: [0, 0, 0], heading: 0}]"), kData).loop);
  CHECK(error_of("loop: true\nwaypoints: [[600, 0, -70], {type: land, ned: [0, 0, 0], heading: 0}]") ==
        "mission config (mission:):1: loop: true would never reach the land item waypoints[1]: give loops: N (the items before it "
        "flown N times, then the landing), or leave loop out (once)");
  // a file's loop gives way to the landing appended by the section; without loops: once
  const Mission f =
      parse_mission_section(YAML::Load("file: fixedwing_mission.yaml\nwaypoints: [{type: land, ned: [0, 0, 0], heading: 0}]"), kData);
  CHECK(f.waypoints.size() == 5);
  CHECK_FALSE(f.loop);
}

TEST_CASE("mission: bad land items give one line naming file:line, the item, the field and the value") {
  const std::string before = "waypoints:\n  - [600, 0, -70]\n  - {type: land, ned: [0, 0, 0], ";
  CHECK(error_of(before + "glide_slope: 0.1}") ==
        "mission config (mission:):3: waypoints[1]: a land item needs heading: the runway heading, rad (the course of the final approach)");
  CHECK(error_of(before + "heading: 1, chi_d: 1}") ==
        "mission config (mission:):3: waypoints[1]: give the runway heading once: heading or chi_d, not both");
  CHECK(error_of(before + "heading: 135}") ==
        "mission config (mission:):3: waypoints[1]: heading 135 rad is outside [-2 pi, 2 pi] (radians: 135 deg would be 2.3562)");
  CHECK(error_of(before + "heading: 0, glide_slope: 5}") ==
        "mission config (mission:):3: waypoints[1]: glide_slope 5 rad is outside (0, 0.35] (radians: 5 deg would be 0.0873)");
  CHECK(error_of(before + "heading: 0, glide_slope: 0}") ==
        "mission config (mission:):3: waypoints[1]: glide_slope 0 rad is outside (0, 0.35]");
  CHECK(error_of(before + "heading: 0, glide_slope: -0.05}") ==
        "mission config (mission:):3: waypoints[1]: glide_slope -0.05 rad is outside (0, 0.35]");
  CHECK(error_of(before + "heading: 0, flare_height: 0}") ==
        "mission config (mission:):3: waypoints[1]: flare_height 0 m must be > 0 (above the touchdown point)");
  CHECK(error_of(before + "heading: 0, flare_height: 5, decision_height: 5}") ==
        "mission config (mission:):3: waypoints[1]: decision_height 5 m must be above flare_height 5 m (the approach is judged before the "
        "flare)");
  CHECK(error_of(before + "heading: 0, flare_height: abc}") ==
        "mission config (mission:):3: waypoints[1].flare_height: 'abc' is not a number");
  CHECK(error_of(before + "heading: 0, radius: 50}") ==
        "mission config (mission:):3: waypoints[1]: a land item takes no radius, direction, time, turns or to_altitude (those are loiter "
        "keys)");
  CHECK(error_of(before + "heading: 0, turns: 1}").find("takes no radius, direction, time, turns or to_altitude") != std::string::npos);
  CHECK(error_of(before + "heading: 0, use_chi: true}") ==
        "mission config (mission:):3: waypoints[1]: use_chi: true is for waypoints (a land item always arrives on its heading)");
  CHECK(error_of(before + "heading: 0, altitude: 0}") ==
        "mission config (mission:):3: waypoints[1]: altitude is for return_home items (others give a position)");
  CHECK(error_of("waypoints:\n  - [600, 0, -70]\n  - {type: land, heading: 0}") ==
        "mission config (mission:):3: waypoints[1]: no position (ned, w or lla: [lat, lon, alt])");
  // the keys of a land item on other items
  CHECK(error_of("waypoints:\n  - {ned: [600, 0, -70], heading: 1}") ==
        "mission config (mission:):2: waypoints[0]: heading is a land item's runway heading (a waypoint takes chi_d)");
  CHECK(error_of("waypoints:\n  - {type: loiter, ned: [600, 0, -70], glide_slope: 0.1}") ==
        "mission config (mission:):2: waypoints[0]: glide_slope, flare_height and decision_height are for land items (type: land)");
}

TEST_CASE("mission: a land item is the last, and is reached") {
  CHECK(error_of("waypoints:\n  - [600, 0, -70]\n  - {type: land, ned: [0, 0, 0], heading: 0}\n  - [0, 600, -70]") ==
        "mission config (mission:):4: waypoints[2]: comes after the land item waypoints[1], which ends the mission: never reached");
  CHECK(error_of("waypoints:\n  - {type: return_home, altitude: 70}\n  - {type: land, ned: [0, 0, 0], heading: 0}") ==
        "mission config (mission:):3: waypoints[1]: never reached: the item before it (return_home) orbits until the mission changes (a "
        "loiter before a landing needs time, turns or to_altitude)");
  CHECK(
      error_of("waypoints:\n  - {type: loiter, ned: [600, 0, -70]}\n  - {type: land, ned: [0, 0, 0], heading: 0}").find("never reached") !=
      std::string::npos);
  CHECK(parse_mission_section(YAML::Load("waypoints:\n  - {type: loiter, ned: [600, 0, -70], turns: 2}\n"
                                         "  - {type: land, ned: [0, 0, 0], heading: 0}"),
                              kData)
            .waypoints.size() == 2);
  // the section's items after a file that lands: the error names the section's own line
  const auto file = std::filesystem::temp_directory_path() / "tern_path_test_lands.yaml";
  {
    std::ofstream f(file);
    f << "waypoints:\n  - [600, 0, -70]\n  - {type: land, ned: [0, 0, 0], heading: 0}\n";
  }
  CHECK(error_of("file: " + file.string() + "\nwaypoints:\n  - [0, 600, -70]") ==
        "mission config (mission:):3: waypoints[0]: comes after the land item waypoints[1], which ends the mission: never reached");
  std::filesystem::remove(file);
}
