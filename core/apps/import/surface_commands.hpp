// core/apps/import/surface_commands.hpp: another autopilot's control-surface and throttle commands
// as the sensor log's `actuators` rows (tern/Actuators; docs/sensor-log.md, "actuators"), shared by
// `tern import ulog` and `tern import alfa`.
//
// The autopilots log normalised commands: roll, pitch and yaw in -1..1 and throttle in 0..1 (PX4's
// actuator_controls), or servo outputs (PX4's actuator_servos in -1..1, ArduPilot's PWM in us). A
// normalised command is a fraction of the surface's full deflection, which no such log holds: the
// researcher states it (`--max-deflection A E R`, rad: the aircraft file's servos.max_delta_a/e/r),
// and sensor_log.yaml's notes record it. Without it no actuators table is written, and the import
// says so in one line.
//
// Signs: the autopilots' positive roll, pitch and yaw commands ask for roll right, nose up and nose
// right; the uavbook's (Beard and McLain, sec. 4.2) positive delta_a rolls right (C_ell_delta_a > 0),
// positive delta_e pitches the nose down (C_m_delta_e < 0), positive delta_r yaws the nose left
// (C_n_delta_r < 0). So
//   delta_a = +u_roll * max_a,  delta_e = -u_pitch * max_e,  delta_r = -u_yaw * max_r,  delta_t = u_throttle.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "tern/msg/control.hpp"
#include "tern/time.hpp"

namespace tern::core {

/// How a log's normalised surface commands become the uavbook's deflections (`tern import`'s options).
struct CommandMapping {
  /// rad: the aileron, elevator and rudder deflections a normalised command of 1 stands for; unset:
  /// the log's commands are not written (the record must not assume them)
  std::optional<std::array<double, 3>> max_deflection;
  /// s: a known transport delay from the logged command to the servo, added to every actuators row's
  /// stamp (the servo's own lag is the aircraft file's servos.tau, applied by whoever reads the log)
  double command_delay = 0.0;
  /// ALFA / ArduPilot PWM outputs: the 1-based channels of aileron, elevator, throttle, rudder
  /// (ArduPlane's default RCMAP_ROLL, _PITCH, _THROTTLE, _YAW: 1 2 3 4); a negative channel is reversed
  /// (SERVOn_REVERSED 1: a higher pulse moves the surface the other way)
  std::array<int, 4> rc_channels{1, 2, 3, 4};
};

/// Normalised commands in the autopilot's sense: roll right, pitch up, yaw right positive (-1..1),
/// throttle 0..1.
struct NormalisedCommand {
  double roll = 0.0, pitch = 0.0, yaw = 0.0, throttle = 0.0;
};

/// The actuators row of a normalised command at `stamp` (ns, the command's own time; the mapping's
/// command_delay is added). Requires mapping.max_deflection.
msg::Actuators actuators_from_normalised(Nanos stamp, const NormalisedCommand& u, const CommandMapping& mapping);

/// An ArduPilot servo pulse (us) as a normalised surface command: (pwm - 1500) / 500, negated when
/// `reversed` (SERVOn_MIN/TRIM/MAX taken as 1000/1500/2000, their defaults).
double normalised_from_pwm(double pwm_us, bool reversed);
/// An ArduPilot throttle pulse (us) as 0..1: (pwm - 1000) / 1000, clamped (SERVO3_MIN/MAX 1000/2000).
double throttle_from_pwm(double pwm_us);

/// The mapping for sensor_log.yaml's notes, one line: the full deflections, the signs, the delay.
std::string describe(const CommandMapping& mapping);

/// Hz: the rate sysid needs of the surfaces' commands (docs/sensor-log.md, "actuators"): a held
/// command lags half a sample, 360 f / (2 rate) degrees at the excitation's frequency f; at 50 Hz
/// that is 14 deg at the top of a 4-Hz chirp (12 samples a cycle).
inline constexpr double kActuatorsMinRateHz = 50.0;
/// One line for a table of surface commands whose mean rate is below kActuatorsMinRateHz; "" otherwise.
std::string actuator_rate_warning(const std::string& file, double rate_hz);

}  // namespace tern::core
