// tern_fcu_serial/mapping.hpp: tern's actuator and RC conventions <-> ROSflight's normalised
// channels. Plain C++, no tern host types.
//
// Actuators -> OFFBOARD_CONTROL in MODE_PASS_THROUGH (rosflight.xml): each surface deflection
// (rad, Beard & McLain sec. 4.2 signs: +delta_a rolls right, +delta_e pitches nose down,
// +delta_r yaws nose left) is divided by its maximum deflection, multiplied by its sign (+1 or
// -1) and clamped to [-1, 1]; the throttle is clamped to [0, 1]. They go to the channels u[i]
// named by `channel` (ROSflight's fixed-wing pass-through: u[0] aileron, u[1] elevator,
// u[2] rudder, u[3] throttle); every other channel is flagged in `ignore` (IGNORE_VALUEi bits).
// Reversal of a servo belongs in the FCU's mixer (REV_* parameters) or in `sign`.
//
// RC_CHANNELS -> sticks: PWM in microseconds, 1500 centred, +-500 full travel for roll, pitch,
// yaw and the auxiliary channels (-1..1), 1000..2000 for throttle (0..1); `stick_channel`
// names the 0-based channels of roll, pitch, yaw and throttle (ROSflight's default AETR:
// 0, 1, 3, 2). A channel the receiver does not report (UINT16_MAX or beyond chancount) reads 0.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "tern_fcu_serial/messages.hpp"

namespace tern::fcu {

/// Bits of OFFBOARD_CONTROL.mode and .ignore (rosflight.xml enums).
inline constexpr std::uint8_t kModePassThrough = 0;

struct ActuatorMap {
  std::array<int, 4> channel{0, 1, 2, 3};                         ///< u index of a, e, r, t (0..9, distinct)
  std::array<double, 3> max_deflection{0.785398, 0.785398, 0.785398};  ///< rad of a, e, r at |u| = 1 (> 0)
  std::array<double, 4> sign{1, 1, 1, 1};                         ///< +1 or -1 per a, e, r, t
  /// Throws std::invalid_argument naming the bad entry.
  void validate() const;
};

/// Surface deflections (rad) and throttle (0..1), in the uavbook's signs.
struct Surfaces {
  double delta_a = 0, delta_e = 0, delta_r = 0, delta_t = 0;
};

/// Pass-through command for s (non-finite values give 0, i.e. centred surfaces / no throttle).
mavlink::OffboardControl to_offboard(const Surfaces& s, const ActuatorMap& map);
/// The inverse (what an FCU emulator applies): ignored channels read 0.
Surfaces from_offboard(const mavlink::OffboardControl& c, const ActuatorMap& map);

struct RcMap {
  std::array<int, 4> stick_channel{0, 1, 3, 2};  ///< roll, pitch, yaw, throttle (0..17, distinct)
  std::array<int, 4> aux_channel{4, 5, 6, 7};
  std::array<double, 3> sign{1, 1, 1};           ///< roll, pitch, yaw stick signs
  void validate() const;
};

struct RcSticks {
  double roll = 0, pitch = 0, yaw = 0, throttle = 0;
  std::array<double, 4> aux{};
};

RcSticks from_rc(const mavlink::RcChannels& rc, const RcMap& map);
/// The inverse, for an emulator: PWM of the mapped channels, 1500 on the others up to channel 8.chancount 8).
mavlink::RcChannels to_rc(const RcSticks& s, const RcMap& map, std::uint32_t time_boot_ms);

/// PWM (us) of channel i of rc (0-based), or 0 when the channel is not reported.
std::uint16_t rc_pwm(const mavlink::RcChannels& rc, int i);

}  // namespace tern::fcu
