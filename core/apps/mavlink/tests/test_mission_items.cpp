// MAVLink mission items <-> tern's mission (mavlink/mission_items.hpp) without a flight, and the
// mission and command messages (mission_messages.hpp) against common.xml's CRC_EXTRA values,
// lengths and enum values (tests/mavlink/crc_extra_mission.txt, enums_mission.txt).
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "mavlink/mavlink_codec.hpp"
#include "mavlink/mission_items.hpp"
#include "mavlink/mission_messages.hpp"
#include "tern/math.hpp"

using namespace tern::core::mavlink;
using tern::GeoOrigin;
using tern::GeoPoint;
namespace path = tern::path;
namespace msg = tern::msg;

namespace {

const GeoPoint kHome{40.2463, -111.6475, 1400.0};  // an origin near ROSplane's (BYU), m MSL

/// A global item at `north`, `east` m from home, `up` m above it (GLOBAL_RELATIVE_ALT_INT).
MissionItemInt at(std::uint16_t seq, std::uint16_t command, double north, double east, double up) {
  const GeoPoint g = GeoOrigin(kHome).to_geodetic(Eigen::Vector3d(north, east, 0.0));
  MissionItemInt it;
  it.seq = seq;
  it.command = command;
  it.frame = MAV_FRAME_GLOBAL_RELATIVE_ALT_INT;
  it.autocontinue = 1;
  it.x = static_cast<std::int32_t>(std::llround(g.lat * 1e7));
  it.y = static_cast<std::int32_t>(std::llround(g.lon * 1e7));
  it.z = static_cast<float>(up);
  return it;
}

/// The planner's list of a NED mission, as the path planner publishes it.
msg::WaypointList list_of(const path::Mission& m) {
  msg::WaypointList list;
  list.count = static_cast<std::uint32_t>(m.waypoints.size());
  for (std::size_t i = 0; i < m.waypoints.size(); ++i) {
    const path::MissionWaypoint& p = m.waypoints[i];
    msg::Waypoint& w = list.items[i];
    w.w = p.w;
    w.Va_d = p.Va_d;
    w.Vg_min = p.Vg_min;
    w.type = static_cast<std::uint8_t>(p.type);
    w.chi_d = p.chi_d;
    w.loiter_radius = p.loiter.radius;
    w.loiter_direction = static_cast<std::int8_t>(p.loiter.direction);
    w.loiter_time = p.loiter.time;
    w.loiter_turns = p.loiter.turns;
    w.loiter_to_altitude = p.loiter.to_altitude;
  }
  return list;
}

MissionItemInt speed(std::uint16_t seq, float Va) {
  MissionItemInt it;
  it.seq = seq;
  it.command = MAV_CMD_DO_CHANGE_SPEED;
  it.frame = MAV_FRAME_MISSION;
  it.autocontinue = 1;
  it.param2 = Va;
  it.param3 = -1.0f;
  return it;
}

/// A mission of 10 items a GCS's plan view makes: takeoff, speed, waypoints, loiters, land.
std::vector<MissionItemInt> plan() {
  std::vector<MissionItemInt> items = {at(0, MAV_CMD_NAV_TAKEOFF, 0, 0, 40),
                                       speed(1, 18.0f),
                                       at(2, MAV_CMD_NAV_WAYPOINT, 400, -250, 70),
                                       at(3, MAV_CMD_NAV_WAYPOINT, -400, -50, 70),
                                       at(4, MAV_CMD_NAV_LOITER_TURNS, 0, 300, 70),
                                       at(5, MAV_CMD_NAV_LOITER_TIME, 300, 300, 60),
                                       speed(6, 15.0f),
                                       at(7, MAV_CMD_NAV_WAYPOINT, -300, -300, 50),
                                       at(8, MAV_CMD_NAV_WAYPOINT, -600, -600, 40),
                                       at(9, MAV_CMD_NAV_LAND, 0, 0, 0)};
  items[4].param1 = 2.0f;    // turns
  items[4].param3 = -80.0f;  // counter-clockwise, 80 m
  items[5].param1 = 30.0f;   // s
  items[9].param4 = NAN;     // the course from item 8
  return items;
}

std::vector<std::string> rows(const std::string& file) {
  std::ifstream in(std::string(TERN_SOURCE_DIR) + "/tests/mavlink/" + file);
  REQUIRE(in.good());
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') out.push_back(line);
  return out;
}

}  // namespace

