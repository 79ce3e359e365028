// core/apps/mavlink/mavlink_messages.cpp: the messages' wire layouts (mavlink_messages.hpp); each
// encoder writes its fields at the offsets of tests/mavlink/crc_extra_common.txt.
#include "mavlink/mavlink_messages.hpp"

#include <algorithm>
#include <cstring>

#include "mavlink/mavlink_codec.hpp"
#include "mavlink/mission_messages.hpp"
#include "mavlink/wire.hpp"

namespace tern::core::mavlink {

const std::vector<MessageDef>& known_messages() {
  // id, CRC_EXTRA, full payload length: tests/mavlink/crc_extra_common.txt (base length, plus the
  // extension fields' bytes where a message has them)
  static const std::vector<MessageDef> table = {
      {"HEARTBEAT", HEARTBEAT, 50, 9},
      {"SYS_STATUS", SYS_STATUS, 124, 43},
      {"SYSTEM_TIME", SYSTEM_TIME, 137, 12},
      {"PARAM_REQUEST_READ", PARAM_REQUEST_READ, 214, 20},
      {"PARAM_REQUEST_LIST", PARAM_REQUEST_LIST, 159, 2},
      {"PARAM_VALUE", PARAM_VALUE, 220, 25},
      {"PARAM_SET", PARAM_SET, 168, 23},
      {"GPS_RAW_INT", GPS_RAW_INT, 24, 52},
      {"ATTITUDE", ATTITUDE, 39, 28},
      {"GLOBAL_POSITION_INT", GLOBAL_POSITION_INT, 104, 28},
      {"MISSION_CURRENT", MISSION_CURRENT, 28, 18},
      {"NAV_CONTROLLER_OUTPUT", NAV_CONTROLLER_OUTPUT, 183, 26},
      {"VFR_HUD", VFR_HUD, 20, 20},
      {"TIMESYNC", TIMESYNC, 34, 18},
      {"WIND_COV", WIND_COV, 105, 40},
      {"HOME_POSITION", HOME_POSITION, 104, 60},
      {"EXTENDED_SYS_STATE", EXTENDED_SYS_STATE, 130, 2},
      {"STATUSTEXT", STATUSTEXT, 83, 54},
  };
  return table;
}

std::optional<MessageInfo> message_info(std::uint32_t msgid) {
  for (const auto& m : known_messages())
    if (m.id == msgid) return MessageInfo{m.crc_extra, m.length};
  for (const auto& m : mission_messages())  // mission_messages.hpp
    if (m.id == msgid) return MessageInfo{m.crc_extra, m.length};
  return std::nullopt;
}

std::vector<std::uint8_t> encode(const Heartbeat& m) {
  return Writer(HEARTBEAT)
      .put(m.custom_mode)
      .put(m.type)
      .put(m.autopilot)
      .put(m.base_mode)
      .put(m.system_status)
      .put(m.mavlink_version)
      .done();
}

std::vector<std::uint8_t> encode(const SysStatus& m) {
  Writer w(SYS_STATUS);
  w.put(m.present).put(m.enabled).put(m.health).put(m.load).put(m.voltage_battery).put(m.current_battery).put(m.drop_rate_comm);
  w.put(m.errors_comm).put(std::uint16_t{0}).put(std::uint16_t{0}).put(std::uint16_t{0}).put(std::uint16_t{0});  // errors_count1-4
  w.put(m.battery_remaining);
  return w.done();  // the *_extended fields: none of those sensors
}

std::vector<std::uint8_t> encode(const GpsRawInt& m) {
  Writer w(GPS_RAW_INT);
  w.put(m.time_usec).put(m.lat).put(m.lon).put(m.alt).put(m.eph).put(m.epv).put(m.vel).put(m.cog).put(m.fix_type).put(m.satellites_visible);
  return w.done();
}

std::vector<std::uint8_t> encode(const Attitude& m) {
  return Writer(ATTITUDE).put(m.time_boot_ms).put(m.roll).put(m.pitch).put(m.yaw).put(m.rollspeed).put(m.pitchspeed).put(m.yawspeed).done();
}

std::vector<std::uint8_t> encode(const GlobalPositionInt& m) {
  return Writer(GLOBAL_POSITION_INT)
      .put(m.time_boot_ms)
      .put(m.lat)
      .put(m.lon)
      .put(m.alt)
      .put(m.relative_alt)
      .put(m.vx)
      .put(m.vy)
      .put(m.vz)
      .put(m.hdg)
      .done();
}

std::vector<std::uint8_t> encode(const VfrHud& m) {
  return Writer(VFR_HUD).put(m.airspeed).put(m.groundspeed).put(m.alt).put(m.climb).put(m.heading).put(m.throttle).done();
}

std::vector<std::uint8_t> encode(const HomePosition& m) {
  Writer w(HOME_POSITION);
  w.put(m.latitude).put(m.longitude).put(m.altitude).put(m.x).put(m.y).put(m.z);
  for (float q : m.q) w.put(q);
  w.put(m.approach_x).put(m.approach_y).put(m.approach_z);
  return w.done();  // time_usec (extension): not sent
}

std::vector<std::uint8_t> encode(const ParamValueMsg& m) {
  return Writer(PARAM_VALUE).put(m.param_value).put(m.param_count).put(m.param_index).text(m.param_id, 16).put(m.param_type).done();
}

std::vector<std::uint8_t> encode(const StatusText& m) {
  return Writer(STATUSTEXT).put(m.severity).text(m.text.substr(0, 50), 50).put(m.id).put(m.chunk_seq).done();
}

std::vector<std::uint8_t> encode(const SystemTime& m) { return Writer(SYSTEM_TIME).put(m.time_unix_usec).put(m.time_boot_ms).done(); }

std::vector<std::uint8_t> encode(const MissionCurrent& m) {
  // extensions: mission_state, mission_mode, then the plan ids (0: not supported)
  return Writer(MISSION_CURRENT).put(m.seq).put(m.total).put(m.mission_state).put(m.mission_mode).done();
}

std::vector<std::uint8_t> encode(const NavControllerOutput& m) {
  return Writer(NAV_CONTROLLER_OUTPUT)
      .put(m.nav_roll)
      .put(m.nav_pitch)
      .put(m.alt_error)
      .put(m.aspd_error)
      .put(m.xtrack_error)
      .put(m.nav_bearing)
      .put(m.target_bearing)
      .put(m.wp_dist)
      .done();
}

std::vector<std::uint8_t> encode(const Timesync& m) {
  return Writer(TIMESYNC).put(m.tc1).put(m.ts1).put(m.target_system).put(m.target_component).done();
}

std::vector<std::uint8_t> encode(const WindCov& m) {
  return Writer(WIND_COV)
      .put(m.time_usec)
      .put(m.wind_x)
      .put(m.wind_y)
      .put(m.wind_z)
      .put(m.var_horiz)
      .put(m.var_vert)
      .put(m.wind_alt)
      .put(m.horiz_accuracy)
      .put(m.vert_accuracy)
      .done();
}

std::vector<std::uint8_t> encode(const ExtendedSysState& m) {
  return Writer(EXTENDED_SYS_STATE).put(m.vtol_state).put(m.landed_state).done();
}

std::vector<StatusText> statustext_chunks(std::uint8_t severity, const std::string& text, std::uint16_t id) {
  if (text.size() <= 50) return {StatusText{severity, text, 0, 0}};
  std::vector<StatusText> out;
  for (std::size_t at = 0; at < text.size() && out.size() < 255; at += 50)
    out.push_back({severity, text.substr(at, 50), id, static_cast<std::uint8_t>(out.size())});
  if (text.size() % 50 == 0 && out.size() < 256) out.push_back({severity, "", id, static_cast<std::uint8_t>(out.size())});
  return out;
}

std::vector<std::uint8_t> encode(const ParamRequestRead& m) {
  return Writer(PARAM_REQUEST_READ).put(m.param_index).put(m.target_system).put(m.target_component).text(m.param_id, 16).done();
}

std::vector<std::uint8_t> encode(const ParamRequestList& m) {
  return Writer(PARAM_REQUEST_LIST).put(m.target_system).put(m.target_component).done();
}

std::vector<std::uint8_t> encode(const ParamSet& m) {
  return Writer(PARAM_SET).put(m.param_value).put(m.target_system).put(m.target_component).text(m.param_id, 16).put(m.param_type).done();
}

Heartbeat decode_heartbeat(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  Heartbeat m;
  m.custom_mode = r.get<std::uint32_t>();
  m.type = r.get<std::uint8_t>();
  m.autopilot = r.get<std::uint8_t>();
  m.base_mode = r.get<std::uint8_t>();
  m.system_status = r.get<std::uint8_t>();
  m.mavlink_version = r.get<std::uint8_t>();
  return m;
}

ParamRequestRead decode_param_request_read(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  ParamRequestRead m;
  m.param_index = r.get<std::int16_t>();
  m.target_system = r.get<std::uint8_t>();
  m.target_component = r.get<std::uint8_t>();
  m.param_id = r.text(16);
  return m;
}

ParamRequestList decode_param_request_list(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  ParamRequestList m;
  m.target_system = r.get<std::uint8_t>();
  m.target_component = r.get<std::uint8_t>();
  return m;
}

ParamSet decode_param_set(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  ParamSet m;
  m.param_value = r.get<float>();
  m.target_system = r.get<std::uint8_t>();
  m.target_component = r.get<std::uint8_t>();
  m.param_id = r.text(16);
  m.param_type = r.get<std::uint8_t>();
  return m;
}

ParamValueMsg decode_param_value(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  ParamValueMsg m;
  m.param_value = r.get<float>();
  m.param_count = r.get<std::uint16_t>();
  m.param_index = r.get<std::uint16_t>();
  m.param_id = r.text(16);
  m.param_type = r.get<std::uint8_t>();
  return m;
}

Timesync decode_timesync(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  Timesync m;
  m.tc1 = r.get<std::int64_t>();
  m.ts1 = r.get<std::int64_t>();
  m.target_system = r.get<std::uint8_t>();
  m.target_component = r.get<std::uint8_t>();
  return m;
}

}  // namespace tern::core::mavlink
