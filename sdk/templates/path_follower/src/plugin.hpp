// @CLASS@: the tern adapter of the vector-field follower (vector_field.hpp).
//
// Ports:  in  state               msg::State (p_n, p_e, p_d, chi, Va); nothing published while !valid
//         in  current_path        msg::CurrentPath from the path manager (line or orbit)
//         out controller_command  msg::ControllerCommand: Va_c (the path's Va_d), h_c, chi_c, phi_ff
// Parameters: chi_inf, k_path, k_orbit (vector_field.hpp).
// Per-flight state (tern/plugin.hpp): everything a flight changes is in `flight_`, which
// reset() replaces wholesale; a new filter, counter or "warned once" flag goes there.
#pragma once

#include <cmath>

#include <spdlog/spdlog.h>

#include "tern/plugin.hpp"
#include "vector_field.hpp"

class @CLASS@ final : public tern::Plugin {
 public:
  void configure() override {
    using tern::ParamSpec;
    declare(state_, "state", "vehicle state (position, course, airspeed)");
    declare(path_, "current_path", "the segment to follow, from the path manager");
    declare(command_, "controller_command", "Va_c, h_c, chi_c and the orbit feed-forward phi_ff");
    const tern_@NAME@::FollowerGains d;
    declare(chi_inf_, "chi_inf", d.chi_inf, ParamSpec("rad", 0.05, 1.5708, "course approach angle far from the line"));
    declare(k_path_, "k_path", d.k_path, ParamSpec("1/m", 1e-4, 1.0, "line convergence gain"));
    declare(k_orbit_, "k_orbit", d.k_orbit, ParamSpec("", 0.01, 20.0, "orbit convergence gain"));
  }

  void step(tern::Nanos now) override {
    const tern::msg::State& x = *state_;
    if (!x.valid || !path_.has_value()) return;  // no guidance without a state and a path
    const tern::msg::CurrentPath& path = *path_;
    const tern_@NAME@::FollowerGains g{chi_inf_(), k_path_(), k_orbit_()};
    const Eigen::Vector3d p(x.p_n, x.p_e, x.p_d);
    const tern_@NAME@::Guidance u =
        path.path_type == tern::msg::CurrentPath::orbit
            ? tern_@NAME@::follow_orbit(path.c, path.rho, path.lambda, p, x.chi, x.Va, g)
            : tern_@NAME@::follow_line(path.r, path.q, p, x.chi, g);
    if (!std::isfinite(u.chi_c) || !std::isfinite(u.h_c)) {
      if (!flight_.warned_degenerate) log().warn("current_path is degenerate (zero direction or NaN): command not updated");
      flight_.warned_degenerate = true;
      return;
    }
    tern::msg::ControllerCommand c;
    c.stamp = now;
    c.Va_c = path.Va_d;
    c.chi_c = u.chi_c;
    c.h_c = u.h_c;
    c.phi_ff = u.phi_ff;
    command_.publish(c);
  }

  /// Between flights: as after configure().
  void reset() override { flight_ = Flight{}; }

 private:
  tern::Input<tern::msg::State> state_;
  tern::Input<tern::msg::CurrentPath> path_;
  tern::Output<tern::msg::ControllerCommand> command_;
  tern::Param<double> chi_inf_, k_path_, k_orbit_;
  /// What a flight changes; reset() replaces it with a fresh one.
  struct Flight {
    bool warned_degenerate = false;  ///< the degenerate-path warning was logged (once a flight)
  } flight_;
};
