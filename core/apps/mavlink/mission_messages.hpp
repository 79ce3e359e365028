// core/apps/mavlink/mission_messages.hpp: the common-dialect messages of the mission protocol
// (https://mavlink.io/en/services/mission.html) and the command protocol
// (https://mavlink.io/en/services/command.html), and AUTOPILOT_VERSION, as plain structs packed in
// MAVLink's wire order (wire.hpp).
//
// Source: github.com/mavlink/mavlink message_definitions/v1.0/common.xml at commit de1e078a; field
// names and units are the XML's. CRC_EXTRA values and layouts: tests/mavlink/crc_extra_mission.txt
// and the enum values tests/mavlink/enums_mission.txt (both from tests/mavlink/crc_extra_from_xml.py),
// checked against this file by core/apps/mavlink/tests/test_mission_items.cpp.
//
// Errors: none thrown; decode_* read a full-length (zero-filled) payload, as parse_datagram gives.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "mavlink/mavlink_messages.hpp"

namespace tern::core::mavlink {

// Message ids (common.xml)
inline constexpr std::uint32_t MISSION_REQUEST = 40, MISSION_SET_CURRENT = 41, MISSION_REQUEST_LIST = 43, MISSION_COUNT = 44,
                               MISSION_CLEAR_ALL = 45, MISSION_ACK = 47, MISSION_REQUEST_INT = 51, MISSION_ITEM_INT = 73, COMMAND_INT = 75,
                               COMMAND_LONG = 76, COMMAND_ACK = 77, AUTOPILOT_VERSION = 148;

// MAV_CMD: the mission items and commands tern takes
inline constexpr std::uint16_t MAV_CMD_NAV_WAYPOINT = 16, MAV_CMD_NAV_LOITER_UNLIM = 17, MAV_CMD_NAV_LOITER_TURNS = 18,
                               MAV_CMD_NAV_LOITER_TIME = 19, MAV_CMD_NAV_RETURN_TO_LAUNCH = 20, MAV_CMD_NAV_LAND = 21,
                               MAV_CMD_NAV_TAKEOFF = 22, MAV_CMD_DO_SET_MODE = 176, MAV_CMD_DO_CHANGE_SPEED = 178,
                               MAV_CMD_DO_LAND_START = 189, MAV_CMD_DO_GO_AROUND = 191, MAV_CMD_DO_REPOSITION = 192,
                               MAV_CMD_MISSION_START = 300, MAV_CMD_COMPONENT_ARM_DISARM = 400, MAV_CMD_SET_MESSAGE_INTERVAL = 511,
                               MAV_CMD_REQUEST_MESSAGE = 512, MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES = 520;
// MAV_FRAME (GLOBAL and GLOBAL_RELATIVE_ALT carry degE7 in the _INT messages, as GLOBAL_INT and
// GLOBAL_RELATIVE_ALT_INT, which common.xml deprecates in their favour)
inline constexpr std::uint8_t MAV_FRAME_GLOBAL = 0, MAV_FRAME_MISSION = 2, MAV_FRAME_GLOBAL_RELATIVE_ALT = 3, MAV_FRAME_GLOBAL_INT = 5,
                              MAV_FRAME_GLOBAL_RELATIVE_ALT_INT = 6;
inline constexpr std::uint8_t MAV_MISSION_TYPE_MISSION = 0, MAV_MISSION_TYPE_FENCE = 1, MAV_MISSION_TYPE_RALLY = 2,
                              MAV_MISSION_TYPE_ALL = 255;
// MAV_MISSION_RESULT
inline constexpr std::uint8_t MAV_MISSION_ACCEPTED = 0, MAV_MISSION_ERROR = 1, MAV_MISSION_UNSUPPORTED_FRAME = 2,
                              MAV_MISSION_UNSUPPORTED = 3, MAV_MISSION_NO_SPACE = 4, MAV_MISSION_INVALID = 5,
                              MAV_MISSION_INVALID_PARAM1 = 6, MAV_MISSION_INVALID_PARAM2 = 7, MAV_MISSION_INVALID_PARAM3 = 8,
                              MAV_MISSION_INVALID_PARAM4 = 9, MAV_MISSION_INVALID_PARAM5_X = 10, MAV_MISSION_INVALID_PARAM6_Y = 11,
                              MAV_MISSION_INVALID_PARAM7 = 12, MAV_MISSION_INVALID_SEQUENCE = 13, MAV_MISSION_DENIED = 14,
                              MAV_MISSION_OPERATION_CANCELLED = 15;
// MAV_RESULT
inline constexpr std::uint8_t MAV_RESULT_ACCEPTED = 0, MAV_RESULT_TEMPORARILY_REJECTED = 1, MAV_RESULT_DENIED = 2,
                              MAV_RESULT_UNSUPPORTED = 3, MAV_RESULT_FAILED = 4;
// MAV_PROTOCOL_CAPABILITY bits
inline constexpr std::uint64_t MAV_PROTOCOL_CAPABILITY_MISSION_FLOAT = 1, MAV_PROTOCOL_CAPABILITY_PARAM_FLOAT = 2,
                               MAV_PROTOCOL_CAPABILITY_MISSION_INT = 4, MAV_PROTOCOL_CAPABILITY_COMMAND_INT = 8,
                               MAV_PROTOCOL_CAPABILITY_MAVLINK2 = 8192;

/// The rows message_info() adds for these messages: name, id, CRC_EXTRA, full payload length.
const std::vector<MessageDef>& mission_messages();

/// MISSION_ITEM_INT (73): one mission item. x, y: latitude, longitude degE7 in the global frames;
/// z: altitude m (MSL in GLOBAL(_INT), above home in GLOBAL_RELATIVE_ALT(_INT)); param1-4 as the
/// command (MAV_CMD) defines them.
struct MissionItemInt {
  float param1 = 0, param2 = 0, param3 = 0, param4 = 0;
  std::int32_t x = 0, y = 0;
  float z = 0;
  std::uint16_t seq = 0, command = 0;
  std::uint8_t target_system = 0, target_component = 0, frame = 0, current = 0, autocontinue = 1;
  std::uint8_t mission_type = MAV_MISSION_TYPE_MISSION;
};
/// MISSION_REQUEST (40, deprecated: answered with MISSION_ITEM_INT) and MISSION_REQUEST_INT (51).
struct MissionRequest {
  std::uint16_t seq = 0;
  std::uint8_t target_system = 0, target_component = 0, mission_type = MAV_MISSION_TYPE_MISSION;
};
/// MISSION_SET_CURRENT (41)
struct MissionSetCurrent {
  std::uint16_t seq = 0;
  std::uint8_t target_system = 0, target_component = 0;
};
/// MISSION_REQUEST_LIST (43) and MISSION_CLEAR_ALL (45): the same fields.
struct MissionTarget {
  std::uint8_t target_system = 0, target_component = 0, mission_type = MAV_MISSION_TYPE_MISSION;
};
/// MISSION_COUNT (44); opaque_id 0: tern does not version its missions.
struct MissionCount {
  std::uint16_t count = 0;
  std::uint8_t target_system = 0, target_component = 0, mission_type = MAV_MISSION_TYPE_MISSION;
  std::uint32_t opaque_id = 0;
};
/// MISSION_ACK (47): type is a MAV_MISSION_RESULT.
struct MissionAck {
  std::uint8_t target_system = 0, target_component = 0, type = MAV_MISSION_ACCEPTED, mission_type = MAV_MISSION_TYPE_MISSION;
  std::uint32_t opaque_id = 0;
};
/// COMMAND_LONG (76): param5-7 are x, y, z of a positional command (latitude and longitude in
/// degrees, not degE7).
struct CommandLong {
  std::array<float, 7> param{};  ///< param1 .. param7
  std::uint16_t command = 0;
  std::uint8_t target_system = 0, target_component = 0, confirmation = 0;
};
/// COMMAND_INT (75): x, y degE7 in the global frames, z m.
struct CommandInt {
  std::array<float, 4> param{};  ///< param1 .. param4
  std::int32_t x = 0, y = 0;
  float z = 0;
  std::uint16_t command = 0;
  std::uint8_t target_system = 0, target_component = 0, frame = 0, current = 0, autocontinue = 0;
};
/// COMMAND_ACK (77): result is a MAV_RESULT.
struct CommandAck {
  std::uint16_t command = 0;
  std::uint8_t result = MAV_RESULT_ACCEPTED, progress = 0;
  std::int32_t result_param2 = 0;
  std::uint8_t target_system = 0, target_component = 0;
};
/// AUTOPILOT_VERSION (148): capabilities (MAV_PROTOCOL_CAPABILITY bits), versions, uid.
struct AutopilotVersion {
  std::uint64_t capabilities = 0, uid = 0;
  std::uint32_t flight_sw_version = 0, middleware_sw_version = 0, os_sw_version = 0, board_version = 0;
  std::uint16_t vendor_id = 0, product_id = 0;
};

std::vector<std::uint8_t> encode(const MissionItemInt& m);
std::vector<std::uint8_t> encode(const MissionRequest& m);  ///< as MISSION_REQUEST_INT
std::vector<std::uint8_t> encode(const MissionCount& m);
std::vector<std::uint8_t> encode(const MissionAck& m);
std::vector<std::uint8_t> encode(const CommandAck& m);
std::vector<std::uint8_t> encode(const AutopilotVersion& m);

MissionItemInt decode_mission_item_int(const std::vector<std::uint8_t>& p);
MissionRequest decode_mission_request(const std::vector<std::uint8_t>& p);  ///< MISSION_REQUEST or _INT: one layout
MissionSetCurrent decode_mission_set_current(const std::vector<std::uint8_t>& p);
MissionTarget decode_mission_target(const std::vector<std::uint8_t>& p);  ///< MISSION_REQUEST_LIST or MISSION_CLEAR_ALL
MissionCount decode_mission_count(const std::vector<std::uint8_t>& p);
MissionAck decode_mission_ack(const std::vector<std::uint8_t>& p);
CommandLong decode_command_long(const std::vector<std::uint8_t>& p);
CommandInt decode_command_int(const std::vector<std::uint8_t>& p);

}  // namespace tern::core::mavlink
