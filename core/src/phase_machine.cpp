#include "phase_machine.hpp"

#include <cmath>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace tern::core {

void PhaseMachine::configure() {
  declare(state_, "state", "vehicle state (altitude)");
  declare(command_, "controller_command", "commanded altitude h_c", Need::optional);
  declare(fcu_, "fcu_status", "flight-control unit status: the flight waits disarmed until it is armed and error-free",
          Need::optional);
  declare(phase_out_, "flight_phase", "current flight phase");
  declare(alt_toz_, "alt_toz", 5.0, ParamSpec("m", 0.0, 1000.0, "top of the takeoff zone: climb begins above this altitude (ROSplane alt_toz)"));
  declare(alt_hz_, "alt_hz", 20.0, ParamSpec("m", 0.1, 1000.0, "altitude-hold zone half-width around h_c: cruise within it (ROSplane alt_hz)"));
  declare(max_deflection_, "max_deflection", 0.7, ParamSpec("rad", 0.01, 3.2, "a controller commanding a larger surface deflection is replaced by the fallback"));
  declare(min_phase_time_, "min_phase_time", 1.0, ParamSpec("s", 0.0, 60.0, "a transition back (loss of altitude) needs its condition this long"));
}

void PhaseMachine::start() { reset(); }

void PhaseMachine::reset() {
  phase_ = msg::Phase::takeoff;
  disarmed_ = false;
  since_ = 0;
  condition_since_ = -1;
  transitions_.clear();
  msg::FlightPhase m;
  m.phase = m.previous = phase_;
  phase_out_.publish(m);
}

void PhaseMachine::enter(Nanos now, msg::Phase to, std::string reason) {
  log().info("phase {} -> {} at t={:.3f} s: {}", msg::phase_name(phase_), msg::phase_name(to), to_seconds(now), reason);
  transitions_.push_back({now, phase_, to, std::move(reason)});
  msg::FlightPhase m;
  m.stamp = now;
  m.previous = phase_;
  m.phase = to;
  m.since = now;
  phase_ = to;
  since_ = now;
  condition_since_ = -1;
  phase_out_.publish(m);
}

bool PhaseMachine::wait_for_arming(Nanos now) {
  if (!fcu_.has_value()) return disarmed_;
  const msg::FcuStatus& f = *fcu_;
  if (!disarmed_ && !f.armed) {
    disarmed_ = true;
    log().warn("t={:.3f} s: flight waits disarmed (no takeoff, no controller running) until the FCU is armed and "
               "error-free (error code 0x{:02x}; the FCU link says what is missing)", to_seconds(now), f.error_code);
    transitions_.push_back({now, phase_, msg::Phase::takeoff, "disarmed: the FCU is not armed"});
    phase_out_.publish(msg::FlightPhase{now, msg::Phase::takeoff, phase_, now});
  } else if (disarmed_ && f.armed && f.error_code == 0) {
    disarmed_ = false;
    enter(now, msg::Phase::takeoff, "FCU armed and error-free: takeoff");
  }
  return disarmed_;
}

void PhaseMachine::step(Nanos now) {
  if (wait_for_arming(now)) return;
  const msg::State& s = state_.get();
  if (!state_.has_value() || !std::isfinite(s.p_d)) return;
  const double h = -s.p_d;
  const double h_c = command_.has_value() && std::isfinite(command_->h_c) ? command_->h_c : h;
  const Nanos dwell = from_seconds(min_phase_time_());
  auto held = [&](bool cond) {
    if (!cond) {
      condition_since_ = -1;
      return false;
    }
    if (condition_since_ < 0) condition_since_ = now;
    return now - condition_since_ >= dwell;
  };
  switch (phase_) {
    case msg::Phase::takeoff:
      if (h >= alt_toz_()) enter(now, msg::Phase::climb, fmt::format("altitude {:.1f} m reached alt_toz {:.1f} m", h, alt_toz_()));
      break;
    case msg::Phase::climb:
      if (h < alt_toz_()) {
        if (held(true)) enter(now, msg::Phase::takeoff, fmt::format("altitude {:.1f} m fell below alt_toz {:.1f} m", h, alt_toz_()));
      } else if (std::fabs(h_c - h) < alt_hz_()) {
        enter(now, msg::Phase::cruise, fmt::format("altitude {:.1f} m within alt_hz {:.1f} m of h_c {:.1f} m", h, alt_hz_(), h_c));
      } else {
        held(false);
      }
      break;
    case msg::Phase::cruise:
    case msg::Phase::loiter:
    case msg::Phase::landing:
      if (h < alt_toz_()) {
        if (held(true)) enter(now, msg::Phase::takeoff, fmt::format("altitude {:.1f} m fell below alt_toz {:.1f} m", h, alt_toz_()));
      } else if (phase_ == msg::Phase::cruise && h_c - h > alt_hz_()) {
        if (held(true)) enter(now, msg::Phase::climb, fmt::format("altitude {:.1f} m is {:.1f} m below h_c {:.1f} m (more than alt_hz)", h, h_c - h, h_c));
      } else {
        held(false);
      }
      break;
  }
}

}  // namespace tern::core
