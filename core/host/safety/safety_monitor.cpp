#include "safety/safety_monitor.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "tern/math.hpp"

namespace tern::core {

namespace {

// The envelope is watched in climb and cruise (not near the ground: takeoff, approach, flare, rollout).
bool envelope_phase(msg::Phase p) { return p == msg::Phase::climb || p == msg::Phase::cruise; }

// The error a surface at its stop should reduce: grown by more than `growth` from its smallest
// since the surface got there (`least`)? `at_stop` false forgets it.
bool grown(bool at_stop, double error, double growth, std::optional<double>& least) {
  if (!at_stop) {
    least.reset();
    return false;
  }
  least = least ? std::min(*least, error) : error;
  return error - *least > growth;
}
}  // namespace

void SafetyMonitor::restart() {
  silent_steps_ = 0;
  envelope_since_ = -1;
  sat_e_.reset();
  sat_t_.reset();
  floor_armed_ = false;
}

std::string SafetyMonitor::check(const SafetyInputs& in) {
  if (!limits_.enabled) return "";
  if (std::string why = silent(in); !why.empty()) return why;
  const bool usable = in.state != nullptr && in.state->valid;
  if (!usable) {  // nothing to judge the controller by (the state-loss recovery's business)
    envelope_since_ = -1;
    return "";
  }
  if (std::string why = held(in.now, envelope(*in.state, in.phase), envelope_since_); !why.empty()) return why;
  return saturated(in);
}

std::string SafetyMonitor::silent(const SafetyInputs& in) {
  silent_steps_ = in.published ? 0 : silent_steps_ + 1;
  if (silent_steps_ < limits_.silent_periods) return "";
  return fmt::format("silent: stepped {} times in a row without publishing actuators", silent_steps_);
}

std::string SafetyMonitor::envelope(const msg::State& s, msg::Phase phase) {
  const SafetyLimits& l = limits_;
  if (std::fabs(s.phi) > l.roll_max)
    return fmt::format("envelope: roll {:.0f} deg beyond {:.0f} deg", s.phi * kDegPerRad, l.roll_max * kDegPerRad);
  if (s.theta > l.pitch_max || s.theta < l.pitch_min)
    return fmt::format("envelope: pitch {:.0f} deg outside {:.0f}..{:.0f} deg", s.theta * kDegPerRad, l.pitch_min * kDegPerRad,
                       l.pitch_max * kDegPerRad);
  // the landing descends through the floor by design: disarmed from the approach on, re-armed
  // after a go-around once above it again (as the geofence's floor, failsafe.hpp)
  floor_armed_ = !msg::landing_phase(phase) && (floor_armed_ || (envelope_phase(phase) && s.altitude() > l.floor));
  if (floor_armed_ && s.altitude() < l.floor)
    return fmt::format("envelope: altitude {:.1f} m below the floor {:.1f} m", s.altitude(), l.floor);
  if (!envelope_phase(phase)) return "";
  if (s.Va < l.airspeed_min) return fmt::format("envelope: airspeed {:.1f} m/s below {:.1f} m/s", s.Va, l.airspeed_min);
  if (s.Va > l.airspeed_max) return fmt::format("envelope: airspeed {:.1f} m/s above {:.1f} m/s", s.Va, l.airspeed_max);
  if (s.v_d > l.sink_max) return fmt::format("envelope: sink rate {:.1f} m/s above {:.1f} m/s", s.v_d, l.sink_max);
  return "";
}

std::string SafetyMonitor::saturated(const SafetyInputs& in) {
  const msg::Actuators* a = in.actuators;
  if (a == nullptr || !in.h_c || !envelope_phase(in.phase)) {
    sat_e_.reset();
    sat_t_.reset();
    return "";
  }
  const SafetyLimits& l = limits_;
  const double h = in.state->altitude();
  const double alt_error = std::fabs(*in.h_c - h);
  if (grown(std::fabs(a->delta_e) >= l.saturation * l.max_deflection, alt_error, l.error_growth, sat_e_))
    return fmt::format("saturated: delta_e {:.2f} rad at its stop while the altitude error grew to {:.1f} m", a->delta_e, alt_error);
  const bool short_of_energy = h < *in.h_c && in.Va_c && in.state->Va < *in.Va_c;
  if (grown(a->delta_t <= 0.0 && short_of_energy, alt_error, l.error_growth, sat_t_))
    return fmt::format("saturated: delta_t 0 while the aircraft sank to {:.1f} m below h_c", alt_error);
  return "";
}

std::string SafetyMonitor::held(Nanos now, std::string why, Nanos& since) {
  if (why.empty()) {
    since = -1;
    return "";
  }
  if (since < 0) since = now;
  return to_seconds(now - since) >= limits_.hold ? why : "";
}

}  // namespace tern::core
