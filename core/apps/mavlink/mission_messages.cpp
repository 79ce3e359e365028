// core/apps/mavlink/mission_messages.cpp: the mission and command messages' wire layouts
// (mission_messages.hpp), at the offsets of tests/mavlink/crc_extra_mission.txt.
#include "mavlink/mission_messages.hpp"

#include "mavlink/wire.hpp"

namespace tern::core::mavlink {

const std::vector<MessageDef>& mission_messages() {
  // id, CRC_EXTRA, full payload length (base plus extensions): tests/mavlink/crc_extra_mission.txt
  static const std::vector<MessageDef> table = {
      {"MISSION_REQUEST", MISSION_REQUEST, 230, 5},
      {"MISSION_SET_CURRENT", MISSION_SET_CURRENT, 28, 4},
      {"MISSION_REQUEST_LIST", MISSION_REQUEST_LIST, 132, 3},
      {"MISSION_COUNT", MISSION_COUNT, 221, 9},
      {"MISSION_CLEAR_ALL", MISSION_CLEAR_ALL, 232, 3},
      {"MISSION_ACK", MISSION_ACK, 153, 8},
      {"MISSION_REQUEST_INT", MISSION_REQUEST_INT, 196, 5},
      {"MISSION_ITEM_INT", MISSION_ITEM_INT, 38, 38},
      {"COMMAND_INT", COMMAND_INT, 158, 35},
      {"COMMAND_LONG", COMMAND_LONG, 152, 33},
      {"COMMAND_ACK", COMMAND_ACK, 143, 10},
      {"AUTOPILOT_VERSION", AUTOPILOT_VERSION, 178, 78},
  };
  return table;
}

std::vector<std::uint8_t> encode(const MissionItemInt& m) {
  Writer w(MISSION_ITEM_INT);
  w.put(m.param1).put(m.param2).put(m.param3).put(m.param4).put(m.x).put(m.y).put(m.z).put(m.seq).put(m.command);
  w.put(m.target_system).put(m.target_component).put(m.frame).put(m.current).put(m.autocontinue).put(m.mission_type);
  return w.done();
}

std::vector<std::uint8_t> encode(const MissionRequest& m) {
  return Writer(MISSION_REQUEST_INT).put(m.seq).put(m.target_system).put(m.target_component).put(m.mission_type).done();
}

std::vector<std::uint8_t> encode(const MissionCount& m) {
  return Writer(MISSION_COUNT).put(m.count).put(m.target_system).put(m.target_component).put(m.mission_type).put(m.opaque_id).done();
}

std::vector<std::uint8_t> encode(const MissionAck& m) {
  return Writer(MISSION_ACK).put(m.target_system).put(m.target_component).put(m.type).put(m.mission_type).put(m.opaque_id).done();
}

std::vector<std::uint8_t> encode(const CommandAck& m) {
  Writer w(COMMAND_ACK);
  w.put(m.command).put(m.result).put(m.progress).put(m.result_param2).put(m.target_system).put(m.target_component);
  return w.done();
}

std::vector<std::uint8_t> encode(const AutopilotVersion& m) {
  Writer w(AUTOPILOT_VERSION);
  w.put(m.capabilities).put(m.uid).put(m.flight_sw_version).put(m.middleware_sw_version).put(m.os_sw_version).put(m.board_version);
  w.put(m.vendor_id).put(m.product_id);
  return w.done();  // the custom version bytes and uid2: none
}

MissionItemInt decode_mission_item_int(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  MissionItemInt m;
  m.param1 = r.get<float>();
  m.param2 = r.get<float>();
  m.param3 = r.get<float>();
  m.param4 = r.get<float>();
  m.x = r.get<std::int32_t>();
  m.y = r.get<std::int32_t>();
  m.z = r.get<float>();
  m.seq = r.get<std::uint16_t>();
  m.command = r.get<std::uint16_t>();
  m.target_system = r.get<std::uint8_t>();
  m.target_component = r.get<std::uint8_t>();
  m.frame = r.get<std::uint8_t>();
  m.current = r.get<std::uint8_t>();
  m.autocontinue = r.get<std::uint8_t>();
  m.mission_type = r.get<std::uint8_t>();
  return m;
}

MissionRequest decode_mission_request(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  MissionRequest m;
  m.seq = r.get<std::uint16_t>();
  m.target_system = r.get<std::uint8_t>();
  m.target_component = r.get<std::uint8_t>();
  m.mission_type = r.get<std::uint8_t>();
  return m;
}

MissionSetCurrent decode_mission_set_current(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  MissionSetCurrent m;
  m.seq = r.get<std::uint16_t>();
  m.target_system = r.get<std::uint8_t>();
  m.target_component = r.get<std::uint8_t>();
  return m;
}

MissionTarget decode_mission_target(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  MissionTarget m;
  m.target_system = r.get<std::uint8_t>();
  m.target_component = r.get<std::uint8_t>();
  m.mission_type = r.get<std::uint8_t>();
  return m;
}

MissionCount decode_mission_count(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  MissionCount m;
  m.count = r.get<std::uint16_t>();
  m.target_system = r.get<std::uint8_t>();
  m.target_component = r.get<std::uint8_t>();
  m.mission_type = r.get<std::uint8_t>();
  m.opaque_id = r.get<std::uint32_t>();
  return m;
}

MissionAck decode_mission_ack(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  MissionAck m;
  m.target_system = r.get<std::uint8_t>();
  m.target_component = r.get<std::uint8_t>();
  m.type = r.get<std::uint8_t>();
  m.mission_type = r.get<std::uint8_t>();
  m.opaque_id = r.get<std::uint32_t>();
  return m;
}

CommandLong decode_command_long(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  CommandLong m;
  for (float& v : m.param) v = r.get<float>();
  m.command = r.get<std::uint16_t>();
  m.target_system = r.get<std::uint8_t>();
  m.target_component = r.get<std::uint8_t>();
  m.confirmation = r.get<std::uint8_t>();
  return m;
}

CommandInt decode_command_int(const std::vector<std::uint8_t>& p) {
  Reader r(p);
  CommandInt m;
  for (float& v : m.param) v = r.get<float>();
  m.x = r.get<std::int32_t>();
  m.y = r.get<std::int32_t>();
  m.z = r.get<float>();
  m.command = r.get<std::uint16_t>();
  m.target_system = r.get<std::uint8_t>();
  m.target_component = r.get<std::uint8_t>();
  m.frame = r.get<std::uint8_t>();
  m.current = r.get<std::uint8_t>();
  m.autocontinue = r.get<std::uint8_t>();
  return m;
}

}  // namespace tern::core::mavlink
