// core/apps/import/surface_commands.cpp: normalised and PWM commands as the uavbook's deflections
// (the mapping and its signs: surface_commands.hpp).
#include "import/surface_commands.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "tern/math.hpp"

namespace tern::core {

namespace {
constexpr double kPwmTrim = 1500.0;       // us: ArduPilot's SERVOn_TRIM default
constexpr double kPwmHalfRange = 500.0;   // us: SERVOn_MAX 2000 - SERVOn_TRIM 1500
constexpr double kPwmMin = 1000.0;        // us: SERVOn_MIN default
constexpr double kPwmFullRange = 1000.0;  // us: SERVOn_MAX - SERVOn_MIN
}  // namespace

msg::Actuators actuators_from_normalised(Nanos stamp, const NormalisedCommand& u, const CommandMapping& mapping) {
  const auto& max = mapping.max_deflection.value();
  msg::Actuators a;
  a.stamp = stamp + from_seconds(mapping.command_delay);
  a.delta_a = u.roll * max[0];
  a.delta_e = 0.0 - u.pitch * max[1];  // 0 - 0 = +0, not -0
  a.delta_r = 0.0 - u.yaw * max[2];
  a.delta_t = u.throttle;
  return a;
}

double normalised_from_pwm(double pwm_us, bool reversed) {
  const double u = (pwm_us - kPwmTrim) / kPwmHalfRange;
  return reversed ? 0.0 - u : u;
}

double throttle_from_pwm(double pwm_us) { return std::clamp((pwm_us - kPwmMin) / kPwmFullRange, 0.0, 1.0); }

std::string describe(const CommandMapping& mapping) {
  const auto& m = mapping.max_deflection.value();
  return fmt::format(
      "actuators: full deflections (--max-deflection) aileron {} rad ({:.1f} deg), elevator {} rad ({:.1f} deg), rudder {} rad "
      "({:.1f} deg), stated at import, not in the log; delta_a = +roll * max_a, delta_e = -pitch * max_e, delta_r = -yaw * max_r "
      "(the autopilot's roll right, nose up, nose right positive; the uavbook's delta_e nose down, delta_r nose left), delta_t = "
      "throttle 0..1; stamps: the command's publication time{}; the latency from there to the surface is not in the log",
      m[0], m[0] / kRadPerDeg, m[1], m[1] / kRadPerDeg, m[2], m[2] / kRadPerDeg,
      mapping.command_delay != 0.0 ? fmt::format(" + {} s (--command-delay)", mapping.command_delay) : std::string());
}

std::string actuator_rate_warning(const std::string& file, double rate_hz) {
  if (!(rate_hz < kActuatorsMinRateHz)) return "";
  constexpr double kPhaseDeg = 15.0;       // the half-sample lag's phase at the highest usable frequency
  constexpr double kQuasiSteadyHz = 10.0;  // below it not even a 1-Hz manoeuvre has 10 samples a cycle
  return fmt::format(
      "{}: the surfaces' commands are logged at {:.1f} Hz, below the {:.0f} Hz sysid needs (a held command lags half a "
      "sample, {:.0f} ms: {:.0f} deg of phase at {:.2f} Hz){}",
      file, rate_hz, kActuatorsMinRateHz, 1e3 / (2.0 * rate_hz), kPhaseDeg, rate_hz * kPhaseDeg / 180.0,
      rate_hz < kQuasiSteadyHz ? "; quasi-steady lift and drag at best" : "");
}

}  // namespace tern::core
