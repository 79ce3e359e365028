// tern_fcu_serial/mapping.hpp: tern's actuator and RC conventions <-> ROSflight's channels.
// Plain C++, no tern host types.
//
// Actuators -> OFFBOARD_CONTROL in MODE_PASS_THROUGH. The firmware reads u[0..5] as the forces
// and torques Fx, Fy, Fz, Qx, Qy, Qz (comm_manager.cpp offboard_control_callback, command_manager.h
// MuxChannel) and its fixed-wing mixers route Qx -> aileron servo, Qy -> elevator, Qz -> rudder,
// Fx -> motor (include/mixer.h fixedwing_mixing). Each surface deflection (rad, Beard & McLain
// sec. 4.2 signs) is divided by its maximum deflection, multiplied by its sign (+1 or -1) and
// clamped to [-1, 1]; the throttle is clamped to [0, 1]. `channel` names the u index of
// aileron, elevator, rudder, throttle (default Qx Qy Qz Fx = 3 4 5 0). Every other channel of
// u[0..5] is sent active at 0: an ignored one would go to the pilot and set an override bit
// (command_manager.cpp check_if_*_overridden_by_rc); u[6..9] are flagged in `ignore`.
// Reversal of a servo belongs to the FCU's mixer (REV_* parameters) or to `sign`.
//
// RC_CHANNELS -> sticks, as rosflight_io reads it (rosflight_io.cpp handle_rc_channels_msg):
// channels 1..8 whatever chancount says (the firmware sends chancount 0: mavlink_adapter.cpp
// send_rc_raw), PWM in microseconds, 1500 centred, +-500 full travel for roll, pitch, yaw and
// the auxiliary channels (-1..1), 1000..2000 for throttle (0..1). `stick_channel` names the
// 0-based channels of roll, pitch, yaw and throttle (the firmware's RC_X/Y/Z/F_CHN: 0, 1, 3, 2).
// A channel at 0 or UINT16_MAX, or beyond 8 and beyond chancount, is not reported (reads 0).
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "tern_fcu_serial/messages.hpp"

namespace tern::fcu {

/// Bits of OFFBOARD_CONTROL.mode (rosflight.xml OFFBOARD_CONTROL_MODE).
inline constexpr std::uint8_t kModePassThrough = 0;

/// The firmware's names of u[0..5] (command_manager.h MuxChannel).
inline constexpr std::array<const char*, 6> kChannelNames{"Fx", "Fy", "Fz", "Qx", "Qy", "Qz"};
/// "Qx" -> 3 etc.; throws std::invalid_argument naming the text.
int channel_index(const std::string& name);

struct ActuatorMap {
  std::array<int, 4> channel{3, 4, 5, 0};                              ///< u index of a, e, r, t (0..5, distinct)
  std::array<double, 3> max_deflection{0.785398, 0.785398, 0.785398};  ///< rad of a, e, r at |u| = 1 (> 0)
  std::array<double, 4> sign{1, 1, 1, 1};                              ///< +1 or -1 per a, e, r, t
  /// Throws std::invalid_argument naming the bad entry.
  void validate() const;
};

/// Surface deflections (rad) and throttle (0..1), in the uavbook's signs.
struct Surfaces {
  double delta_a = 0, delta_e = 0, delta_r = 0, delta_t = 0;
};

/// Pass-through command for s (non-finite values give 0, i.e. centred surfaces / no throttle).
mavlink::OffboardControl to_offboard(const Surfaces& s, const ActuatorMap& map);

struct RcMap {
  std::array<int, 4> stick_channel{0, 1, 3, 2};  ///< roll, pitch, yaw, throttle (0..17, distinct)
  std::array<int, 4> aux_channel{4, 5, 6, 7};
  std::array<double, 3> sign{1, 1, 1};  ///< roll, pitch, yaw stick signs
  void validate() const;
};

struct RcSticks {
  double roll = 0, pitch = 0, yaw = 0, throttle = 0;
  std::array<double, 4> aux{};
};

RcSticks from_rc(const mavlink::RcChannels& rc, const RcMap& map);

/// PWM (us) of channel i of rc (0-based), or 0 when the channel is not reported.
std::uint16_t rc_pwm(const mavlink::RcChannels& rc, int i);

/// ROSFLIGHT_OUTPUT_RAW value of a servo output (PWM fraction 0..1, mixer.cpp Mixer::mix_output:
/// 0.5 + 0.5 u) as the normalised command u in -1..1.
inline double servo_command(float raw) { return 2.0 * static_cast<double>(raw) - 1.0; }

}  // namespace tern::fcu
