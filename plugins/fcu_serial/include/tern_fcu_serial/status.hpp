// tern_fcu_serial/status.hpp: what ROSFLIGHT_STATUS and ROSFLIGHT_GNSS mean, in words a pilot
// can act on. Plain C++, no tern host types.
//
// Sources (rosflight_firmware, the commit rosflight_ros_pkgs pins): error bits
// include/state_manager.h (StateManager::ErrorCode; the message carries the low 8 bits,
// mavlink_adapter.cpp send_status), override bits include/command_manager.h
// (CommandManager::RCOverrideReason), arming src/state_manager.cpp (set_event), GNSS fix types
// include/interface/board.h (GNSS_FIX_TYPE_*).
#pragma once

#include <cstdint>
#include <string>

namespace tern::fcu {

/// Override bits that mean the pilot flies (switches, a deflected stick, TAKE_MIN_THR): 0x3F.
/// The others (0x3C0, OFFBOARD_*_INACTIVE) mean tern's command for that channel is missing
/// (ignored, or older than OFFBOARD_TIMEOUT at the last RC frame) and RC has it.
inline constexpr std::uint16_t kPilotOverride = 0x3F;
inline constexpr std::uint16_t kOffboardInactive = 0x3C0;

/// One line: why the FCU will not arm or fly tern's commands, and what to do; "" when armed
/// and error-free. E.g. "FCU disarmed: arm from the transmitter; IMU not calibrated: run
/// `tern fcu calibrate imu`".
std::string arming_problems(bool armed, std::uint16_t error_code);
/// The error bits in words ("" for none).
std::string describe_errors(std::uint16_t error_code);
/// The override bits in words ("" for none).
std::string describe_override(std::uint16_t rc_override);
/// tern's fix type (0 none, 1 dead reckoning, 2 2D, 3 3D) of ROSflight's GNSS fix type:
/// 4 (GNSS + dead reckoning), 6 and 7 (RTK) are 3D fixes; 5 (time only) is no position fix.
std::uint8_t fix_type(std::uint8_t rosflight_fix_type);

}  // namespace tern::fcu