TEST_CASE("the mission and command messages' CRC_EXTRA and lengths are common.xml's (crc_extra_mission.txt)") {
  const std::map<std::string, int> size = {{"uint8_t", 1}, {"int8_t", 1}, {"uint16_t", 2}, {"int16_t", 2}, {"uint32_t", 4},
                                           {"int32_t", 4}, {"float", 4},  {"uint64_t", 8}, {"char", 1}};
  for (const std::string& line : rows("crc_extra_mission.txt")) {
    std::istringstream head(line);
    std::uint32_t id = 0;
    std::string name;
    int crc = 0;
    head >> id >> name >> crc;
    // the full length: the last field's offset plus its size ("60:uint8_t uid2[18]")
    const std::string last = line.substr(line.rfind(", ") + 2);
    const int offset = std::stoi(last);
    const std::string type = last.substr(last.find(':') + 1, last.find(' ') - last.find(':') - 1);
    const auto bracket = last.find('[');
    const int full = offset + size.at(type) * (bracket == std::string::npos ? 1 : std::stoi(last.substr(bracket + 1)));
    INFO(name);
    const auto info = message_info(id);
    REQUIRE(info.has_value());
    CHECK(info->crc_extra == crc);
    CHECK(info->length == full);
  }
  // that every message of the generated table is in this file or crc_extra_common.txt: test_mavlink_codec.cpp
}

