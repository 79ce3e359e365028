// @CLASS@: a simulator I/O plugin around GuidanceModel (guidance_model.hpp): the aircraft as
// its autopilot makes it behave, for fast tests of guidance (path planner, manager, follower)
// without aerodynamics, sensors or an estimator.
//
// Ports:  in  controller_command  msg::ControllerCommand (chi_c, h_c, Va_c, phi_ff), optional:
//                                 without one the aircraft keeps its initial course, height, speed
//         out truth               msg::State of the model (p, v, phi, theta = gamma, psi = chi,
//                                 Va, chi, Vg = Va, gamma; no wind, alpha = beta = 0), valid
// Parameters: initial state (init_*, start-only: read at a flight's first step), model gains
// (b_*), phi_max, max_climb_rate, and the geodetic origin reported in the state (default:
// sim_aero's).
// Per-flight state (tern/plugin.hpp): everything a flight changes is in `flight_`, which
// reset() replaces wholesale; a new state variable or counter goes there.
#pragma once

#include <cmath>
#include <vector>

#include "guidance_model.hpp"
#include "tern/math.hpp"
#include "tern/plugin.hpp"

class @CLASS@ final : public tern::Plugin {
 public:
  void configure() override {
    using tern::ParamSpec;
    declare(command_, "controller_command", "course, altitude and airspeed commands", tern::Need::optional);
    declare(truth_, "truth", "state of the kinematic model");
    declare(init_position_, "init_position", std::vector<double>{0.0, 0.0},
            ParamSpec("m", -1e6, 1e6, "initial north, east position").of_size(2).start_only());
    declare(init_altitude_, "init_altitude", 100.0, ParamSpec("m", -500.0, 10000.0, "initial height above the origin").start_only());
    declare(init_airspeed_, "init_airspeed", 17.0, ParamSpec("m/s", 1.0, 100.0, "initial airspeed").start_only());
    declare(init_heading_, "init_heading", 0.0, ParamSpec("rad", -7.0, 7.0, "initial course").start_only());
    const tern_@NAME@::ModelGains d;
    declare(b_chi_, "b_chi", d.b_chi, ParamSpec("1/s^2", 0.01, 100.0, "course stiffness"));
    declare(b_chidot_, "b_chidot", d.b_chidot, ParamSpec("1/s", 0.01, 100.0, "course-rate damping"));
    declare(b_h_, "b_h", d.b_h, ParamSpec("1/s^2", 0.01, 100.0, "altitude stiffness"));
    declare(b_hdot_, "b_hdot", d.b_hdot, ParamSpec("1/s", 0.01, 100.0, "climb-rate damping"));
    declare(b_Va_, "b_Va", d.b_Va, ParamSpec("1/s", 0.01, 100.0, "airspeed response"));
    declare(phi_max_, "phi_max", d.phi_max, ParamSpec("rad", 0.05, 1.2, "roll limit of the coordinated turn"));
    declare(max_climb_rate_, "max_climb_rate", d.max_climb_rate, ParamSpec("m/s", 0.1, 50.0, "climb and sink rate limit"));
    declare(origin_lat_, "origin_lat", 40.2463724, ParamSpec("deg", -90.0, 90.0, "latitude of the NED origin"));
    declare(origin_lon_, "origin_lon", -111.6474138, ParamSpec("deg", -180.0, 180.0, "longitude of the NED origin"));
    declare(origin_alt_, "origin_alt", 1387.0, ParamSpec("m", -500.0, 9000.0, "altitude (MSL) of the NED origin"));
  }

  /// Between flights: as after configure(); the next step starts the model at the init_* values.
  void reset() override { flight_ = Flight{}; }

  void step(tern::Nanos now) override {
    flight_.model.set_gains({b_chi_(), b_chidot_(), b_h_(), b_hdot_(), b_Va_(), phi_max_(), max_climb_rate_()});
    if (flight_.last_step < 0) {
      begin_flight();
    } else {
      tern_@NAME@::ModelCommand c = flight_.hold;
      if (command_.has_value()) c = {command_->chi_c, command_->h_c, command_->Va_c, command_->phi_ff};
      flight_.model.step(c, tern::to_seconds(now - flight_.last_step));
    }
    flight_.last_step = now;
    publish(now);
  }

 private:
  /// A flight's first step: the model at the initial state the init_* parameters give now.
  void begin_flight() {
    tern_@NAME@::ModelState x;
    x.p_n = init_position_()[0];
    x.p_e = init_position_()[1];
    x.h = init_altitude_();
    x.Va = init_airspeed_();
    x.chi = tern::wrap_pi(init_heading_());
    flight_.model.set_state(x);
    flight_.hold = {x.chi, x.h, x.Va, 0.0};
  }

  void publish(tern::Nanos now) {
    const tern_@NAME@::GuidanceModel& model = flight_.model;
    const tern_@NAME@::ModelState& m = model.state();
    const double gamma = model.gamma();
    tern::msg::State s;
    s.stamp = now;
    s.p_n = m.p_n;
    s.p_e = m.p_e;
    s.p_d = -m.h;
    s.v_n = m.Va * std::cos(m.chi) * std::cos(gamma);
    s.v_e = m.Va * std::sin(m.chi) * std::cos(gamma);
    s.v_d = -m.h_dot;
    s.phi = model.phi();
    s.theta = gamma;
    s.psi = m.chi;
    s.quat = tern::quaternion_from_euler(s.phi, s.theta, s.psi);
    const Eigen::Vector3d v_body = tern::rotation_from_euler(s.phi, s.theta, s.psi).transpose() *
                                   Eigen::Vector3d(s.v_n, s.v_e, s.v_d);
    s.u = v_body.x();
    s.v = v_body.y();
    s.w = v_body.z();
    s.r = m.chi_dot * std::cos(s.phi);  // coordinated turn, small pitch
    s.q = m.chi_dot * std::sin(s.phi);
    s.Va = m.Va;
    s.chi = m.chi;
    s.Vg = m.Va * std::cos(gamma);
    s.gamma = gamma;
    s.origin_lat = origin_lat_();
    s.origin_lon = origin_lon_();
    s.origin_alt = origin_alt_();
    s.origin_valid = true;
    s.valid = true;
    truth_.publish(s);
  }

  tern::Input<tern::msg::ControllerCommand> command_;
  tern::Output<tern::msg::State> truth_;
  tern::Param<std::vector<double>> init_position_;
  tern::Param<double> init_altitude_, init_airspeed_, init_heading_;
  tern::Param<double> b_chi_, b_chidot_, b_h_, b_hdot_, b_Va_, phi_max_, max_climb_rate_;
  tern::Param<double> origin_lat_, origin_lon_, origin_alt_;
  /// What a flight changes; reset() replaces it with a fresh one.
  struct Flight {
    tern_@NAME@::GuidanceModel model;  ///< the aircraft (step() gives it the b_* gains first)
    tern_@NAME@::ModelCommand hold;    ///< flown until a controller_command comes: the initial course, height, speed
    tern::Nanos last_step = -1;       ///< time of the previous step, -1: none this flight
  } flight_;
};
