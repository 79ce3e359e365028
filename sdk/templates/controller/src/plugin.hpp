// @CLASS@: the tern adapter of Slc (slc.hpp): ports, parameters, time.
//
// Ports:  in  state                msg::State, the estimate (phi, theta, chi, p, q, p_d, Va);
//                                  trim surfaces while it is not valid
//         in  controller_command   msg::ControllerCommand from the path follower (chi_c, h_c,
//                                  Va_c, phi_ff); trim surfaces until the first one
//         in  flight_phase         msg::FlightPhase, optional: copied to controller_internals
//         out actuators            msg::Actuators (delta_r = 0: no rudder)
//         out controller_internals msg::ControllerInternals (phi_c, theta_c, delta_t_c)
// Parameters: the gains, trims and limits of slc.hpp (Gains::describe), declared at once with
// declare_struct(gains_): gains_ always holds their values, also after a change in flight.
// Per-flight state (tern/plugin.hpp): everything a flight changes is in `flight_`, which
// reset() replaces wholesale; a new integrator, filter or counter goes there.
#pragma once

#include <cstdint>

#include "slc.hpp"
#include "tern/plugin.hpp"

class @CLASS@ final : public tern::Plugin {
 public:
  void configure() override {
    declare(state_, "state", "estimated state");
    declare(command_, "controller_command", "course, altitude and airspeed commands of the path follower");
    declare(phase_, "flight_phase", "flight phase (only reported in controller_internals)", tern::Need::optional);
    declare(actuators_, "actuators", "surface deflections, rad, and throttle 0..1");
    declare(internals_, "controller_internals", "roll and pitch commands, throttle before saturation");
    declare_struct(gains_);
  }

  void step(tern::Nanos now) override {
    tern_@NAME@::Slc& slc = flight_.slc;
    slc.set_gains(gains_);  // parameters may change in flight
    const tern::msg::State& x = *state_;
    const double dt = flight_.last_step >= 0 ? tern::to_seconds(now - flight_.last_step) : 0.0;
    flight_.last_step = now;
    tern_@NAME@::Output o = slc.trim();
    if (x.valid && command_.has_value()) {
      const tern::msg::ControllerCommand& c = *command_;
      o = slc.update({c.chi_c, c.h_c, c.Va_c, c.phi_ff}, {x.phi, x.theta, x.chi, x.p, x.q, -x.p_d, x.Va}, dt);
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

  /// Between flights: as after configure() (integrators clean; the next step integrates nothing).
  void reset() override { flight_ = Flight{}; }

  /// Handover from another controller: integrators clean, except the throttle's, which starts
  /// where the outgoing controller left the throttle.
  void take_over(const tern::msg::Actuators& last) override {
    reset();
    flight_.slc.set_gains(gains_);
    if (state_->valid && command_.has_value()) flight_.slc.take_over(last.delta_t, command_->Va_c - state_->Va);
  }

 private:
  tern::Input<tern::msg::State> state_;
  tern::Input<tern::msg::ControllerCommand> command_;
  tern::Input<tern::msg::FlightPhase> phase_;
  tern::Output<tern::msg::Actuators> actuators_;
  tern::Output<tern::msg::ControllerInternals> internals_;
  tern_@NAME@::Gains gains_;  ///< the parameters' values (slc.hpp: names, defaults, ranges)
  /// What a flight changes; reset() replaces it with a fresh one.
  struct Flight {
    tern_@NAME@::Slc slc;         ///< the loops' integrators (step() gives it gains_ first)
    tern::Nanos last_step = -1;  ///< time of the previous step, -1: none this flight
  } flight_;
};