TEST_CASE("the enum values of the mission and commands are common.xml's (enums_mission.txt)") {
  const std::map<std::string, std::uint64_t> ours = {
      {"MAV_CMD_COMPONENT_ARM_DISARM", MAV_CMD_COMPONENT_ARM_DISARM},
      {"MAV_CMD_DO_CHANGE_SPEED", MAV_CMD_DO_CHANGE_SPEED},
      {"MAV_CMD_DO_GO_AROUND", MAV_CMD_DO_GO_AROUND},
      {"MAV_CMD_DO_JUMP", MAV_CMD_DO_JUMP},
      {"MAV_CMD_NAV_FENCE_RETURN_POINT", MAV_CMD_NAV_FENCE_RETURN_POINT},
      {"MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION", MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION},
      {"MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION", MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION},
      {"MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION", MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION},
      {"MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION", MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION},
      {"MAV_CMD_NAV_RALLY_POINT", MAV_CMD_NAV_RALLY_POINT},
      {"MAV_PROTOCOL_CAPABILITY_MISSION_FENCE", MAV_PROTOCOL_CAPABILITY_MISSION_FENCE},
      {"MAV_PROTOCOL_CAPABILITY_MISSION_RALLY", MAV_PROTOCOL_CAPABILITY_MISSION_RALLY},
      {"MAV_CMD_DO_LAND_START", MAV_CMD_DO_LAND_START},
      {"MAV_CMD_DO_REPOSITION", MAV_CMD_DO_REPOSITION},
      {"MAV_CMD_DO_SET_HOME", MAV_CMD_DO_SET_HOME},
      {"MAV_CMD_DO_SET_MODE", MAV_CMD_DO_SET_MODE},
      {"MAV_CMD_MISSION_START", MAV_CMD_MISSION_START},
      {"MAV_CMD_NAV_LAND", MAV_CMD_NAV_LAND},
      {"MAV_CMD_NAV_LOITER_TIME", MAV_CMD_NAV_LOITER_TIME},
      {"MAV_CMD_NAV_LOITER_TO_ALT", MAV_CMD_NAV_LOITER_TO_ALT},
      {"MAV_CMD_NAV_LOITER_TURNS", MAV_CMD_NAV_LOITER_TURNS},
      {"MAV_CMD_NAV_LOITER_UNLIM", MAV_CMD_NAV_LOITER_UNLIM},
      {"MAV_CMD_NAV_RETURN_TO_LAUNCH", MAV_CMD_NAV_RETURN_TO_LAUNCH},
      {"MAV_CMD_NAV_TAKEOFF", MAV_CMD_NAV_TAKEOFF},
      {"MAV_CMD_NAV_WAYPOINT", MAV_CMD_NAV_WAYPOINT},
      {"MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES", MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES},
      {"MAV_CMD_REQUEST_MESSAGE", MAV_CMD_REQUEST_MESSAGE},
      {"MAV_CMD_SET_MESSAGE_INTERVAL", MAV_CMD_SET_MESSAGE_INTERVAL},
      {"MAV_FRAME_GLOBAL", MAV_FRAME_GLOBAL},
      {"MAV_FRAME_GLOBAL_INT", MAV_FRAME_GLOBAL_INT},
      {"MAV_FRAME_GLOBAL_RELATIVE_ALT", MAV_FRAME_GLOBAL_RELATIVE_ALT},
      {"MAV_FRAME_GLOBAL_RELATIVE_ALT_INT", MAV_FRAME_GLOBAL_RELATIVE_ALT_INT},
      {"MAV_FRAME_GLOBAL_TERRAIN_ALT", MAV_FRAME_GLOBAL_TERRAIN_ALT},
      {"MAV_FRAME_GLOBAL_TERRAIN_ALT_INT", MAV_FRAME_GLOBAL_TERRAIN_ALT_INT},
      {"MAV_FRAME_MISSION", MAV_FRAME_MISSION},
      {"MAV_MISSION_ACCEPTED", MAV_MISSION_ACCEPTED},
      {"MAV_MISSION_DENIED", MAV_MISSION_DENIED},
      {"MAV_MISSION_ERROR", MAV_MISSION_ERROR},
      {"MAV_MISSION_INVALID", MAV_MISSION_INVALID},
      {"MAV_MISSION_INVALID_PARAM1", MAV_MISSION_INVALID_PARAM1},
      {"MAV_MISSION_INVALID_PARAM2", MAV_MISSION_INVALID_PARAM2},
      {"MAV_MISSION_INVALID_PARAM3", MAV_MISSION_INVALID_PARAM3},
      {"MAV_MISSION_INVALID_PARAM4", MAV_MISSION_INVALID_PARAM4},
      {"MAV_MISSION_INVALID_PARAM5_X", MAV_MISSION_INVALID_PARAM5_X},
      {"MAV_MISSION_INVALID_PARAM6_Y", MAV_MISSION_INVALID_PARAM6_Y},
      {"MAV_MISSION_INVALID_PARAM7", MAV_MISSION_INVALID_PARAM7},
      {"MAV_MISSION_INVALID_SEQUENCE", MAV_MISSION_INVALID_SEQUENCE},
      {"MAV_MISSION_NO_SPACE", MAV_MISSION_NO_SPACE},
      {"MAV_MISSION_OPERATION_CANCELLED", MAV_MISSION_OPERATION_CANCELLED},
      {"MAV_MISSION_TYPE_ALL", MAV_MISSION_TYPE_ALL},
      {"MAV_MISSION_TYPE_FENCE", MAV_MISSION_TYPE_FENCE},
      {"MAV_MISSION_TYPE_MISSION", MAV_MISSION_TYPE_MISSION},
      {"MAV_MISSION_TYPE_RALLY", MAV_MISSION_TYPE_RALLY},
      {"MAV_MISSION_UNSUPPORTED", MAV_MISSION_UNSUPPORTED},
      {"MAV_MISSION_UNSUPPORTED_FRAME", MAV_MISSION_UNSUPPORTED_FRAME},
      {"MAV_PROTOCOL_CAPABILITY_COMMAND_INT", MAV_PROTOCOL_CAPABILITY_COMMAND_INT},
      {"MAV_PROTOCOL_CAPABILITY_MAVLINK2", MAV_PROTOCOL_CAPABILITY_MAVLINK2},
      {"MAV_PROTOCOL_CAPABILITY_MISSION_FLOAT", MAV_PROTOCOL_CAPABILITY_MISSION_FLOAT},
      {"MAV_PROTOCOL_CAPABILITY_MISSION_INT", MAV_PROTOCOL_CAPABILITY_MISSION_INT},
      {"MAV_PROTOCOL_CAPABILITY_PARAM_FLOAT", MAV_PROTOCOL_CAPABILITY_PARAM_FLOAT},
      {"MAV_RESULT_ACCEPTED", MAV_RESULT_ACCEPTED},
      {"MAV_RESULT_DENIED", MAV_RESULT_DENIED},
      {"MAV_RESULT_FAILED", MAV_RESULT_FAILED},
      {"MAV_RESULT_TEMPORARILY_REJECTED", MAV_RESULT_TEMPORARILY_REJECTED},
      {"MAV_RESULT_UNSUPPORTED", MAV_RESULT_UNSUPPORTED},
  };
  std::size_t checked = 0;
  for (const std::string& line : rows("enums_mission.txt")) {
    std::istringstream row(line);
    std::string name;
    std::uint64_t value = 0;
    row >> name >> value;
    INFO(name);
    REQUIRE(ours.count(name) == 1);
    CHECK(ours.at(name) == value);
    ++checked;
  }
  CHECK(checked == ours.size());
}

