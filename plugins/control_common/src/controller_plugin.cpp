#include "control_common/controller_plugin.hpp"

#include <cmath>

#include <spdlog/spdlog.h>

namespace tern::control {

void ControllerPlugin::configure() {
  declare(state_, "state", "estimated vehicle state");
  declare(command_, "controller_command", "airspeed, altitude and course commands of the path follower");
  declare(phase_, "flight_phase", "flight phase (takeoff, climb, cruise, approach, flare, rollout); absent: cruise", Need::optional);
  declare(rc_, "rc", "pilot sticks and override switch (manual modes)", Need::optional);
  declare(range_, "range", "downward range finder: the height above the runway in the flare (absent: the altitude estimate's)",
          Need::optional);
  declare(fcu_, "fcu_status", "flight-control unit status (rc_override: manual modes)", Need::optional);
  declare(actuators_, "actuators", "surface deflections, rad, and throttle 0..1");
  declare(internals_, "controller_internals", "roll and pitch commands, throttle before saturation");

  // The gains, limits and settings: one name, default and spec each, in their structs'
  // describe() (control_common/loops.hpp, autopilot.hpp).
  declare_gains(lateral_);
  declare_gains(pitch_);
  declare_gains(limits_);
  declare_gains(settings_);
  declare_gains(landing_);
  declare_struct(manual_);
  declare_law_params();

  if (limits_.min_t > limits_.max_t) {
    throw ParamError("parameter '" + context().instance_name() + ".min_t': value " + std::to_string(limits_.min_t) + " exceeds max_t " +
                     std::to_string(limits_.max_t));
  }
  autopilot_.emplace(law());
  apply_params();
  autopilot_->reset();
}

Autopilot& ControllerPlugin::autopilot() { return *autopilot_; }

void ControllerPlugin::apply_params() {
  autopilot_->set_lateral_gains(lateral_);
  autopilot_->set_pitch_gains(pitch_);
  autopilot_->set_settings(settings_);
  autopilot_->set_landing_settings(landing_);
  apply_law_params();
  dirty_ = false;
}

Mode ControllerPlugin::select_mode(const msg::State&) {
  const bool rc_ok = rc_.has_value() && !rc_->failsafe;
  const bool overridden = (rc_ok && rc_->rc_override) || (fcu_.has_value() && fcu_->rc_override);
  if (overridden) {
    const std::int64_t aux = manual_.angle_aux;
    const bool angle = manual_.mode == "angle" || (aux >= 0 && rc_ok && rc_->aux[static_cast<std::size_t>(aux)] > 0.5);
    return angle ? Mode::manual_angle : Mode::manual_passthrough;
  }
  if (!phase_.has_value()) return Mode::cruise;
  switch (phase_->phase) {
    case msg::Phase::takeoff: return Mode::takeoff;
    case msg::Phase::climb: return Mode::climb;
    case msg::Phase::approach: return Mode::approach;
    case msg::Phase::flare: return Mode::flare;
    case msg::Phase::rollout: return Mode::rollout;
    default: return Mode::cruise;
  }
}

void ControllerPlugin::step(Nanos now) {
  if (!state_.has_value()) return;
  if (dirty_) apply_params();
  const double dt = flight_.last_step ? to_seconds(now - *flight_.last_step) : 0.0;
  flight_.last_step = now;

  const msg::State& s = *state_;
  VehicleState x;
  x.phi = s.phi;
  x.theta = s.theta;
  x.chi = s.chi;
  x.p = s.p;
  x.q = s.q;
  x.r = s.r;
  x.h = -s.p_d;
  x.h_dot = -s.v_d;
  x.Va = s.Va;
  if (range_.has_value()) x.h_agl = range_->height_at(now, s.phi, s.theta);

  Command c;
  if (command_.has_value()) {
    const auto& m = *command_;
    c = {m.Va_c, m.h_c, m.chi_c, m.phi_ff, m.phi_c, m.theta_c, m.override_phi, m.override_theta, m.landing, m.h_td};
  } else {
    if (!flight_.hold_command && x.finite()) flight_.hold_command = Command{x.Va, x.h, x.chi, 0.0, 0.0, 0.0, false, false};
    if (flight_.hold_command) c = *flight_.hold_command;
  }
  Sticks sticks;
  if (rc_.has_value()) sticks = {rc_->roll, rc_->pitch, rc_->yaw, rc_->throttle};

  const Mode mode = select_mode(s);
  if (mode == Mode::manual_passthrough || mode == Mode::manual_angle) ++flight_.manual_steps;
  AutopilotOutput out;
  if (!s.valid) {
    // The estimator is not initialised (or lost its solution): hold the last command; before
    // the first one that is trim with throttle 0. Manual pass-through still works.
    if (mode == Mode::manual_passthrough) {
      out = autopilot().update(mode, x, c, sticks, dt);
    } else {
      out.surfaces = autopilot().last();
      out.held = true;
    }
  } else {
    out = autopilot().update(mode, x, c, sticks, dt);
  }
  if (s.valid) flight_.state_valid_once = true;
  if (out.held) {
    ++flight_.held_steps;
    if (!flight_.holding && !s.valid && !flight_.state_valid_once) {
      // every flight starts so (an air release before the estimator's first solution): not a fault
      log().info("state not valid yet (estimator not initialised) at t = {:.3f} s; holding the last actuator command", to_seconds(now));
    } else if (!flight_.holding) {
      log().warn("{} at t = {:.3f} s; holding the last actuator command",
                 s.valid ? "non-finite state, command or sticks" : "state not valid (estimator lost its solution)", to_seconds(now));
    }
  } else if (flight_.holding) {
    log().info("inputs valid again at t = {:.3f} s; control resumed", to_seconds(now));
  }
  flight_.holding = out.held;

  msg::Actuators a;
  a.stamp = now;
  a.delta_a = out.surfaces.delta_a;
  a.delta_e = out.surfaces.delta_e;
  a.delta_r = out.surfaces.delta_r;
  a.delta_t = out.surfaces.delta_t;
  a.brake = out.brake;
  actuators_.publish(a);

  msg::ControllerInternals in;
  in.stamp = now;
  in.phi_c = out.phi_c;
  in.theta_c = out.theta_c;
  in.delta_t_c = out.delta_t_c;
  in.alt_zone = static_cast<std::uint8_t>(phase_.has_value() ? phase_->phase : msg::Phase::cruise);
  internals_.publish(in);
}

void ControllerPlugin::reset() {
  if (dirty_) apply_params();
  autopilot().reset();
  flight_ = Flight{};
}

void ControllerPlugin::take_over(const msg::Actuators& last) {
  if (dirty_) apply_params();
  autopilot().take_over({last.delta_a, last.delta_e, last.delta_r, last.delta_t});
  flight_.holding = false;
}

std::string ControllerPlugin::health() const {
  std::string s;
  if (flight_.held_steps > 0) s = fmt::format("{} steps held the previous command (invalid or non-finite inputs)", flight_.held_steps);
  if (flight_.manual_steps > 0) s += fmt::format("{}{} steps under the pilot's override", s.empty() ? "" : ", ", flight_.manual_steps);
  return s;
}

std::vector<std::pair<std::string, double>> ControllerPlugin::summary() const {
  return {{"held_steps", static_cast<double>(flight_.held_steps)}, {"manual_steps", static_cast<double>(flight_.manual_steps)}};
}

}  // namespace tern::control
