#include "control_common/controller_plugin.hpp"

#include <cmath>

#include <spdlog/spdlog.h>

namespace tern::control {

void ControllerPlugin::declare_gain(Param<double>& p, std::string name, double default_value, ParamSpec spec) {
  declare(p, std::move(name), default_value, std::move(spec));
  p.on_change([this](const double&) { dirty_ = true; });
}

void ControllerPlugin::configure() {
  declare(state_, "state", "estimated vehicle state");
  declare(command_, "controller_command", "airspeed, altitude and course commands of the path follower");
  declare(phase_, "flight_phase", "flight phase (takeoff, climb, cruise); absent: cruise", Need::optional);
  declare(rc_, "rc", "pilot sticks and override switch (manual modes)", Need::optional);
  declare(fcu_, "fcu_status", "flight-control unit status (rc_override: manual modes)", Need::optional);
  declare(actuators_, "actuators", "surface deflections, rad, and throttle 0..1");
  declare(internals_, "controller_internals", "roll and pitch commands, throttle before saturation");

  // Defaults: ROSplane 2.0's Anaconda values where a ROSplane parameter maps (see
  // plugins/control_slc/README.md for the table).
  declare_gain(course_kp_, "course_kp", 2.0, ParamSpec("rad/rad", 0.0, 20.0, "course -> roll proportional gain (ROSplane c_kp)"));
  declare_gain(course_ki_, "course_ki", 0.0025, ParamSpec("rad/(rad s)", 0.0, 10.0, "course -> roll integral gain (c_ki)"));
  declare_gain(course_kd_, "course_kd", 0.0, ParamSpec("rad/(rad/s)", 0.0, 10.0, "course -> roll derivative gain, on yaw rate r (c_kd)"));
  declare_gain(roll_max_, "roll_max", 0.7854, ParamSpec("rad", 0.05, 1.4, "roll command limit (max_roll)"));
  declare_gain(roll_rate_max_, "roll_rate_max", 0.0, ParamSpec("rad/s", 0.0, 20.0, "slew limit of the roll command; 0: none (ROSplane has none)"));
  declare_gain(roll_ff_, "roll_ff", 0.0, ParamSpec("rad/(rad/s)", 0.0, 2.0, "aileron per commanded roll rate, feed-forward (design: a_phi1/a_phi2)"));
  declare_gain(roll_kp_, "roll_kp", 0.55, ParamSpec("rad/rad", 0.0, 10.0, "roll -> aileron proportional gain (r_kp)"));
  declare_gain(roll_ki_, "roll_ki", 0.0, ParamSpec("rad/(rad s)", 0.0, 10.0, "roll -> aileron integral gain (r_ki)"));
  declare_gain(roll_kd_, "roll_kd", 0.2, ParamSpec("rad/(rad/s)", 0.0, 5.0, "roll -> aileron gain on roll rate p (r_kd)"));
  declare_gain(trim_a_, "trim_a", 0.0, ParamSpec("rad", -0.5, 0.5, "aileron trim (trim_a)"));
  declare_gain(max_a_, "max_a", 0.6981, ParamSpec("rad", 0.01, 1.5, "aileron limit (ROSplane max_a 0.8; default: the Anaconda servo limit)"));
  declare_gain(yaw_kr_, "yaw_damper_kr", 0.3, ParamSpec("rad/(rad/s)", 0.0, 5.0, "yaw damper gain on washed-out yaw rate"));
  declare_gain(yaw_p_wo_, "yaw_damper_p_wo", 0.5, ParamSpec("rad/s", 0.0, 10.0, "yaw damper washout pole"));
  declare_gain(trim_r_, "trim_r", 0.0, ParamSpec("rad", -0.5, 0.5, "rudder trim (trim_r)"));
  declare_gain(max_r_, "max_r", 0.523, ParamSpec("rad", 0.01, 1.5, "rudder limit (max_r)"));
  declare_gain(pitch_kp_, "pitch_kp", 4.25, ParamSpec("rad/rad", 0.0, 50.0, "pitch -> elevator proportional gain, magnitude (p_kp)"));
  declare_gain(pitch_ki_, "pitch_ki", 0.0, ParamSpec("rad/(rad s)", 0.0, 50.0, "pitch -> elevator integral gain (p_ki)"));
  declare_gain(pitch_kd_, "pitch_kd", 0.6, ParamSpec("rad/(rad/s)", 0.0, 10.0, "pitch -> elevator gain on pitch rate q (p_kd)"));
  declare_gain(trim_e_, "trim_e", -0.075, ParamSpec("rad", -0.6, 0.6, "elevator trim, uavbook sign: negative is nose up (-trim_e of ROSplane)"));
  declare_gain(max_e_, "max_e", 0.61, ParamSpec("rad", 0.01, 1.5, "elevator limit (max_e)"));
  declare_gain(theta_max_, "theta_max", 0.35, ParamSpec("rad", 0.0, 1.2, "pitch command upper limit"));
  declare_gain(theta_min_, "theta_min", -0.35, ParamSpec("rad", -1.2, 0.0, "pitch command lower limit"));
  declare_gain(trim_t_, "trim_t", 0.5, ParamSpec("", 0.0, 1.0, "throttle at trim (trim_t)"));
  declare_gain(max_t_, "max_t", 1.0, ParamSpec("", 0.0, 1.0, "throttle upper limit (max_t)"));
  declare_gain(min_t_, "min_t", 0.0, ParamSpec("", 0.0, 1.0, "throttle lower limit"));
  declare_gain(takeoff_throttle_, "takeoff_throttle", 1.0, ParamSpec("", 0.0, 1.0, "throttle during takeoff (max_takeoff_throttle)"));
  declare_gain(takeoff_pitch_, "takeoff_pitch", 0.1745, ParamSpec("rad", 0.0, 0.6, "pitch command after rotation in takeoff"));
  declare_gain(rotation_Va_, "rotation_Va", 12.0, ParamSpec("m/s", 0.0, 100.0, "airspeed at which takeoff rotates to takeoff_pitch"));
  declare_gain(handover_tau_, "handover_tau", 1.0, ParamSpec("s", 0.0, 60.0, "decay time of the bumpless-transfer offset"));
  declare(climb_course_hold_, "climb_course_hold", true,
          ParamSpec("", 0, 0, "climb phase: hold the commanded course (false: wings level)"));
  climb_course_hold_.on_change([this](const bool&) { dirty_ = true; });
  declare(manual_mode_, "manual_mode", "passthrough",
          ParamSpec("", 0, 0, "when the pilot overrides: surfaces from the sticks, or roll and pitch angles from the sticks")
              .one_of({"passthrough", "angle"}));
  declare(angle_mode_aux_, "angle_mode_aux", std::int64_t{-1},
          ParamSpec("", -1, 3, "rc aux channel (0..3) whose value > 0.5 selects angle mode in override; -1: none"));
  declare_gain(angle_roll_max_, "angle_roll_max", 0.7854, ParamSpec("rad", 0.0, 1.4, "angle mode: roll command at full stick"));
  declare_gain(angle_pitch_max_, "angle_pitch_max", 0.35, ParamSpec("rad", 0.0, 1.0, "angle mode: pitch command at full stick"));
  declare_law_params();

  if (min_t_() > max_t_()) {
    throw ParamError("parameter '" + context().instance_name() + ".min_t': value " + std::to_string(min_t_()) +
                     " exceeds max_t " + std::to_string(max_t_()));
  }
  autopilot_.emplace(law());
  apply_params();
  autopilot_->reset();
}

Autopilot& ControllerPlugin::autopilot() { return *autopilot_; }

void ControllerPlugin::apply_params() {
  LateralGains lg;
  lg.course_kp = course_kp_;
  lg.course_ki = course_ki_;
  lg.course_kd = course_kd_;
  lg.roll_max = roll_max_;
  lg.roll_rate_max = roll_rate_max_;
  lg.roll_ff = roll_ff_;
  lg.roll_kp = roll_kp_;
  lg.roll_ki = roll_ki_;
  lg.roll_kd = roll_kd_;
  lg.trim_a = trim_a_;
  lg.max_a = max_a_;
  lg.yaw_kr = yaw_kr_;
  lg.yaw_p_wo = yaw_p_wo_;
  lg.trim_r = trim_r_;
  lg.max_r = max_r_;
  autopilot_->set_lateral_gains(lg);
  autopilot_->set_pitch_gains({pitch_kp_, pitch_ki_, pitch_kd_, trim_e_, max_e_});
  AutopilotSettings s;
  s.takeoff_throttle = takeoff_throttle_;
  s.takeoff_pitch = takeoff_pitch_;
  s.rotation_Va = rotation_Va_;
  s.climb_course_hold = climb_course_hold_;
  s.handover_tau = handover_tau_;
  s.angle_roll_max = angle_roll_max_;
  s.angle_pitch_max = angle_pitch_max_;
  autopilot_->set_settings(s);
  apply_law_params();
  dirty_ = false;
}

Mode ControllerPlugin::select_mode(const msg::State&) {
  const bool rc_ok = rc_.has_value() && !rc_->failsafe;
  const bool overridden = (rc_ok && rc_->rc_override) || (fcu_.has_value() && fcu_->rc_override);
  if (overridden) {
    const std::int64_t aux = angle_mode_aux_();
    const bool angle = manual_mode_() == "angle" || (aux >= 0 && rc_ok && rc_->aux[static_cast<std::size_t>(aux)] > 0.5);
    return angle ? Mode::manual_angle : Mode::manual_passthrough;
  }
  if (!phase_.has_value()) return Mode::cruise;
  switch (phase_->phase) {
    case msg::Phase::takeoff: return Mode::takeoff;
    case msg::Phase::climb: return Mode::climb;
    default: return Mode::cruise;
  }
}

void ControllerPlugin::step(Nanos now) {
  if (!state_.has_value()) return;
  if (dirty_) apply_params();
  const double dt = last_step_ ? to_seconds(now - *last_step_) : 0.0;
  last_step_ = now;

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

  Command c;
  if (command_.has_value()) {
    const auto& m = *command_;
    c = {m.Va_c, m.h_c, m.chi_c, m.phi_ff, m.phi_c, m.theta_c, m.override_phi, m.override_theta};
  } else {
    if (!hold_command_ && x.finite()) hold_command_ = Command{x.Va, x.h, x.chi, 0.0, 0.0, 0.0, false, false};
    if (hold_command_) c = *hold_command_;
  }
  Sticks sticks;
  if (rc_.has_value()) sticks = {rc_->roll, rc_->pitch, rc_->yaw, rc_->throttle};

  const Mode mode = select_mode(s);
  if (mode == Mode::manual_passthrough || mode == Mode::manual_angle) ++manual_steps_;
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
  if (out.held) {
    ++held_steps_;
    if (!holding_) {
      log().warn("{} at t = {:.3f} s; holding the last actuator command",
                 s.valid ? "non-finite state, command or sticks" : "state not valid (estimator not initialised)",
                 to_seconds(now));
    }
  } else if (holding_) {
    log().info("inputs valid again at t = {:.3f} s; control resumed", to_seconds(now));
  }
  holding_ = out.held;

  msg::Actuators a;
  a.stamp = now;
  a.delta_a = out.surfaces.delta_a;
  a.delta_e = out.surfaces.delta_e;
  a.delta_r = out.surfaces.delta_r;
  a.delta_t = out.surfaces.delta_t;
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
  last_step_.reset();
  hold_command_.reset();
  holding_ = false;
}

void ControllerPlugin::take_over(const msg::Actuators& last) {
  if (dirty_) apply_params();
  autopilot().take_over({last.delta_a, last.delta_e, last.delta_r, last.delta_t});
  holding_ = false;
}

std::vector<std::pair<std::string, double>> ControllerPlugin::summary() const {
  return {{"held_steps", static_cast<double>(held_steps_)}, {"manual_steps", static_cast<double>(manual_steps_)}};
}

}  // namespace tern::control