TEST_CASE("a MISSION_ITEM_INT survives a frame, trailing zeros trimmed") {
  MissionItemInt it = plan()[4];
  it.target_system = 1;
  it.target_component = 1;
  const auto bytes = encode_frame(MissionItemInt::kId, encode(it), 3, 255, 190);
  Counters c;
  const auto frames = parse_datagram(bytes.data(), bytes.size(), c);
  REQUIRE(frames.size() == 1);
  const MissionItemInt back = decode<MissionItemInt>(frames[0]);
  CHECK(back.seq == 4);
  CHECK(back.command == MAV_CMD_NAV_LOITER_TURNS);
  CHECK(back.x == it.x);
  CHECK(back.y == it.y);
  CHECK(back.z == it.z);
  CHECK(back.param3 == -80.0f);
  CHECK(back.frame == MAV_FRAME_GLOBAL_RELATIVE_ALT_INT);
  CHECK(back.mission_type == MAV_MISSION_TYPE_MISSION);
  CHECK(bytes[1] == 37);  // mission_type 0 (the last byte) trimmed
}

TEST_CASE("a plan's items become tern's waypoints about home, NED") {
  const GeoOrigin home(kHome);
  std::vector<std::uint16_t> nav_seq;
  const path::Mission m = to_mission(plan(), home, &nav_seq);
  REQUIRE(m.waypoints.size() == 8);  // two DO_CHANGE_SPEED items set the airspeed of the items after them
  CHECK(nav_seq == std::vector<std::uint16_t>{0, 2, 3, 4, 5, 7, 8, 9});
  CHECK_FALSE(m.loop);
  const auto& w = m.waypoints;
  // takeoff without a position: above home
  CHECK(w[0].type == path::ItemType::waypoint);
  CHECK(w[0].w.norm() == doctest::Approx(40.0));
  CHECK(w[0].w.z() == doctest::Approx(-40.0));
  CHECK(w[0].Va_d == 0.0);
  // lat/lon to NED: within the degE7 rounding (1.1 cm) of where the plan put it
  CHECK(w[1].w.x() == doctest::Approx(400.0).epsilon(1e-4));
  CHECK(w[1].w.y() == doctest::Approx(-250.0).epsilon(1e-4));
  CHECK(w[1].w.z() == doctest::Approx(-70.0 + 400.0 * 400.0 / 2 / 6.37e6 + 250.0 * 250.0 / 2 / 6.37e6).epsilon(1e-3));  // Earth's curvature
  CHECK(w[1].Va_d == 18.0);
  CHECK(w[3].type == path::ItemType::loiter);
  CHECK(w[3].loiter.turns == 2.0);
  CHECK(w[3].loiter.radius == 80.0);
  CHECK(w[3].loiter.direction == -1);
  CHECK(w[4].loiter.time == 30.0);
  CHECK(w[4].loiter.direction == 1);
  CHECK(w[5].Va_d == 15.0);
  CHECK(w[7].type == path::ItemType::land);
  CHECK(w[7].chi_d == doctest::Approx(std::atan2(600.0, 600.0)).epsilon(1e-3));  // from (-600, -600) towards home: north-east
  // the same mission through a tern waypoint file, read with the planner's own reader
  const path::Mission back = path::parse_mission_text(mission_text(m), "test");
  REQUIRE(back.waypoints.size() == m.waypoints.size());
  for (std::size_t i = 0; i < m.waypoints.size(); ++i) {
    INFO(i);
    CHECK((back.waypoints[i].w - m.waypoints[i].w).norm() == doctest::Approx(0.0));
    CHECK(back.waypoints[i].type == m.waypoints[i].type);
    CHECK(back.waypoints[i].Va_d == m.waypoints[i].Va_d);
  }
  CHECK_FALSE(back.loop);
}

TEST_CASE("GLOBAL_INT's altitude is MSL, GLOBAL_RELATIVE_ALT's above home") {
  const GeoOrigin home(kHome);
  MissionItemInt msl = at(0, MAV_CMD_NAV_WAYPOINT, 100, 0, 0);
  msl.frame = MAV_FRAME_GLOBAL_INT;
  msl.z = static_cast<float>(kHome.alt + 50.0);
  MissionItemInt rel = at(1, MAV_CMD_NAV_WAYPOINT, 100, 0, 50);
  rel.frame = MAV_FRAME_GLOBAL_RELATIVE_ALT;
  const path::Mission m = to_mission({msl, rel}, home);
  CHECK(m.waypoints[0].w.z() == doctest::Approx(m.waypoints[1].w.z()).epsilon(1e-6));
  CHECK(m.waypoints[0].w.z() == doctest::Approx(-50.0).epsilon(1e-3));
}

