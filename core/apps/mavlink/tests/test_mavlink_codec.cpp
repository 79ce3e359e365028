// The MAVLink codec (mavlink/mavlink_codec.hpp, mavlink_messages.hpp: the SDK's framing and the
// structs generated from common.xml) and the parameter ids (param_ids.hpp) without a flight: CRCs,
// the generated CRC_EXTRA table against common.xml's, frames, zero trimming, and hostile bytes.
#include <doctest/doctest.h>

#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <sstream>

#include "mavlink/mavlink_codec.hpp"
#include "mavlink/mavlink_messages.hpp"
#include "mavlink/param_ids.hpp"

using namespace tern::core::mavlink;

TEST_CASE("X.25 CRC: CRC-16/MCRF4XX's check value") {
  const std::string s = "123456789";
  CHECK(crc_calculate(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()) == 0x6F91);
}

TEST_CASE("CRC_EXTRA and payload lengths are common.xml's (tests/mavlink/crc_extra_common.txt)") {
  std::ifstream in(std::string(TERN_SOURCE_DIR) + "/tests/mavlink/crc_extra_common.txt");
  REQUIRE(in.good());
  const std::map<std::string, int> size = {{"char", 1},     {"int8_t", 1}, {"uint8_t", 1}, {"int16_t", 2},  {"uint16_t", 2}, {"int32_t", 4},
                                           {"uint32_t", 4}, {"float", 4},  {"int64_t", 8}, {"uint64_t", 8}, {"double", 8}};
  std::set<std::uint32_t> seen;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream head(line.substr(0, line.find('|')));
    std::uint32_t id = 0;
    std::string name;
    int crc = 0, base = 0;
    head >> id >> name >> crc >> base;
    // the full length: the last field's offset plus its size
    const std::string layout = line.substr(line.find('|') + 1);
    std::smatch m;
    REQUIRE(std::regex_search(layout, m, std::regex(R"((\d+):(\w+) \w+(?:\[(\d+)\])?\s*$)")));
    const int full = std::stoi(m[1]) + size.at(m[2]) * (m[3].matched ? std::stoi(m[3]) : 1);
    const auto info = message_info(id);
    INFO(name);
    REQUIRE(info.has_value());
    CHECK(info->crc_extra == crc);
    CHECK(info->length == full);
    seen.insert(id);
  }
  // every message of the generated table is in this file or in crc_extra_mission.txt
  std::ifstream mission(std::string(TERN_SOURCE_DIR) + "/tests/mavlink/crc_extra_mission.txt");
  REQUIRE(mission.good());
  while (std::getline(mission, line))
    if (!line.empty() && line[0] != '#') seen.insert(static_cast<std::uint32_t>(std::stoul(line)));
  for (const auto& d : kDialect) {
    INFO(d.name);
    CHECK(seen.count(d.id) == 1);
  }
}

