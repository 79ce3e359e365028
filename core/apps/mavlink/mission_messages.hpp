// core/apps/mavlink/mission_messages.hpp: the enum values of the mission protocol
// (https://mavlink.io/en/services/mission.html) and the command protocol
// (https://mavlink.io/en/services/command.html) that tern uses. Their messages (MISSION_*,
// COMMAND_*, AUTOPILOT_VERSION) are structs generated from common.xml (mavlink/common_messages.hpp,
// through mavlink_messages.hpp).
//
// Source: github.com/mavlink/mavlink message_definitions/v1.0/common.xml at commit de1e078a. The
// enum values are checked against tests/mavlink/enums_mission.txt and the generated CRC_EXTRA
// values and lengths against tests/mavlink/crc_extra_mission.txt (both from
// tests/mavlink/crc_extra_from_xml.py) by core/apps/mavlink/tests/test_mission_items.cpp.
#pragma once

#include <cstdint>

#include "mavlink/mavlink_messages.hpp"

namespace tern::core::mavlink {

// MAV_CMD: the mission items and commands tern takes
inline constexpr std::uint16_t MAV_CMD_NAV_WAYPOINT = 16, MAV_CMD_NAV_LOITER_UNLIM = 17, MAV_CMD_NAV_LOITER_TURNS = 18,
                               MAV_CMD_NAV_LOITER_TIME = 19, MAV_CMD_NAV_RETURN_TO_LAUNCH = 20, MAV_CMD_NAV_LAND = 21,
                               MAV_CMD_NAV_TAKEOFF = 22, MAV_CMD_NAV_LOITER_TO_ALT = 31, MAV_CMD_DO_SET_MODE = 176, MAV_CMD_DO_JUMP = 177,
                               MAV_CMD_DO_CHANGE_SPEED = 178, MAV_CMD_DO_SET_HOME = 179, MAV_CMD_DO_LAND_START = 189,
                               MAV_CMD_DO_GO_AROUND = 191, MAV_CMD_DO_REPOSITION = 192, MAV_CMD_MISSION_START = 300,
                               MAV_CMD_COMPONENT_ARM_DISARM = 400, MAV_CMD_SET_MESSAGE_INTERVAL = 511, MAV_CMD_REQUEST_MESSAGE = 512,
                               MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES = 520, MAV_CMD_NAV_FENCE_RETURN_POINT = 5000,
                               MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION = 5001, MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION = 5002,
                               MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION = 5003, MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION = 5004,
                               MAV_CMD_NAV_RALLY_POINT = 5100;
// MAV_FRAME (GLOBAL and GLOBAL_RELATIVE_ALT carry degE7 in the _INT messages, as GLOBAL_INT and
// GLOBAL_RELATIVE_ALT_INT, which common.xml deprecates in their favour)
inline constexpr std::uint8_t MAV_FRAME_GLOBAL = 0, MAV_FRAME_MISSION = 2, MAV_FRAME_GLOBAL_RELATIVE_ALT = 3, MAV_FRAME_GLOBAL_INT = 5,
                              MAV_FRAME_GLOBAL_RELATIVE_ALT_INT = 6, MAV_FRAME_GLOBAL_TERRAIN_ALT = 10,
                              MAV_FRAME_GLOBAL_TERRAIN_ALT_INT = 11;
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
                               MAV_PROTOCOL_CAPABILITY_MAVLINK2 = 8192, MAV_PROTOCOL_CAPABILITY_MISSION_FENCE = 16384,
                               MAV_PROTOCOL_CAPABILITY_MISSION_RALLY = 32768;

}  // namespace tern::core::mavlink