TEST_CASE("the planner's list comes back as the items that made it") {
  const GeoOrigin home(kHome);
  const std::vector<MissionItemInt> sent = plan();
  const path::Mission m = path::parse_mission_text(mission_text(to_mission(sent, home)), "test");
  const std::vector<MissionItemInt> back = to_items(list_of(m), home);
  REQUIRE(back.size() == sent.size());
  for (std::size_t i = 0; i < sent.size(); ++i) {
    INFO(i);
    CHECK(back[i].seq == i);
    if (i == 0) {
      CHECK(back[i].command == MAV_CMD_NAV_WAYPOINT);  // a takeoff is flown (and listed) as a waypoint
      continue;
    }
    CHECK(back[i].command == sent[i].command);
    if (sent[i].command == MAV_CMD_DO_CHANGE_SPEED) {
      CHECK(back[i].param2 == sent[i].param2);
      continue;
    }
    CHECK(std::abs(back[i].x - sent[i].x) <= 1);
    CHECK(std::abs(back[i].y - sent[i].y) <= 1);
    CHECK(back[i].z == doctest::Approx(sent[i].z).epsilon(1e-4));
    CHECK(back[i].frame == MAV_FRAME_GLOBAL_RELATIVE_ALT);
  }
  CHECK(back[4].param1 == 2.0f);
  CHECK(back[4].param3 == -80.0f);
  CHECK(back[5].param1 == 30.0f);
  CHECK(back[9].param4 == doctest::Approx(45.0).epsilon(1e-3));
}

