// core/apps/mavlink/mavlink_messages.hpp: the common-dialect messages tern sends and reads, as plain
// structs with their payloads packed in MAVLink's wire order (fields sorted by type size, largest
// first; extensions after, in XML order: https://mavlink.io/en/guide/serialization.html#field_reordering).
//
// Source: github.com/mavlink/mavlink message_definitions/v1.0/common.xml (and the standard.xml and
// minimal.xml it includes) at commit de1e078a; each struct names its message and id. Field names
// and units are the XML's. CRC_EXTRA values and layouts: tests/mavlink/crc_extra_common.txt, made
// by tests/mavlink/crc_extra_from_xml.py from that XML and checked against this table by the unit
// test (core/apps/mavlink/tests/test_mavlink_codec.cpp).
//
// Errors: none thrown; decode_* read a full-length (zero-filled) payload, as parse_datagram gives.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace tern::core::mavlink {

// Message ids (common.xml)
inline constexpr std::uint32_t HEARTBEAT = 0, SYS_STATUS = 1, SYSTEM_TIME = 2, PARAM_REQUEST_READ = 20, PARAM_REQUEST_LIST = 21,
                               PARAM_VALUE = 22, PARAM_SET = 23, GPS_RAW_INT = 24, ATTITUDE = 30, GLOBAL_POSITION_INT = 33,
                               MISSION_CURRENT = 42, NAV_CONTROLLER_OUTPUT = 62, VFR_HUD = 74, TIMESYNC = 111, WIND_COV = 231,
                               HOME_POSITION = 242, EXTENDED_SYS_STATE = 245, STATUSTEXT = 253;

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
                               MAV_SYS_STATUS_AHRS = 0x200000, MAV_SYS_STATUS_SENSOR_RC_RECEIVER = 65536;

/// One row of the table behind message_info(): name, id, CRC_EXTRA, full payload length.
struct MessageDef {
  const char* name;
  std::uint32_t id;
  std::uint8_t crc_extra;
  std::uint8_t length;
};
/// Every message tern knows, in id order.
const std::vector<MessageDef>& known_messages();

