// control_tecs/tecs.hpp: total energy control of the longitudinal axes (Lambregts, "Vertical
// flight path and speed control autopilot design using total energy principles", AIAA 83-2239;
// the form used by ArduPilot's TECS and ROSplane 2.0's controller_total_energy).
//
// Specific energy rates normalised by g Va (dimensionless):
//   total    E_dot / (m g Va) = gamma + Va_dot / g          (thrust changes it)
//   balance  B_dot / (m g Va) = gamma - Va_dot / g          (pitch trades one for the other)
// Demands from the outer errors, with limits:
//   h_dot_c  = sat(h_kp (h_c - h), -sink_rate_max, climb_rate_max),  gamma_c = h_dot_c / Va
//   Va_c'    = sat(Va_c, Va_min, Va_max)
//   Va_dot_c = sat(Va_kp (Va_c' - Va), -Va_dot_max, Va_dot_max)
// Errors: e_E = (gamma_c - gamma) + (Va_dot_c - Va_dot)/g,
//         e_B = w_gamma (gamma_c - gamma) - w_V (Va_dot_c - Va_dot)/g   (w_gamma = w_V = 1)
// Laws (PI with saturation and integrator clamping, control_common/pid.hpp):
//   delta_t = sat(trim_t + energy_ff (gamma_c + Va_dot_c/g) + energy_kp e_E + energy_ki int(e_E), [min_t, max_t])
//   theta_c = sat(balance_ff (w_gamma gamma_c - w_V Va_dot_c/g) + balance_kp e_B + balance_ki int(e_B),
//                 [theta_min, theta_max])
// The pitch command is slew-rate limited to theta_rate_max (the acceleration term reacts fast).
// Underspeed protection: below Va_min the throttle goes to max_t and the balance weights become
// w_gamma = 0, w_V = 2 (pitch controls speed only; the height demand is dropped) until the airspeed
// is back above Va_min + underspeed_hysteresis.
// Measurements: gamma = h_dot / max(Va, 1 m/s); Va_dot from a dirty derivative of Va.
// Plain C++, no tern host types.
#pragma once

#include "control_common/autopilot.hpp"
#include "control_common/pid.hpp"

namespace tern::control {

struct TecsGains {
  double energy_kp = 0.3;              ///< throttle per unit normalised energy-rate error
  double energy_ki = 1.2;              ///< throttle per unit error per s
  double energy_ff = 0.64;             ///< throttle per unit normalised energy-rate demand (g / a_V2)
  double balance_kp = 0.3;             ///< rad pitch per unit balance-rate error
  double balance_ki = 1.0;             ///< rad pitch per unit error per s
  double balance_ff = 1.0;             ///< rad pitch per unit balance-rate demand
  double h_kp = 0.5;                   ///< 1/s
  double climb_rate_max = 3.0;         ///< m/s
  double sink_rate_max = 3.0;          ///< m/s
  double Va_kp = 0.5;                  ///< 1/s
  double Va_dot_max = 2.0;             ///< m/s^2
  double Va_min = 13.0;                ///< m/s, underspeed threshold and lowest airspeed demand
  double Va_max = 35.0;                ///< m/s, highest airspeed demand
  double underspeed_hysteresis = 1.0;  ///< m/s
  double Va_dot_tau = 0.2;             ///< dirty-derivative time constant for Va_dot, s
  double theta_rate_max = 0.5;         ///< slew-rate limit of the pitch command, rad/s
  // Trim and limits: the parameters of control_common's LongitudinalLimits.
  double trim_t = LongitudinalLimits{}.trim_t, min_t = LongitudinalLimits{}.min_t, max_t = LongitudinalLimits{}.max_t;
  double theta_min = LongitudinalLimits{}.theta_min, theta_max = LongitudinalLimits{}.theta_max;  ///< rad

  /// The law's own gains as plugin parameters (trim and limits are LongitudinalLimits').
  template <class V>
  static void describe(V& v) {
    using tern::ParamSpec;
    using G = TecsGains;
    v(&G::energy_kp, "energy_kp", ParamSpec("", 0.0, 10.0, "throttle per unit specific total-energy-rate error (gamma + Va_dot/g)"));
    v(&G::energy_ki, "energy_ki", ParamSpec("1/s", 0.0, 20.0, "integral gain of the total-energy-rate error"));
    v(&G::energy_ff, "energy_ff", ParamSpec("", 0.0, 10.0, "throttle feed-forward per unit energy-rate demand (about g / a_V2)"));
    v(&G::balance_kp, "balance_kp", ParamSpec("rad", 0.0, 10.0, "pitch per unit energy-balance-rate error (gamma - Va_dot/g)"));
    v(&G::balance_ki, "balance_ki", ParamSpec("rad/s", 0.0, 20.0, "integral gain of the energy-balance-rate error"));
    v(&G::balance_ff, "balance_ff", ParamSpec("rad", 0.0, 5.0, "pitch feed-forward per unit balance-rate demand"));
    v(&G::h_kp, "h_kp", ParamSpec("1/s", 0.0, 5.0, "climb-rate demand per metre of altitude error"));
    v(&G::climb_rate_max, "climb_rate_max", ParamSpec("m/s", 0.1, 30.0, "largest climb-rate demand"));
    v(&G::sink_rate_max, "sink_rate_max", ParamSpec("m/s", 0.1, 30.0, "largest sink-rate demand"));
    v(&G::Va_kp, "Va_kp", ParamSpec("1/s", 0.0, 5.0, "acceleration demand per m/s of airspeed error"));
    v(&G::Va_dot_max, "Va_dot_max", ParamSpec("m/s^2", 0.1, 20.0, "largest acceleration demand"));
    v(&G::Va_min, "Va_min", ParamSpec("m/s", 0.0, 100.0, "underspeed threshold and lowest airspeed demand"));
    v(&G::Va_max, "Va_max", ParamSpec("m/s", 1.0, 200.0, "highest airspeed demand"));
    v(&G::underspeed_hysteresis, "underspeed_hysteresis", ParamSpec("m/s", 0.0, 20.0, "underspeed ends above Va_min plus this"));
    v(&G::Va_dot_tau, "Va_dot_tau", ParamSpec("s", 0.001, 10.0, "dirty-derivative time constant for Va_dot"));
    v(&G::theta_rate_max, "theta_rate_max", ParamSpec("rad/s", 0.01, 10.0, "slew-rate limit of the pitch command"));
  }
};

class Tecs final : public LongitudinalLaw {
 public:
  Tecs() { set_gains({}); }
  void set_gains(const TecsGains& g);
  const TecsGains& gains() const { return g_; }
  Output update(const VehicleState& x, const Command& c, bool climb, double dt) override;
  void initialise(const VehicleState& x, const Command& c, double theta_c, double delta_t) override;
  void reset() override;
  double theta_min() const override { return g_.theta_min; }
  double theta_max() const override { return g_.theta_max; }
  bool underspeed() const { return underspeed_; }

 private:
  struct Errors {
    double e_E, e_B, ff_t, ff_theta;
  };
  Errors errors(const VehicleState& x, const Command& c, double Va_dot) const;
  TecsGains g_;
  Pid throttle_, pitch_;
  DirtyDerivative Va_dot_;
  bool underspeed_ = false;
  bool have_theta_c_ = false;
  double theta_c_ = 0.0;
};

}  // namespace tern::control