TEST_CASE("a frame round-trips, trimmed of trailing zeros and zero-filled on reading") {
  ParamSet set{1, 1, to_chars<16>("slc.roll_kp"), 0.5f, MAV_PARAM_TYPE_REAL32};
  const auto bytes = encode_frame(ParamSet::kId, encode(set), 7, 255, 190);
  CHECK(bytes[0] == kMagicV2);
  CHECK(bytes[1] == 23);  // param_type is the last byte and not zero: nothing trimmed
  Counters c;
  const auto frames = parse_datagram(bytes.data(), bytes.size(), c);
  REQUIRE(frames.size() == 1);
  CHECK(frames[0].seq == 7);
  CHECK(frames[0].sysid == 255);
  CHECK(frames[0].compid == 190);
  const ParamSet back = decode<ParamSet>(frames[0]);
  CHECK(to_string(back.param_id) == "slc.roll_kp");
  CHECK(back.param_value == 0.5f);
  CHECK(back.target_system == 1);

  // a heartbeat of zeros keeps one payload byte; it reads back full length
  const auto hb = encode_frame(Heartbeat::kId, encode(Heartbeat{0, 0, 0, 0, 0, 0}), 0, 1, 1);
  CHECK(hb[1] == 1);
  Counters c2;
  const auto f2 = parse_datagram(hb.data(), hb.size(), c2);
  REQUIRE(f2.size() == 1);
  CHECK(f2[0].payload.size() == 9);
  // a 16-char id fills its field without a terminator
  ParamValue v{to_chars<16>("abcdefghijklmnop"), 2.0f, MAV_PARAM_TYPE_INT32, 3, 2};
  const auto vb = encode_frame(ParamValue::kId, encode(v), 1, 1, 1);
  Counters c3;
  const auto f3 = parse_datagram(vb.data(), vb.size(), c3);
  REQUIRE(f3.size() == 1);
  const auto vv = decode<ParamValue>(f3[0]);
  CHECK(to_string(vv.param_id) == "abcdefghijklmnop");
  CHECK(vv.param_count == 3);
  CHECK(vv.param_index == 2);
  CHECK(vv.param_type == MAV_PARAM_TYPE_INT32);
}

TEST_CASE("a frame's target system: the field where the wire order puts it; none for a message to every system") {
  const auto read_back = [](std::uint32_t id, const std::vector<std::uint8_t>& payload) {
    const auto bytes = encode_frame(id, payload, 0, 255, 190);
    Counters c;
    const auto frames = parse_datagram(bytes.data(), bytes.size(), c);
    REQUIRE(frames.size() == 1);
    return target_system(frames[0]);
  };
  CHECK(read_back(ParamSet::kId, encode(ParamSet{2, 1, to_chars<16>("slc.roll_kp"), 0.5f, MAV_PARAM_TYPE_REAL32})) == 2);
  CommandLong c;
  c.target_system = 3;
  c.command = 400;
  CHECK(read_back(CommandLong::kId, encode(c)) == 3);                  // after the seven floats and the command
  CHECK(read_back(Timesync::kId, encode(Timesync{0, 5, 4, 1})) == 4);  // an extension field
  CHECK(read_back(Timesync::kId, encode(Timesync{0, 5, 0, 0})) == 0);  // not sent: 0, every system
  CHECK_FALSE(read_back(Heartbeat::kId, encode(Heartbeat{6, 8, 0, 0, 0, 3})).has_value());
}

