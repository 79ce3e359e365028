// attitude_hold.hpp: wings-level, pitch-hold and airspeed-hold autopilot (plain C++, no tern
// types), after Beard & McLain, *Small Unmanned Aircraft*, ch. 6 (successive loop closure):
//   roll hold     delta_a = trim_a + kp_phi (phi_c - phi) - kd_phi p                 (sec. 6.1.1)
//   pitch hold    delta_e = trim_e - kp_theta (theta_c - theta) + kd_theta q         (sec. 6.1.2)
//   airspeed      delta_t = trim_t + kp_V (Va_c - Va) + ki_V int(Va_c - Va) dt       (sec. 6.1.2,
//                 airspeed hold with throttle)
// Signs follow tern's actuators (uavbook 4.2): positive delta_a rolls right, positive delta_e
// pitches the nose down. The default gains and trims suit the Anaconda near 17 m/s
// (configs/aircraft/anaconda.yaml: tern aero trim --Va 17 gives delta_e 0.168, delta_t 0.568).
#pragma once

namespace tern_@NAME@ {

struct Gains {
  double roll_kp = 1.0;    ///< aileron per roll error, rad/rad
  double roll_kd = 0.05;   ///< aileron per roll rate, rad/(rad/s)
  double pitch_kp = 3.0;   ///< elevator per pitch error, rad/rad
  double pitch_kd = 0.2;   ///< elevator per pitch rate, rad/(rad/s)
  double airspeed_kp = 0.2;   ///< throttle per airspeed error, 1/(m/s)
  double airspeed_ki = 0.1;   ///< throttle per integrated airspeed error, 1/m
  double trim_a = 0.0;     ///< aileron at trim, rad
  double trim_e = 0.168;   ///< elevator at trim, rad
  double trim_t = 0.568;   ///< throttle at trim, 0..1
  double max_a = 0.6;      ///< aileron limit, rad (symmetric)
  double max_e = 0.6;      ///< elevator limit, rad (symmetric)
};

/// Aircraft state the loops use (uavbook symbols; angles rad, rates rad/s, Va m/s).
struct Attitude {
  double phi = 0.0, theta = 0.0, p = 0.0, q = 0.0, Va = 0.0;
};

/// Commands: roll phi_c (rad), pitch theta_c (rad), airspeed Va_c (m/s).
struct Setpoint {
  double phi_c = 0.0, theta_c = 0.0, Va_c = 17.0;
};

/// Surface and throttle commands: delta_a, delta_e in rad (saturated), delta_t in [0, 1].
struct Surfaces {
  double delta_a = 0.0, delta_e = 0.0, delta_t = 0.0;
};

class AttitudeHold {
 public:
  explicit AttitudeHold(Gains g = {}) : g_(g) {}
  void set_gains(const Gains& g) { g_ = g; }
  const Gains& gains() const { return g_; }

  /// One control step of length dt (s, >= 0; 0 on a first step: no integration). Non-finite or
  /// negative inputs give the trim surfaces and leave
  /// the integrator unchanged. The throttle integrator stops growing while the throttle is
  /// saturated (anti-windup).
  Surfaces update(const Setpoint& sp, const Attitude& x, double dt);

  /// Integrators clean (start of a flight).
  void reset() { Va_integral_ = 0.0; }
  /// Bumpless transfer: sets the integrator so that the next throttle command equals delta_t
  /// when the airspeed error is Va_error (m/s).
  void take_over(double delta_t, double Va_error);

 private:
  Gains g_;
  double Va_integral_ = 0.0;  ///< integral of (Va_c - Va), m
};

}  // namespace tern_@NAME@
