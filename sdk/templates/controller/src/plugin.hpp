// @CLASS@: the tern adapter of Slc (slc.hpp): ports, parameters, time.
//
// Ports:  in  state                msg::State, the estimate (phi, theta, chi, p, q, p_d, Va);
//                                  trim surfaces while it is not valid
//         in  controller_command   msg::ControllerCommand from the path follower (chi_c, h_c,
//                                  Va_c, phi_ff); trim surfaces until the first one
//         in  flight_phase         msg::FlightPhase, optional: copied to controller_internals
//         out actuators            msg::Actuators (delta_r = 0: no rudder)
//         out controller_internals msg::ControllerInternals (phi_c, theta_c, delta_t_c)
// Parameters: the gains, trims and limits of slc.hpp, one tern::Param each.
#pragma once

#include <cstdint>

#include "slc.hpp"
#include "tern/plugin.hpp"

class @CLASS@ final : public tern::Plugin {
 public:
  void configure() override {
    using tern::ParamSpec;
    declare(state_, "state", "estimated state");
    declare(command_, "controller_command", "course, altitude and airspeed commands of the path follower");
    declare(phase_, "flight_phase", "flight phase (only reported in controller_internals)", tern::Need::optional);
    declare(actuators_, "actuators", "surface deflections, rad, and throttle 0..1");
    declare(internals_, "controller_internals", "roll and pitch commands, throttle before saturation");
    const tern_@NAME@::Gains d;
    declare(course_kp_, "course_kp", d.course_kp, ParamSpec("rad/rad", 0.0, 20.0, "roll command per course error"));
    declare(course_ki_, "course_ki", d.course_ki, ParamSpec("rad/(rad s)", 0.0, 5.0, "roll command per integrated course error"));
    declare(roll_max_, "roll_max", d.roll_max, ParamSpec("rad", 0.05, 1.2, "roll command limit"));
    declare(roll_kp_, "roll_kp", d.roll_kp, ParamSpec("rad/rad", 0.0, 10.0, "aileron per roll error"));
    declare(roll_kd_, "roll_kd", d.roll_kd, ParamSpec("rad/(rad/s)", 0.0, 2.0, "aileron per roll rate p"));
    declare(trim_a_, "trim_a", d.trim_a, ParamSpec("rad", -0.3, 0.3, "aileron at trim"));
    declare(max_a_, "max_a", d.max_a, ParamSpec("rad", 0.01, 0.7, "aileron limit (the host's max_deflection is 0.7)"));
    declare(altitude_kp_, "altitude_kp", d.altitude_kp, ParamSpec("rad/m", 0.0, 1.0, "pitch command per altitude error"));
    declare(altitude_ki_, "altitude_ki", d.altitude_ki, ParamSpec("rad/(m s)", 0.0, 1.0, "pitch command per integrated altitude error"));
    declare(theta_max_, "theta_max", d.theta_max, ParamSpec("rad", 0.05, 0.8, "pitch command limit (both signs)"));
    declare(pitch_kp_, "pitch_kp", d.pitch_kp, ParamSpec("rad/rad", 0.0, 20.0, "elevator per pitch error"));
    declare(pitch_kd_, "pitch_kd", d.pitch_kd, ParamSpec("rad/(rad/s)", 0.0, 2.0, "elevator per pitch rate q"));
    declare(trim_e_, "trim_e", d.trim_e, ParamSpec("rad", -0.5, 0.5, "elevator at trim (positive: nose down)"));
    declare(max_e_, "max_e", d.max_e, ParamSpec("rad", 0.01, 0.7, "elevator limit"));
    declare(airspeed_kp_, "airspeed_kp", d.airspeed_kp, ParamSpec("1/(m/s)", 0.0, 2.0, "throttle per airspeed error"));
    declare(airspeed_ki_, "airspeed_ki", d.airspeed_ki, ParamSpec("1/m", 0.0, 2.0, "throttle per integrated airspeed error"));
    declare(trim_t_, "trim_t", d.trim_t, ParamSpec("", 0.0, 1.0, "throttle at trim"));
  }

  void start() override { reset(); }

  void step(tern::Nanos now) override {
    slc_.set_gains(gains());  // parameters may change in flight
    const tern::msg::State& x = *state_;
    const double dt = last_ >= 0 ? tern::to_seconds(now - last_) : 0.0;
    last_ = now;
    tern_@NAME@::Output o = slc_.trim();
    if (x.valid && command_.has_value()) {
      const tern::msg::ControllerCommand& c = *command_;
      o = slc_.update({c.chi_c, c.h_c, c.Va_c, c.phi_ff}, {x.phi, x.theta, x.chi, x.p, x.q, -x.p_d, x.Va}, dt);
    }
    tern::msg::Actuators a;
    a.stamp = now;
    a.delta_a = o.delta_a;
    a.delta_e = o.delta_e;
    a.delta_t = o.delta_t;
    actuators_.publish(a);
    tern::msg::ControllerInternals in;
    in.stamp = now;
    in.phi_c = o.phi_c;
    in.theta_c = o.theta_c;
    in.delta_t_c = o.delta_t_c;
    in.alt_zone = static_cast<std::uint8_t>(phase_.has_value() ? phase_->phase : tern::msg::Phase::cruise);
    internals_.publish(in);
  }

  /// Integrators clean; the next step integrates nothing.
  void reset() override {
    slc_.reset();
    last_ = -1;
  }

  /// Handover from another controller: integrators clean, except the throttle's, which starts
  /// where the outgoing controller left the throttle.
  void take_over(const tern::msg::Actuators& last) override {
    reset();
    slc_.set_gains(gains());
    if (state_->valid && command_.has_value()) slc_.take_over(last.delta_t, command_->Va_c - state_->Va);
  }

 private:
  tern_@NAME@::Gains gains() const {
    return {course_kp_(),   course_ki_(),   roll_max_(), roll_kp_(),  roll_kd_(),  trim_a_(),
            max_a_(),       altitude_kp_(), altitude_ki_(), theta_max_(), pitch_kp_(), pitch_kd_(),
            trim_e_(),      max_e_(),       airspeed_kp_(), airspeed_ki_(), trim_t_()};
  }

  tern::Input<tern::msg::State> state_;
  tern::Input<tern::msg::ControllerCommand> command_;
  tern::Input<tern::msg::FlightPhase> phase_;
  tern::Output<tern::msg::Actuators> actuators_;
  tern::Output<tern::msg::ControllerInternals> internals_;
  tern::Param<double> course_kp_, course_ki_, roll_max_, roll_kp_, roll_kd_, trim_a_, max_a_;
  tern::Param<double> altitude_kp_, altitude_ki_, theta_max_, pitch_kp_, pitch_kd_, trim_e_, max_e_;
  tern::Param<double> airspeed_kp_, airspeed_ki_, trim_t_;
  tern_@NAME@::Slc slc_;
  tern::Nanos last_ = -1;  ///< time of the previous step, -1: none since reset
};