TEST_CASE("two frames in one datagram, and hostile bytes counted and dropped") {
  auto a = encode_frame(ParamRequestList::kId, encode(ParamRequestList{1, 1}), 0, 255, 190);
  const auto b = encode_frame(Heartbeat::kId, encode(Heartbeat{MAV_TYPE_GCS, 8, 0, 0, 4, 3}), 1, 255, 190);
  a.insert(a.end(), b.begin(), b.end());
  Counters c;
  CHECK(parse_datagram(a.data(), a.size(), c).size() == 2);
  CHECK(c.dropped() == 0);

  SUBCASE("wrong CRC") {
    auto bad = b;
    bad.back() ^= 0x5A;
    Counters k;
    CHECK(parse_datagram(bad.data(), bad.size(), k).empty());
    CHECK(k.bad_crc == 1);
  }
  SUBCASE("truncated") {
    Counters k;
    CHECK(parse_datagram(b.data(), b.size() - 3, k).empty());
    CHECK(k.truncated == 1);
  }
  SUBCASE("unknown message id") {
    auto u = b;
    u[7] = 0x99;  // msgid 153: not a message tern reads
    Counters k;
    CHECK(parse_datagram(u.data(), u.size(), k).empty());
    CHECK(k.unknown_id == 1);
  }
  SUBCASE("MAVLink 1") {
    const std::vector<std::uint8_t> v1 = {0xFE, 9, 0, 255, 190, 0, 0, 0, 0, 0, 6, 8, 0, 4, 3, 0x12, 0x34};
    Counters k;
    CHECK(parse_datagram(v1.data(), v1.size(), k).empty());
    CHECK(k.mavlink1 == 1);
  }
  SUBCASE("a known message longer than its definition") {
    std::vector<std::uint8_t> p(30, 1);  // HEARTBEAT is 9 bytes
    std::vector<std::uint8_t> f = {kMagicV2, 30, 0, 0, 0, 255, 190, 0, 0, 0};
    f.insert(f.end(), p.begin(), p.end());
    std::uint16_t crc = crc_calculate(f.data() + 1, f.size() - 1);
    crc = crc_accumulate(50, crc);
    f.push_back(static_cast<std::uint8_t>(crc & 0xFF));
    f.push_back(static_cast<std::uint8_t>(crc >> 8));
    Counters k;
    CHECK(parse_datagram(f.data(), f.size(), k).empty());
    CHECK(k.bad_length == 1);
  }
  SUBCASE("random datagrams never crash and never make a frame out of noise") {
    std::mt19937 rng(42);
    Counters k;
    std::size_t frames = 0;
    for (int i = 0; i < 20000; ++i) {
      std::vector<std::uint8_t> d(rng() % 300);
      for (auto& x : d) x = static_cast<std::uint8_t>(rng());
      if (!d.empty() && i % 2 == 0) d[0] = kMagicV2;  // half of them start like a frame
      frames += parse_datagram(d.data(), d.size(), k).size();
    }
    CHECK(k.datagrams == 20000);
    CHECK(frames == 0);
    CHECK(k.noise > 0);
    CHECK(k.dropped() >= 10000);  // every datagram that started like a frame was dropped one way or another
  }
}

TEST_CASE("parameter ids: 16 characters, deterministic, unique") {
  CHECK(shorten_param_id("slc.roll_kp") == "slc.roll_kp");
  const std::string id = shorten_param_id("estimator_ekf.gyro_noise_density");
  CHECK(id.size() == 16);
  CHECK(id.substr(0, 12) == "estimator_e~");
  CHECK(shorten_param_id("estimator_ekf.gyro_noise_density") == id);
  CHECK(shorten_param_id("estimator_ekf.gyro_noise_density", 1) != id);

  const ParamTable t({{"slc.roll_kp", tern::ParamKind::real},
                      {"sim.aircraft", tern::ParamKind::text},
                      {"sim.wind", tern::ParamKind::vector},
                      {"planner.loop", tern::ParamKind::boolean},
                      {"controller_slc_long.altitude_hold_kp", tern::ParamKind::real},
                      {"controller_slc_long.altitude_hold_ki", tern::ParamKind::real},
                      {"planner.max_items", tern::ParamKind::integer}});
  REQUIRE(t.params().size() == 5);  // text and vector left out
  CHECK(t.params()[0].mav_type == MAV_PARAM_TYPE_REAL32);
  CHECK(t.params()[1].mav_type == MAV_PARAM_TYPE_UINT8);
  CHECK(t.params()[4].mav_type == MAV_PARAM_TYPE_INT32);
  CHECK(t.params()[2].id != t.params()[3].id);
  CHECK(t.find(t.params()[3].id) == std::optional<std::size_t>(3));
  CHECK(t.shortened().size() == 3);
  CHECK_FALSE(t.find("nope").has_value());
}

TEST_CASE("parameter values as MAVLink's float") {
  CHECK(std::get<double>(from_mav_value(0.7f, tern::ParamKind::real)) == 0.7);  // not 0.699999988...
  CHECK(std::get<std::int64_t>(from_mav_value(41.6f, tern::ParamKind::integer)) == 42);
  CHECK(std::get<bool>(from_mav_value(1.0f, tern::ParamKind::boolean)));
  CHECK(to_mav_value(tern::ParamValue(std::int64_t{12})) == 12.0f);
  CHECK(to_mav_value(tern::ParamValue(true)) == 1.0f);
}

