// control_slc: successive loop closure autopilot (Beard & McLain ch. 6, ROSplane 2.0's
// controller_successive_loop). The loops live in plugins/control_common (autopilot.hpp,
// loops.hpp); this class declares the parameters of the longitudinal law (altitude -> pitch PI,
// airspeed -> throttle PI). Ports and the shared parameters: control_common/controller_plugin.hpp.
#pragma once

#include "control_common/controller_plugin.hpp"

namespace tern::control {

class ControlSlc final : public ControllerPlugin {
 protected:
  void declare_law_params() override {
    declare_gain(altitude_kp_, "altitude_kp", 0.015, ParamSpec("rad/m", 0.0, 5.0, "altitude -> pitch proportional gain (ROSplane a_kp)"));
    declare_gain(altitude_ki_, "altitude_ki", 0.001, ParamSpec("rad/(m s)", 0.0, 5.0, "altitude -> pitch integral gain (a_ki)"));
    declare_gain(altitude_kd_, "altitude_kd", 0.0, ParamSpec("rad/(m/s)", 0.0, 5.0, "altitude -> pitch gain on climb rate (a_kd)"));
    declare_gain(airspeed_kp_, "airspeed_kp", 0.1, ParamSpec("1/(m/s)", 0.0, 5.0, "airspeed -> throttle proportional gain (a_t_kp)"));
    declare_gain(airspeed_ki_, "airspeed_ki", 0.02, ParamSpec("1/m", 0.0, 5.0, "airspeed -> throttle integral gain (a_t_ki)"));
    declare_gain(airspeed_kd_, "airspeed_kd", 0.0, ParamSpec("1/(m/s^2)", 0.0, 5.0, "airspeed -> throttle gain on dVa/dt (a_t_kd)"));
    declare_gain(derivative_tau_, "derivative_tau", 0.05, ParamSpec("s", 0.001, 10.0, "dirty-derivative time constant for dVa/dt"));
  }
  void apply_law_params() override {
    law_.set_gains({altitude_kp_, altitude_ki_, altitude_kd_, theta_max_, theta_min_},
                   {airspeed_kp_, airspeed_ki_, airspeed_kd_, trim_t_, max_t_, min_t(), derivative_tau_});
  }
  LongitudinalLaw& law() override { return law_; }

 private:
  SlcLongitudinal law_;
  Param<double> altitude_kp_, altitude_ki_, altitude_kd_;
  Param<double> airspeed_kp_, airspeed_ki_, airspeed_kd_, derivative_tau_;
};

}  // namespace tern::control
