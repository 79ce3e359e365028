// Closed-loop test support shared by the control_slc and control_tecs tests: a controller
// plugin in the SDK harness flying the linearised test plant (linear_model.hpp) at 100 Hz,
// the flat gains files of configs/gains/, and step-response figures.
#pragma once

#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "control_common/testing/linear_model.hpp"
#include "tern/math.hpp"
#include "tern/testing/harness.hpp"

namespace tern::control::testmodel {

/// Reads a flat `param: value` YAML file into harness parameters (bool or real values).
inline std::map<std::string, ParamValue> load_gains(const std::string& path) {
  const YAML::Node doc = YAML::LoadFile(path);
  std::map<std::string, ParamValue> out;
  for (const auto& kv : doc) {
    const auto name = kv.first.as<std::string>();
    const auto text = kv.second.as<std::string>();
    if (text == "true" || text == "false") {
      out[name] = (text == "true");
    } else {
      try {
        out[name] = kv.second.as<double>();
      } catch (const YAML::Exception&) {
        out[name] = text;
      }
    }
  }
  return out;
}

inline msg::State to_state(const LinearAircraft& plant, Nanos t) {
  const VehicleState x = plant.state();
  msg::State s;
  s.stamp = t;
  s.phi = x.phi;
  s.theta = x.theta;
  s.psi = x.chi;
  s.chi = x.chi;
  s.quat = quaternion_from_euler(x.phi, x.theta, x.chi);
  s.p = x.p;
  s.q = x.q;
  s.r = x.r;
  s.p_d = -x.h;
  s.v_d = -x.h_dot;
  s.v_n = x.Va * std::cos(x.chi);
  s.v_e = x.Va * std::sin(x.chi);
  s.Va = x.Va;
  s.Vg = x.Va;
  s.gamma = x.theta - plant.coefficients().alpha_trim;
  s.alpha = plant.coefficients().alpha_trim;
  s.valid = true;
  return s;
}

/// A controller plugin flying the linear plant at 100 Hz.
class ClosedLoop {
 public:
  ClosedLoop(std::unique_ptr<Plugin> controller, const Coefficients& k, std::map<std::string, ParamValue> params)
      : h(std::move(controller), std::move(params)), plant(k) {
    cmd.Va_c = k.Va_trim;
    cmd.h_c = plant.h;
    cmd.chi_c = 0.0;
  }
  testing::Harness h;
  LinearAircraft plant;
  msg::ControllerCommand cmd;
  Nanos t = 0;
  static constexpr double dt = 0.01;

  /// Runs `seconds`; `watch` sees the plant after every step.
  void run(double seconds, const std::function<void(double t, const LinearAircraft&)>& watch = {}) {
    const int n = static_cast<int>(std::lround(seconds / dt));
    for (int i = 0; i < n; ++i) {
      h.set_input("state", to_state(plant, t));
      h.set_input("controller_command", cmd);
      h.step(t);
      const auto& a = h.output<msg::Actuators>("actuators");
      last = {a.delta_a, a.delta_e, a.delta_r, a.delta_t};
      plant.step(last, dt);
      t += from_seconds(dt);
      if (watch) watch(to_seconds(t), plant);
    }
  }
  Surfaces last;
};

/// A controller (built from `gains`) on a plant whose trim differs from the gains file's
/// (elevator +0.02 rad, throttle +0.03), flown 30 s so that the integrators found the trim.
inline std::unique_ptr<ClosedLoop> settled_loop(std::unique_ptr<Plugin> controller, const Coefficients& k, const std::string& gains) {
  auto L = std::make_unique<ClosedLoop>(std::move(controller), k, load_gains(gains));
  L->plant.delta_e_offset = 0.02;
  L->plant.delta_t_offset = 0.03;
  L->run(30.0);
  return L;
}

/// Step-response figures of y towards `target` from a start value: overshoot past the target
/// (in the direction of the step, >= 0) and the time after which |y - target| stays within band.
struct StepResponse {
  double start, target, band;
  double overshoot = 0.0;
  double settle_time = 0.0;
  void add(double t, double y) {
    const double dir = target >= start ? 1.0 : -1.0;
    overshoot = std::max(overshoot, dir * (y - target));
    if (std::fabs(y - target) > band) settle_time = t;
  }
};

}  // namespace tern::control::testmodel