TEST_CASE("STATUSTEXT: one message up to 50 characters, chunks beyond") {
  const auto one = statustext_chunks(MAV_SEVERITY_INFO, "phase cruise", 7);
  REQUIRE(one.size() == 1);
  CHECK(one[0].id == 0);
  const std::string long_text(120, 'x');
  const auto three = statustext_chunks(MAV_SEVERITY_WARNING, long_text, 7);
  REQUIRE(three.size() == 3);
  CHECK(to_string(three[2].text).size() == 20);
  CHECK(three[2].chunk_seq == 2);
  CHECK(three[1].id == 7);
  // a multiple of 50: an empty last chunk carries the NUL that ends the text
  const auto exact = statustext_chunks(MAV_SEVERITY_WARNING, std::string(100, 'y'), 8);
  REQUIRE(exact.size() == 3);
  CHECK(to_string(exact[2].text).empty());
  // a chunk's fields on the wire
  const auto bytes = encode_frame(Statustext::kId, encode(three[1]), 0, 1, 1);
  Counters c;
  const auto f = parse_datagram(bytes.data(), bytes.size(), c);
  REQUIRE(f.size() == 1);
  CHECK(f[0].payload[51] == 7);  // id, little endian
  CHECK(f[0].payload[53] == 1);  // chunk_seq
}

