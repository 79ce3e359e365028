// @CLASS@: the tern adapter of AttitudeHold (attitude_hold.hpp): ports, parameters, time.
//
// Ports:  in  state               msg::State (phi, theta, p, q, Va; holds trim while !valid)
//         in  controller_command  msg::ControllerCommand, optional: its Va_c (> 0) replaces
//                                 the Va_c parameter
//         out actuators           msg::Actuators (delta_r = 0)
//         out controller_internals msg::ControllerInternals (phi_c, theta_c, delta_t_c)
// Parameters: phi_c, theta_c, Va_c (setpoints) and the gains/trims of attitude_hold.hpp.
#pragma once

#include <cmath>

#include "attitude_hold.hpp"
#include "tern/plugin.hpp"

class @CLASS@ final : public tern::Plugin {
 public:
  void configure() override {
    using tern::ParamSpec;
    declare(state_, "state", "estimated state");
    declare(command_, "controller_command", "airspeed command (Va_c) from the path follower", tern::Need::optional);
    declare(actuators_, "actuators", "surface and throttle commands");
    declare(internals_, "controller_internals", "roll and pitch setpoints, throttle before saturation");
    declare(phi_c_, "phi_c", 0.0, ParamSpec("rad", -0.7, 0.7, "roll setpoint (0: wings level)"));
    declare(theta_c_, "theta_c", 0.0, ParamSpec("rad", -0.35, 0.35, "pitch setpoint"));
    declare(Va_c_, "Va_c", 17.0, ParamSpec("m/s", 5.0, 60.0, "airspeed setpoint, unless controller_command has one"));
    const tern_@NAME@::Gains d;
    declare(roll_kp_, "roll_kp", d.roll_kp, ParamSpec("rad/rad", 0.0, 10.0, "aileron per roll error"));
    declare(roll_kd_, "roll_kd", d.roll_kd, ParamSpec("rad/(rad/s)", 0.0, 2.0, "aileron per roll rate"));
    declare(pitch_kp_, "pitch_kp", d.pitch_kp, ParamSpec("rad/rad", 0.0, 20.0, "elevator per pitch error"));
    declare(pitch_kd_, "pitch_kd", d.pitch_kd, ParamSpec("rad/(rad/s)", 0.0, 2.0, "elevator per pitch rate"));
    declare(airspeed_kp_, "airspeed_kp", d.airspeed_kp, ParamSpec("1/(m/s)", 0.0, 2.0, "throttle per airspeed error"));
    declare(airspeed_ki_, "airspeed_ki", d.airspeed_ki, ParamSpec("1/m", 0.0, 2.0, "throttle per integrated airspeed error"));
    declare(trim_a_, "trim_a", d.trim_a, ParamSpec("rad", -0.3, 0.3, "aileron at trim"));
    declare(trim_e_, "trim_e", d.trim_e, ParamSpec("rad", -0.5, 0.5, "elevator at trim"));
    declare(trim_t_, "trim_t", d.trim_t, ParamSpec("", 0.0, 1.0, "throttle at trim"));
    declare(max_a_, "max_a", d.max_a, ParamSpec("rad", 0.0, 1.0, "aileron limit"));
    declare(max_e_, "max_e", d.max_e, ParamSpec("rad", 0.0, 1.0, "elevator limit"));
  }

  void start() override { reset(); }

  void step(tern::Nanos now) override {
    hold_.set_gains(gains());  // parameters may change while flying
    const tern::msg::State& x = *state_;
    const double dt = last_ >= 0 ? tern::to_seconds(now - last_) : 0.0;
    last_ = now;
    tern_@NAME@::Setpoint sp{phi_c_(), theta_c_(), Va_c_()};
    if (command_.has_value() && command_->Va_c > 0.0) sp.Va_c = command_->Va_c;

    tern_@NAME@::Surfaces s{trim_a_(), trim_e_(), trim_t_()};
    if (x.valid) s = hold_.update(sp, {x.phi, x.theta, x.p, x.q, x.Va}, dt);

    tern::msg::Actuators a;
    a.stamp = now;
    a.delta_a = s.delta_a;
    a.delta_e = s.delta_e;
    a.delta_t = s.delta_t;
    actuators_.publish(a);
    tern::msg::ControllerInternals in;
    in.stamp = now;
    in.phi_c = sp.phi_c;
    in.theta_c = sp.theta_c;
    in.delta_t_c = s.delta_t;
    internals_.publish(in);
  }

  void reset() override {
    hold_.reset();
    last_ = -1;
  }

  /// Bumpless: the throttle integrator starts where the outgoing controller left the throttle.
  void take_over(const tern::msg::Actuators& last) override {
    reset();
    hold_.set_gains(gains());
    const double Va_c = command_.has_value() && command_->Va_c > 0.0 ? command_->Va_c : Va_c_();
    if (state_->valid) hold_.take_over(last.delta_t, Va_c - state_->Va);
  }

 private:
  tern_@NAME@::Gains gains() const {
    return {roll_kp_(), roll_kd_(), pitch_kp_(), pitch_kd_(), airspeed_kp_(), airspeed_ki_(),
            trim_a_(),  trim_e_(),  trim_t_(),   max_a_(),    max_e_()};
  }

  tern::Input<tern::msg::State> state_;
  tern::Input<tern::msg::ControllerCommand> command_;
  tern::Output<tern::msg::Actuators> actuators_;
  tern::Output<tern::msg::ControllerInternals> internals_;
  tern::Param<double> phi_c_, theta_c_, Va_c_;
  tern::Param<double> roll_kp_, roll_kd_, pitch_kp_, pitch_kd_, airspeed_kp_, airspeed_ki_;
  tern::Param<double> trim_a_, trim_e_, trim_t_, max_a_, max_e_;
  tern_@NAME@::AttitudeHold hold_;
  tern::Nanos last_ = -1;
};