TEST_CASE("an item tern cannot fly is refused with the result a GCS shows and the item named") {
  const auto refused = [](MissionItemInt it) -> std::pair<int, std::string> {
    try {
      check_item(it);
    } catch (const ItemError& e) {
      return {e.result(), e.what()};
    }
    return {-1, ""};
  };
  MissionItemInt servo = at(3, 183, 0, 0, 0);  // DO_SET_SERVO
  auto r = refused(servo);
  CHECK(r.first == MAV_MISSION_UNSUPPORTED);
  CHECK(r.second == "mission item 3 (MAV_CMD 183): not a mission item tern flies (docs/ground-station.md)");
  MissionItemInt jump = at(3, MAV_CMD_DO_JUMP, 0, 0, 0);
  jump.param1 = 1.5f;
  CHECK(refused(jump).first == MAV_MISSION_INVALID_PARAM1);
  jump.param1 = 1.0f, jump.param2 = -2.0f;
  CHECK(refused(jump).first == MAV_MISSION_INVALID_PARAM2);
  jump.param2 = NAN;
  CHECK(refused(jump).first == MAV_MISSION_INVALID_PARAM2);
  MissionItemInt local = at(2, MAV_CMD_NAV_WAYPOINT, 0, 0, 50);
  local.frame = 1;  // LOCAL_NED
  CHECK(refused(local).first == MAV_MISSION_UNSUPPORTED_FRAME);
  MissionItemInt hold = at(1, MAV_CMD_NAV_WAYPOINT, 0, 0, 50);
  hold.param1 = 5.0f;
  r = refused(hold);
  CHECK(r.first == MAV_MISSION_INVALID_PARAM1);
  CHECK(r.second.find("mission item 1 (NAV_WAYPOINT): hold 5 s") == 0);
  MissionItemInt north = at(0, MAV_CMD_NAV_WAYPOINT, 0, 0, 50);
  north.x = 91 * 10'000'000;
  CHECK(refused(north).first == MAV_MISSION_INVALID_PARAM5_X);
  MissionItemInt turns = at(0, MAV_CMD_NAV_LOITER_TURNS, 0, 0, 50);
  CHECK(refused(turns).first == MAV_MISSION_INVALID_PARAM1);  // 0 turns
  MissionItemInt climb_speed = speed(0, 2.0f);
  climb_speed.param1 = 2.0f;  // SPEED_TYPE_CLIMB_SPEED
  CHECK(refused(climb_speed).first == MAV_MISSION_INVALID_PARAM1);
  MissionItemInt nan_land = at(0, MAV_CMD_NAV_LAND, 0, 0, 0);
  nan_land.z = NAN;  // a touchdown needs its altitude (a waypoint of NaN keeps the one before: below)
  CHECK(refused(nan_land).first == MAV_MISSION_INVALID_PARAM7);
  MissionItemInt inf_alt = at(0, MAV_CMD_NAV_WAYPOINT, 0, 0, 50);
  inf_alt.z = INFINITY;
  CHECK(refused(inf_alt).first == MAV_MISSION_INVALID_PARAM7);
  MissionItemInt heading_required = at(0, MAV_CMD_NAV_LOITER_TO_ALT, 0, 0, 50);
  heading_required.param1 = 2.0f;  // MAV_BOOL: 0 or 1
  CHECK(refused(heading_required).first == MAV_MISSION_INVALID_PARAM1);
  heading_required.param1 = 1.0f;  // QGroundControl's landing pattern asks for it: the path turns onto the next leg
  CHECK(refused(heading_required).first == -1);
  CHECK(refused(at(0, MAV_CMD_NAV_WAYPOINT, 10, 10, 50)).first == -1);
  // above the terrain: taken as above home (flat ground at home's altitude)
  MissionItemInt over_terrain = at(0, MAV_CMD_NAV_WAYPOINT, 100, 0, 50);
  over_terrain.frame = MAV_FRAME_GLOBAL_TERRAIN_ALT;
  CHECK(refused(over_terrain).first == -1);
  CHECK(to_mission({over_terrain}, GeoOrigin(kHome)).waypoints[0].w.z() == doctest::Approx(-50.0).epsilon(1e-4));  // the curvature at 100 m
  MissionItemInt body = over_terrain;
  body.frame = 12;  // BODY_NED
  CHECK(refused(body).first == MAV_MISSION_UNSUPPORTED_FRAME);
  // DO_LAND_START (QGroundControl's landing pattern) is a marker: taken, no waypoint
  MissionItemInt marker = speed(1, 0.0f);
  marker.command = MAV_CMD_DO_LAND_START;
  CHECK(refused(marker).first == -1);
  MissionItemInt touchdown = at(2, MAV_CMD_NAV_LAND, 0, 0, 0);
  touchdown.param4 = 90.0f;
  const path::Mission landing = to_mission({at(0, MAV_CMD_NAV_WAYPOINT, 0, -600, 60), marker, touchdown}, GeoOrigin(kHome));
  REQUIRE(landing.waypoints.size() == 2);
  CHECK(landing.waypoints[1].chi_d == doctest::Approx(tern::kPi / 2));
  // a land item without heading or an item before it: nothing to take the course from
  MissionItemInt land = at(0, MAV_CMD_NAV_LAND, 0, 0, 0);
  land.param4 = NAN;
  CHECK_THROWS_AS(to_mission({land}, GeoOrigin(kHome)), ItemError);
  // DO_SET_HOME: param1 a MAV_BOOL; the location given needs a latitude, a longitude and an altitude
  MissionItemInt set_home = at(4, MAV_CMD_DO_SET_HOME, 0, 0, 0);
  set_home.param1 = 2.0f;
  CHECK(refused(set_home).first == MAV_MISSION_INVALID_PARAM1);
  set_home.param1 = 1.0f;
  set_home.frame = MAV_FRAME_MISSION;
  CHECK(refused(set_home).first == -1);  // where the aircraft is: no location, any frame
  set_home.param1 = 0.0f;
  CHECK(refused(set_home).first == MAV_MISSION_UNSUPPORTED_FRAME);
  set_home.frame = MAV_FRAME_GLOBAL_RELATIVE_ALT_INT;
  set_home.x = set_home.y = 0;
  r = refused(set_home);
  CHECK(r.first == MAV_MISSION_INVALID_PARAM5_X);
  CHECK(r.second == "mission item 4 (DO_SET_HOME): the location given (param1 0) has no latitude and longitude");
  set_home = at(4, MAV_CMD_DO_SET_HOME, 100, 100, 0);
  set_home.param1 = 0.0f;
  set_home.z = NAN;
  CHECK(refused(set_home).first == MAV_MISSION_INVALID_PARAM7);
}

