// control_tecs: total energy control (control_tecs/tecs.hpp) for the longitudinal axes, with the
// lateral loops, pitch loop, phases and manual modes of plugins/control_common (the same code
// as control_slc, not a copy). Ports and shared parameters: control_common/controller_plugin.hpp.
#pragma once

#include "control_common/controller_plugin.hpp"
#include "control_tecs/tecs.hpp"

namespace tern::control {

class ControlTecs final : public ControllerPlugin {
 protected:
  void declare_law_params() override { declare_gains(gains_); }
  void apply_law_params() override {
    TecsGains g = gains_;
    g.trim_t = limits_.trim_t;
    g.min_t = min_t();
    g.max_t = limits_.max_t;
    g.theta_min = limits_.theta_min;
    g.theta_max = limits_.theta_max;
    law_.set_gains(g);
  }
  LongitudinalLaw& law() override { return law_; }

 private:
  Tecs law_;
  TecsGains gains_;  ///< the law's parameters (TecsGains::describe)
};

}  // namespace tern::control
