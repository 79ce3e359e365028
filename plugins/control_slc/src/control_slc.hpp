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
    declare_gains(altitude_);
    declare_gains(airspeed_);
  }
  void apply_law_params() override {
    AltitudeGains a = altitude_;
    a.theta_max = limits_.theta_max;
    a.theta_min = limits_.theta_min;
    AirspeedGains v = airspeed_;
    v.trim_t = limits_.trim_t;
    v.max_t = limits_.max_t;
    v.min_t = min_t();
    law_.set_gains(a, v);
  }
  LongitudinalLaw& law() override { return law_; }

 private:
  SlcLongitudinal law_;
  AltitudeGains altitude_;  ///< altitude_kp, altitude_ki, altitude_kd (AltitudeGains::describe)
  AirspeedGains airspeed_;  ///< airspeed_kp, airspeed_ki, airspeed_kd, derivative_tau
};

}  // namespace tern::control