TEST_CASE("DO_SET_HOME moves the home the items after it return to, land at and climb above") {
  const GeoOrigin origin(kHome);
  MissionItemInt here = at(2, MAV_CMD_DO_SET_HOME, 0, 0, 0);
  here.frame = MAV_FRAME_MISSION;
  here.param1 = 1.0f;  // where the aircraft is: at item 1
  const std::vector<MissionItemInt> items = {at(0, MAV_CMD_NAV_TAKEOFF, 0, 0, 40), at(1, MAV_CMD_NAV_WAYPOINT, 500, 0, 60), here,
                                             at(3, MAV_CMD_NAV_WAYPOINT, 500, 300, 20), at(4, MAV_CMD_NAV_RETURN_TO_LAUNCH, 0, 0, 0)};
  const path::Mission m = to_mission(items, origin);
  REQUIRE(m.waypoints.size() == 4);
  const Eigen::Vector3d home = m.waypoints[1].w;                                  // item 1's position, 60 m up
  CHECK(m.waypoints[2].w.z() == doctest::Approx(home.z() - 20.0).epsilon(1e-3));  // 20 m above the new home (the curvature at 300 m)
  CHECK(m.waypoints[3].type == path::ItemType::loiter);                           // RTL: over the new home, until the mission changes
  CHECK(m.waypoints[3].loiter.time == 0.0);
  CHECK(m.waypoints[3].loiter.turns == 0.0);
  CHECK(m.waypoints[3].w.head<2>().isApprox(home.head<2>()));
  CHECK(m.waypoints[3].w.z() == m.waypoints[2].w.z());  // at the altitude of the item before, as any RTL
  // a given location (GLOBAL_RELATIVE_ALT: above the current home); a land item at x = y = 0 lands there
  MissionItemInt there = at(1, MAV_CMD_DO_SET_HOME, 0, 800, 0);
  there.param1 = 0.0f;
  MissionItemInt land_home = at(2, MAV_CMD_NAV_LAND, 0, 0, 0);
  land_home.x = land_home.y = 0;  // no position: at home
  land_home.param4 = NAN;         // the course from the item before
  const path::Mission l = to_mission({at(0, MAV_CMD_NAV_WAYPOINT, 0, 400, 50), there, land_home}, origin);
  REQUIRE(l.waypoints.size() == 2);
  CHECK(l.waypoints[1].w.y() == doctest::Approx(800.0).epsilon(1e-4));
  CHECK(std::fabs(l.waypoints[1].w.x()) < 0.01);
  CHECK(l.waypoints[1].chi_d == doctest::Approx(tern::kPi / 2));  // the course from item 0 to the new home
  // before any nav item "here" is the ground at home: no change; the frame's origin never moves
  here.seq = 0;
  const path::Mission first =
      to_mission({here, at(1, MAV_CMD_NAV_WAYPOINT, 300, 0, 50), at(2, MAV_CMD_NAV_RETURN_TO_LAUNCH, 0, 0, 0)}, origin);
  REQUIRE(first.waypoints.size() == 2);
  CHECK(first.waypoints[1].type == path::ItemType::return_home);
  CHECK(first.waypoints[0].w.z() == doctest::Approx(-50.0).epsilon(1e-3));
}

TEST_CASE("DO_JUMP: the upload unrolled into the waypoints it flies, as PX4 and ArduPilot count jumps") {
  const GeoOrigin home(kHome);
  const auto jump = [](std::uint16_t seq, float target, float repeat) {
    MissionItemInt it = at(seq, MAV_CMD_DO_JUMP, 0, 0, 0);
    it.frame = MAV_FRAME_MISSION;
    it.param1 = target, it.param2 = repeat;
    return it;
  };
  // a survey leg flown three times (the jump taken twice), then home
  std::vector<MissionItemInt> items = {at(0, MAV_CMD_NAV_TAKEOFF, 0, 0, 40), at(1, MAV_CMD_NAV_WAYPOINT, 400, 0, 60),
                                       at(2, MAV_CMD_NAV_WAYPOINT, 400, 300, 60), jump(3, 1, 2),
                                       at(4, MAV_CMD_NAV_RETURN_TO_LAUNCH, 0, 0, 0)};
  std::vector<std::uint16_t> nav_seq;
  path::Mission m = to_mission(items, home, &nav_seq);
  CHECK(nav_seq == std::vector<std::uint16_t>{0, 1, 2, 1, 2, 1, 2, 4});
  CHECK_FALSE(m.loop);
  CHECK(m.waypoints[3].w.x() == doctest::Approx(400.0).epsilon(1e-4));
  // nested: the inner jump's count is used up on the first pass and never reset
  items = {at(0, MAV_CMD_NAV_WAYPOINT, 100, 0, 50), at(1, MAV_CMD_NAV_WAYPOINT, 200, 0, 50), jump(2, 1, 1), jump(3, 0, 1)};
  nav_seq.clear();
  to_mission(items, home, &nav_seq);
  CHECK(nav_seq == std::vector<std::uint16_t>{0, 1, 1, 0, 1});
  // for ever, from the last item back to the first nav item: the mission loops
  items = {at(0, MAV_CMD_NAV_WAYPOINT, 100, 0, 50), at(1, MAV_CMD_NAV_WAYPOINT, 200, 0, 50), jump(2, 0, -1)};
  m = to_mission(items, home);
  CHECK(m.loop);
  CHECK(m.waypoints.size() == 2);
  const auto refused = [&](const std::vector<MissionItemInt>& list) -> std::pair<int, std::string> {
    try {
      to_mission(list, home);
    } catch (const ItemError& e) {
      return {e.result(), e.what()};
    }
    return {-1, ""};
  };
  // for ever anywhere else, a target past the end, and a loop that would never end in waypoints
  items = {at(0, MAV_CMD_NAV_WAYPOINT, 100, 0, 50), jump(1, 0, -1), at(2, MAV_CMD_NAV_WAYPOINT, 200, 0, 50)};
  CHECK(refused(items).first == MAV_MISSION_INVALID_PARAM2);
  items = {at(0, MAV_CMD_NAV_WAYPOINT, 100, 0, 50), jump(1, 7, 1)};
  const auto past = refused(items);
  CHECK(past.first == MAV_MISSION_INVALID_PARAM1);
  CHECK(past.second == "mission item 1 (DO_JUMP): jump to item 7: the mission has 2");
  items = {at(0, MAV_CMD_NAV_WAYPOINT, 100, 0, 50), jump(1, 0, 65535)};
  CHECK(refused(items).first == MAV_MISSION_NO_SPACE);
  items = {jump(0, 0, 65535), at(1, MAV_CMD_NAV_WAYPOINT, 100, 0, 50)};  // a jump to itself: no waypoint, bounded
  CHECK(refused(items).first == MAV_MISSION_NO_SPACE);
}