TEST_CASE("the enum values tern sends are common.xml's (tests/mavlink/enums_common.txt)") {
  const std::map<std::string, std::uint32_t> ours = {
      {"GPS_FIX_TYPE_2D_FIX", GPS_FIX_TYPE_2D_FIX},
      {"GPS_FIX_TYPE_3D_FIX", GPS_FIX_TYPE_3D_FIX},
      {"GPS_FIX_TYPE_NO_FIX", GPS_FIX_TYPE_NO_FIX},
      {"GPS_FIX_TYPE_NO_GPS", GPS_FIX_TYPE_NO_GPS},
      {"MAV_AUTOPILOT_GENERIC", MAV_AUTOPILOT_GENERIC},
      {"MAV_COMP_ID_AUTOPILOT1", MAV_COMP_ID_AUTOPILOT1},
      {"MAV_MODE_FLAG_AUTO_ENABLED", MAV_MODE_FLAG_AUTO_ENABLED},
      {"MAV_MODE_FLAG_CUSTOM_MODE_ENABLED", MAV_MODE_FLAG_CUSTOM_MODE_ENABLED},
      {"MAV_MODE_FLAG_GUIDED_ENABLED", MAV_MODE_FLAG_GUIDED_ENABLED},
      {"MAV_MODE_FLAG_MANUAL_INPUT_ENABLED", MAV_MODE_FLAG_MANUAL_INPUT_ENABLED},
      {"MAV_MODE_FLAG_SAFETY_ARMED", MAV_MODE_FLAG_SAFETY_ARMED},
      {"MAV_MODE_FLAG_STABILIZE_ENABLED", MAV_MODE_FLAG_STABILIZE_ENABLED},
      {"MAV_PARAM_TYPE_INT32", MAV_PARAM_TYPE_INT32},
      {"MAV_PARAM_TYPE_REAL32", MAV_PARAM_TYPE_REAL32},
      {"MAV_PARAM_TYPE_UINT8", MAV_PARAM_TYPE_UINT8},
      {"MAV_SEVERITY_CRITICAL", MAV_SEVERITY_CRITICAL},
      {"MAV_SEVERITY_ERROR", MAV_SEVERITY_ERROR},
      {"MAV_SEVERITY_INFO", MAV_SEVERITY_INFO},
      {"MAV_SEVERITY_NOTICE", MAV_SEVERITY_NOTICE},
      {"MAV_SEVERITY_WARNING", MAV_SEVERITY_WARNING},
      {"MAV_STATE_ACTIVE", MAV_STATE_ACTIVE},
      {"MAV_STATE_BOOT", MAV_STATE_BOOT},
      {"MAV_STATE_CRITICAL", MAV_STATE_CRITICAL},
      {"MAV_STATE_STANDBY", MAV_STATE_STANDBY},
      {"MAV_STATE_UNINIT", MAV_STATE_UNINIT},
      {"MAV_SYS_STATUS_AHRS", MAV_SYS_STATUS_AHRS},
      {"MAV_SYS_STATUS_GEOFENCE", MAV_SYS_STATUS_GEOFENCE},
      {"MAV_SYS_STATUS_SENSOR_3D_ACCEL", MAV_SYS_STATUS_SENSOR_3D_ACCEL},
      {"MAV_SYS_STATUS_SENSOR_3D_GYRO", MAV_SYS_STATUS_SENSOR_3D_GYRO},
      {"MAV_SYS_STATUS_SENSOR_3D_MAG", MAV_SYS_STATUS_SENSOR_3D_MAG},
      {"MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE", MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE},
      {"MAV_SYS_STATUS_SENSOR_ANGULAR_RATE_CONTROL", MAV_SYS_STATUS_SENSOR_ANGULAR_RATE_CONTROL},
      {"MAV_SYS_STATUS_SENSOR_ATTITUDE_STABILIZATION", MAV_SYS_STATUS_SENSOR_ATTITUDE_STABILIZATION},
      {"MAV_SYS_STATUS_SENSOR_DIFFERENTIAL_PRESSURE", MAV_SYS_STATUS_SENSOR_DIFFERENTIAL_PRESSURE},
      {"MAV_SYS_STATUS_SENSOR_GPS", MAV_SYS_STATUS_SENSOR_GPS},
      {"MAV_SYS_STATUS_SENSOR_RC_RECEIVER", MAV_SYS_STATUS_SENSOR_RC_RECEIVER},
      {"MAV_SYS_STATUS_SENSOR_XY_POSITION_CONTROL", MAV_SYS_STATUS_SENSOR_XY_POSITION_CONTROL},
      {"MAV_SYS_STATUS_SENSOR_YAW_POSITION", MAV_SYS_STATUS_SENSOR_YAW_POSITION},
      {"MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL", MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL},
      {"MAV_TYPE_FIXED_WING", MAV_TYPE_FIXED_WING},
      {"MAV_TYPE_GCS", MAV_TYPE_GCS},
      {"MAV_LANDED_STATE_UNDEFINED", MAV_LANDED_STATE_UNDEFINED},
      {"MAV_LANDED_STATE_ON_GROUND", MAV_LANDED_STATE_ON_GROUND},
      {"MAV_LANDED_STATE_IN_AIR", MAV_LANDED_STATE_IN_AIR},
      {"MAV_LANDED_STATE_TAKEOFF", MAV_LANDED_STATE_TAKEOFF},
      {"MAV_LANDED_STATE_LANDING", MAV_LANDED_STATE_LANDING},
      {"MAV_VTOL_STATE_UNDEFINED", MAV_VTOL_STATE_UNDEFINED},
      {"MISSION_STATE_UNKNOWN", MISSION_STATE_UNKNOWN},
      {"MISSION_STATE_NO_MISSION", MISSION_STATE_NO_MISSION},
      {"MISSION_STATE_NOT_STARTED", MISSION_STATE_NOT_STARTED},
      {"MISSION_STATE_ACTIVE", MISSION_STATE_ACTIVE},
      {"MISSION_STATE_COMPLETE", MISSION_STATE_COMPLETE},
  };
  std::ifstream in(std::string(TERN_SOURCE_DIR) + "/tests/mavlink/enums_common.txt");
  REQUIRE(in.good());
  std::string line;
  std::size_t checked = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream row(line);
    std::string name;
    std::uint32_t value = 0;
    row >> name >> value;
    INFO(name);
    REQUIRE(ours.count(name) == 1);
    CHECK(ours.at(name) == value);
    ++checked;
  }
  CHECK(checked == ours.size());
}