/// HEARTBEAT (0, minimal.xml)
struct Heartbeat {
  std::uint32_t custom_mode = 0;
  std::uint8_t type = 0, autopilot = 0, base_mode = 0, system_status = 0, mavlink_version = 3;
};
/// SYS_STATUS (1): the sensors and controls present, enabled and healthy (MAV_SYS_STATUS_SENSOR),
/// load in d%, battery (UINT16_MAX / -1: not sent), link drops in c% and error counts.
struct SysStatus {
  std::uint32_t present = 0, enabled = 0, health = 0;
  std::uint16_t load = 0, voltage_battery = UINT16_MAX;
  std::int16_t current_battery = -1;
  std::uint16_t drop_rate_comm = 0, errors_comm = 0;
  std::int8_t battery_remaining = -1;
};
/// GPS_RAW_INT (24): lat, lon degE7, alt mm MSL, eph/epv (HDOP/VDOP x100, UINT16_MAX unknown),
/// vel cm/s, cog cdeg (UINT16_MAX unknown); base fields only.
struct GpsRawInt {
  std::uint64_t time_usec = 0;
  std::int32_t lat = 0, lon = 0, alt = 0;
  std::uint16_t eph = UINT16_MAX, epv = UINT16_MAX, vel = UINT16_MAX, cog = UINT16_MAX;
  std::uint8_t fix_type = 0, satellites_visible = UINT8_MAX;
};
/// ATTITUDE (30): rad, rad/s, time_boot_ms.
struct Attitude {
  std::uint32_t time_boot_ms = 0;
  float roll = 0, pitch = 0, yaw = 0, rollspeed = 0, pitchspeed = 0, yawspeed = 0;
};
/// GLOBAL_POSITION_INT (33): degE7, mm (alt MSL, relative_alt above home), cm/s NED, hdg cdeg.
struct GlobalPositionInt {
  std::uint32_t time_boot_ms = 0;
  std::int32_t lat = 0, lon = 0, alt = 0, relative_alt = 0;
  std::int16_t vx = 0, vy = 0, vz = 0;
  std::uint16_t hdg = UINT16_MAX;
};
/// VFR_HUD (74): m/s, m MSL, m/s up, deg [0, 360), throttle %.
struct VfrHud {
  float airspeed = 0, groundspeed = 0, alt = 0, climb = 0;
  std::int16_t heading = 0;
  std::uint16_t throttle = 0;
};
/// HOME_POSITION (242): degE7, mm MSL, local x y z (m), q (w, x, y, z), approach vector (m).
struct HomePosition {
  std::int32_t latitude = 0, longitude = 0, altitude = 0;
  float x = 0, y = 0, z = 0;
  std::array<float, 4> q{1, 0, 0, 0};
  float approach_x = 0, approach_y = 0, approach_z = 0;
};
/// SYSTEM_TIME (2): UNIX time (us; 0: unknown) and time since boot (ms).
struct SystemTime {
  std::uint64_t time_unix_usec = 0;
  std::uint32_t time_boot_ms = 0;
};
/// MISSION_CURRENT (42): the item flown to, the items on the vehicle (UINT16_MAX: unknown), the
/// mission's state (MISSION_STATE) and mode (0 unknown, 1 in mission, 2 suspended); ids 0: none.
struct MissionCurrent {
  std::uint16_t seq = 0, total = UINT16_MAX;
  std::uint8_t mission_state = MISSION_STATE_UNKNOWN, mission_mode = 0;
};
/// NAV_CONTROLLER_OUTPUT (62): deg, deg, m, m/s, m; bearings deg; wp_dist m.
struct NavControllerOutput {
  float nav_roll = 0, nav_pitch = 0, alt_error = 0, aspd_error = 0, xtrack_error = 0;
  std::int16_t nav_bearing = 0, target_bearing = 0;
  std::uint16_t wp_dist = 0;
};
/// TIMESYNC (111): a request has tc1 0; the answer carries the responder's time in tc1 and the
/// request's ts1, addressed to the requester (ns).
struct Timesync {
  std::int64_t tc1 = 0, ts1 = 0;
  std::uint8_t target_system = 0, target_component = 0;
};
/// WIND_COV (231): wind NED (m/s, NaN unknown), variability 1-STD (m/s, NaN unknown), altitude
/// MSL (m), accuracies 1-STD (m/s, 0 unknown); time_usec since boot.
struct WindCov {
  std::uint64_t time_usec = 0;
  float wind_x = 0, wind_y = 0, wind_z = 0, var_horiz = 0, var_vert = 0, wind_alt = 0, horiz_accuracy = 0, vert_accuracy = 0;
};
/// EXTENDED_SYS_STATE (245): MAV_VTOL_STATE, MAV_LANDED_STATE.
struct ExtendedSysState {
  std::uint8_t vtol_state = MAV_VTOL_STATE_UNDEFINED, landed_state = MAV_LANDED_STATE_UNDEFINED;
};
/// PARAM_VALUE (22)
struct ParamValueMsg {
  std::string param_id;  ///< up to 16 chars
  float param_value = 0;
  std::uint8_t param_type = MAV_PARAM_TYPE_REAL32;
  std::uint16_t param_count = 0, param_index = 0;
};
/// STATUSTEXT (253): one chunk of up to 50 chars; id 0: the only chunk (statustext_chunks()).
struct StatusText {
  std::uint8_t severity = MAV_SEVERITY_INFO;
  std::string text;
  std::uint16_t id = 0;        ///< non-zero: the chunks of one long text share it
  std::uint8_t chunk_seq = 0;  ///< from 0
};
/// A text as STATUSTEXT chunks (common.xml: a text of at most 50 chars is one message with id 0; a
/// longer one is cut into 50-char chunks with `id` (non-zero) and chunk_seq 0, 1, ...; a NUL in a
/// chunk ends the text, so one whose length is a multiple of 50 gets an empty last chunk).
std::vector<StatusText> statustext_chunks(std::uint8_t severity, const std::string& text, std::uint16_t id);
/// PARAM_REQUEST_READ (20): by id, or by index when param_index >= 0.
struct ParamRequestRead {
  std::uint8_t target_system = 0, target_component = 0;
  std::string param_id;
  std::int16_t param_index = -1;
};
/// PARAM_REQUEST_LIST (21)
struct ParamRequestList {
  std::uint8_t target_system = 0, target_component = 0;
};
/// PARAM_SET (23)
struct ParamSet {
  std::uint8_t target_system = 0, target_component = 0;
  std::string param_id;
  float param_value = 0;
  std::uint8_t param_type = 0;
};

std::vector<std::uint8_t> encode(const Heartbeat& m);
std::vector<std::uint8_t> encode(const SysStatus& m);
std::vector<std::uint8_t> encode(const GpsRawInt& m);
std::vector<std::uint8_t> encode(const Attitude& m);
std::vector<std::uint8_t> encode(const GlobalPositionInt& m);
std::vector<std::uint8_t> encode(const VfrHud& m);
std::vector<std::uint8_t> encode(const HomePosition& m);
std::vector<std::uint8_t> encode(const ParamValueMsg& m);
std::vector<std::uint8_t> encode(const StatusText& m);
std::vector<std::uint8_t> encode(const ParamRequestRead& m);
std::vector<std::uint8_t> encode(const ParamRequestList& m);
std::vector<std::uint8_t> encode(const ParamSet& m);
std::vector<std::uint8_t> encode(const SystemTime& m);
std::vector<std::uint8_t> encode(const MissionCurrent& m);
std::vector<std::uint8_t> encode(const NavControllerOutput& m);
std::vector<std::uint8_t> encode(const Timesync& m);
std::vector<std::uint8_t> encode(const WindCov& m);
std::vector<std::uint8_t> encode(const ExtendedSysState& m);

Heartbeat decode_heartbeat(const std::vector<std::uint8_t>& p);
ParamRequestRead decode_param_request_read(const std::vector<std::uint8_t>& p);
ParamRequestList decode_param_request_list(const std::vector<std::uint8_t>& p);
ParamSet decode_param_set(const std::vector<std::uint8_t>& p);
ParamValueMsg decode_param_value(const std::vector<std::uint8_t>& p);
Timesync decode_timesync(const std::vector<std::uint8_t>& p);

}  // namespace tern::core::mavlink
