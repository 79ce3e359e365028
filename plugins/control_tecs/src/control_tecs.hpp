// control_tecs: total energy control (control_tecs/tecs.hpp) for the longitudinal axes, with the
// lateral loops, pitch loop, phases and manual modes of plugins/control_common (the same code
// as control_slc, not a copy). Ports and shared parameters: control_common/controller_plugin.hpp.
#pragma once

#include "control_common/controller_plugin.hpp"
#include "control_tecs/tecs.hpp"

namespace tern::control {

class ControlTecs final : public ControllerPlugin {
 protected:
  void declare_law_params() override {
    declare_gain(energy_kp_, "energy_kp", 0.3, ParamSpec("", 0.0, 10.0, "throttle per unit specific total-energy-rate error (gamma + Va_dot/g)"));
    declare_gain(energy_ki_, "energy_ki", 1.2, ParamSpec("1/s", 0.0, 20.0, "integral gain of the total-energy-rate error"));
    declare_gain(energy_ff_, "energy_ff", 0.64, ParamSpec("", 0.0, 10.0, "throttle feed-forward per unit energy-rate demand (about g / a_V2)"));
    declare_gain(balance_kp_, "balance_kp", 0.3, ParamSpec("rad", 0.0, 10.0, "pitch per unit energy-balance-rate error (gamma - Va_dot/g)"));
    declare_gain(balance_ki_, "balance_ki", 1.0, ParamSpec("rad/s", 0.0, 20.0, "integral gain of the energy-balance-rate error"));
    declare_gain(balance_ff_, "balance_ff", 1.0, ParamSpec("rad", 0.0, 5.0, "pitch feed-forward per unit balance-rate demand"));
    declare_gain(h_kp_, "h_kp", 0.5, ParamSpec("1/s", 0.0, 5.0, "climb-rate demand per metre of altitude error"));
    declare_gain(climb_rate_max_, "climb_rate_max", 3.0, ParamSpec("m/s", 0.1, 30.0, "largest climb-rate demand"));
    declare_gain(sink_rate_max_, "sink_rate_max", 3.0, ParamSpec("m/s", 0.1, 30.0, "largest sink-rate demand"));
    declare_gain(Va_kp_, "Va_kp", 0.5, ParamSpec("1/s", 0.0, 5.0, "acceleration demand per m/s of airspeed error"));
    declare_gain(Va_dot_max_, "Va_dot_max", 2.0, ParamSpec("m/s^2", 0.1, 20.0, "largest acceleration demand"));
    declare_gain(Va_min_, "Va_min", 13.0, ParamSpec("m/s", 0.0, 100.0, "underspeed threshold and lowest airspeed demand"));
    declare_gain(Va_max_, "Va_max", 35.0, ParamSpec("m/s", 1.0, 200.0, "highest airspeed demand"));
    declare_gain(underspeed_hysteresis_, "underspeed_hysteresis", 1.0, ParamSpec("m/s", 0.0, 20.0, "underspeed ends above Va_min plus this"));
    declare_gain(Va_dot_tau_, "Va_dot_tau", 0.2, ParamSpec("s", 0.001, 10.0, "dirty-derivative time constant for Va_dot"));
    declare_gain(theta_rate_max_, "theta_rate_max", 0.5, ParamSpec("rad/s", 0.01, 10.0, "slew-rate limit of the pitch command"));
  }
  void apply_law_params() override {
    TecsGains g;
    g.energy_kp = energy_kp_;
    g.energy_ki = energy_ki_;
    g.energy_ff = energy_ff_;
    g.balance_kp = balance_kp_;
    g.balance_ki = balance_ki_;
    g.balance_ff = balance_ff_;
    g.h_kp = h_kp_;
    g.climb_rate_max = climb_rate_max_;
    g.sink_rate_max = sink_rate_max_;
    g.Va_kp = Va_kp_;
    g.Va_dot_max = Va_dot_max_;
    g.Va_min = Va_min_;
    g.Va_max = Va_max_;
    g.underspeed_hysteresis = underspeed_hysteresis_;
    g.Va_dot_tau = Va_dot_tau_;
    g.theta_rate_max = theta_rate_max_;
    g.trim_t = trim_t_;
    g.min_t = min_t();
    g.max_t = max_t_;
    g.theta_min = theta_min_;
    g.theta_max = theta_max_;
    law_.set_gains(g);
  }
  LongitudinalLaw& law() override { return law_; }

 private:
  Tecs law_;
  Param<double> energy_kp_, energy_ki_, energy_ff_, balance_kp_, balance_ki_, balance_ff_;
  Param<double> h_kp_, climb_rate_max_, sink_rate_max_, Va_kp_, Va_dot_max_, Va_min_, Va_max_;
  Param<double> underspeed_hysteresis_, Va_dot_tau_, theta_rate_max_;
};

}  // namespace tern::control
