// core/apps/mavlink/mavlink_enums.hpp: the values of common.xml's and minimal.xml's enums that the
// ground-station endpoint sends and reads (MAV_TYPE, MAV_MODE_FLAG, MAV_STATE, MAV_PARAM_TYPE,
// MAV_SEVERITY, ...), as plain constants, so that `tern params --mavlink` reads them without the
// generated messages.
//
// Source: github.com/mavlink/mavlink message_definitions/v1.0/common.xml at commit de1e078a
// (sdk/mavlink/message_definitions/); checked against tests/mavlink/enums_common.txt by
// core/apps/mavlink/tests/test_mavlink_codec.cpp.
#pragma once

#include <cstdint>

namespace tern::core::mavlink {

// Enums (common.xml / minimal.xml), the values tern uses; checked against the XML's by the unit test
// (tests/mavlink/enums_common.txt, from crc_extra_from_xml.py --entries)
inline constexpr std::uint8_t MAV_TYPE_FIXED_WING = 1, MAV_TYPE_GCS = 6;
inline constexpr std::uint8_t MAV_AUTOPILOT_GENERIC = 0;
inline constexpr std::uint8_t MAV_MODE_FLAG_CUSTOM_MODE_ENABLED = 1, MAV_MODE_FLAG_AUTO_ENABLED = 4, MAV_MODE_FLAG_GUIDED_ENABLED = 8,
                              MAV_MODE_FLAG_STABILIZE_ENABLED = 16, MAV_MODE_FLAG_MANUAL_INPUT_ENABLED = 64,
                              MAV_MODE_FLAG_SAFETY_ARMED = 128;
inline constexpr std::uint8_t MAV_STATE_UNINIT = 0, MAV_STATE_BOOT = 1, MAV_STATE_STANDBY = 3, MAV_STATE_ACTIVE = 4, MAV_STATE_CRITICAL = 5;
inline constexpr std::uint8_t MAV_COMP_ID_AUTOPILOT1 = 1;
inline constexpr std::uint8_t MAV_PARAM_TYPE_UINT8 = 1, MAV_PARAM_TYPE_INT32 = 6, MAV_PARAM_TYPE_REAL32 = 9;
inline constexpr std::uint8_t MAV_SEVERITY_CRITICAL = 2, MAV_SEVERITY_ERROR = 3, MAV_SEVERITY_WARNING = 4, MAV_SEVERITY_NOTICE = 5,
                              MAV_SEVERITY_INFO = 6;
inline constexpr std::uint8_t GPS_FIX_TYPE_NO_GPS = 0, GPS_FIX_TYPE_NO_FIX = 1, GPS_FIX_TYPE_2D_FIX = 2, GPS_FIX_TYPE_3D_FIX = 3;
inline constexpr std::uint8_t MAV_LANDED_STATE_UNDEFINED = 0, MAV_LANDED_STATE_ON_GROUND = 1, MAV_LANDED_STATE_IN_AIR = 2,
                              MAV_LANDED_STATE_TAKEOFF = 3, MAV_LANDED_STATE_LANDING = 4;
inline constexpr std::uint8_t MAV_VTOL_STATE_UNDEFINED = 0;
inline constexpr std::uint8_t MISSION_STATE_UNKNOWN = 0, MISSION_STATE_NO_MISSION = 1, MISSION_STATE_NOT_STARTED = 2,
                              MISSION_STATE_ACTIVE = 3, MISSION_STATE_COMPLETE = 5;
// MAV_SYS_STATUS_SENSOR bits
inline constexpr std::uint32_t MAV_SYS_STATUS_SENSOR_3D_GYRO = 1, MAV_SYS_STATUS_SENSOR_3D_ACCEL = 2, MAV_SYS_STATUS_SENSOR_3D_MAG = 4,
                               MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE = 8, MAV_SYS_STATUS_SENSOR_DIFFERENTIAL_PRESSURE = 16,
                               MAV_SYS_STATUS_SENSOR_GPS = 32, MAV_SYS_STATUS_SENSOR_ANGULAR_RATE_CONTROL = 1024,
                               MAV_SYS_STATUS_SENSOR_ATTITUDE_STABILIZATION = 2048, MAV_SYS_STATUS_SENSOR_YAW_POSITION = 4096,
                               MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL = 8192, MAV_SYS_STATUS_SENSOR_XY_POSITION_CONTROL = 16384,
                               MAV_SYS_STATUS_AHRS = 0x200000, MAV_SYS_STATUS_SENSOR_RC_RECEIVER = 65536,
                               MAV_SYS_STATUS_GEOFENCE = 0x100000;

}  // namespace tern::core::mavlink