TEST_CASE("QGroundControl's fixed-wing items: LOITER_TO_ALT, a ground speed, an altitude left NaN") {
  const GeoOrigin home(kHome);
  MissionItemInt climb = at(1, MAV_CMD_NAV_LOITER_TO_ALT, 0, 600, 80);
  climb.param2 = -200.0f;  // counter-clockwise, 200 m
  MissionItemInt ground = speed(2, 18.0f);
  ground.param1 = 1.0f;  // SPEED_TYPE_GROUNDSPEED
  MissionItemInt keep = at(3, MAV_CMD_NAV_LOITER_TURNS, 400, 600, 0);
  keep.frame = MAV_FRAME_GLOBAL;  // QGroundControl's "calc above terrain" item without its terrain query: alt NaN
  keep.z = NAN;
  keep.param1 = 2.0f;
  keep.param3 = 250.0f;
  const std::vector<MissionItemInt> items = {at(0, MAV_CMD_NAV_WAYPOINT, 300, 0, 120), climb, ground, keep};
  const path::Mission m = to_mission(items, home);
  REQUIRE(m.waypoints.size() == 3);
  const path::MissionWaypoint& c = m.waypoints[1];
  CHECK(c.type == path::ItemType::loiter);
  CHECK(c.loiter.to_altitude);
  CHECK(c.loiter.radius == 200.0);
  CHECK(c.loiter.direction == -1);
  CHECK(c.loiter.time == 0.0);
  CHECK(c.loiter.turns == 0.0);
  CHECK(c.w.z() == doctest::Approx(-80.0).epsilon(1e-3));
  CHECK(c.Vg_min == 0.0);
  const path::MissionWaypoint& k = m.waypoints[2];
  CHECK(k.Vg_min == 18.0);
  CHECK(k.Va_d == 0.0);       // a ground speed leaves the airspeed as it was
  CHECK(k.w.z() == c.w.z());  // NaN: the altitude of the item before
  CHECK(k.w.x() == doctest::Approx(400.0).epsilon(1e-3));
  // the first nav item has nothing before it to keep
  MissionItemInt first = keep;
  first.seq = 0;
  CHECK_THROWS_AS(to_mission({first}, home), ItemError);
  // read back: LOITER_TO_ALT with its signed radius in param2, the ground speed as type 1
  const path::Mission again = path::parse_mission_text(mission_text(m), "test");
  REQUIRE(again.waypoints.size() == 3);
  CHECK(again.waypoints[1].loiter.to_altitude);
  CHECK(again.waypoints[2].Vg_min == 18.0);
  const std::vector<MissionItemInt> back = to_items(list_of(again), home);
  REQUIRE(back.size() == 4);
  CHECK(back[1].command == MAV_CMD_NAV_LOITER_TO_ALT);
  CHECK(back[1].param1 == 0.0f);
  CHECK(back[1].param2 == -200.0f);
  CHECK(back[2].command == MAV_CMD_DO_CHANGE_SPEED);
  CHECK(back[2].param1 == 1.0f);
  CHECK(back[2].param2 == 18.0f);
  CHECK(back[3].command == MAV_CMD_NAV_LOITER_TURNS);
  CHECK(back[3].z == doctest::Approx(80.0).epsilon(1e-3));
}
