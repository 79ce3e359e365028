// control_common/loops.hpp: the successive-loop-closure autopilot loops of Beard & McLain,
// *Small Unmanned Aircraft*, ch. 6, as used by ROSplane 2.0 (controller_successive_loop):
//
//   course -> roll     phi_c   = sat(phi_ff + kp e_chi + ki int(e_chi) - kd r, +-roll_max)   (6.1.2)
//   roll -> aileron    delta_a = sat(trim_a + k_ff p_c + kp e_phi + ki int(e_phi) - kd p, +-max_a) (6.1.1)
//   with the roll command slew-limited to +-roll_rate_max and p_c its rate (command shaping:
//   the roll loop is type 0, so a ramp in phi_c is followed with a lag unless its rate is fed
//   forward; k_ff = a_phi1/a_phi2 is the aileron that sustains the roll rate p_c, uavbook eq. 5.26)
//   yaw damper         delta_r = sat(trim_r + kr s/(s + p_wo) r, +-max_r)                     (6.1.3)
//   pitch -> elevator  delta_e = sat(trim_e - (kp e_theta + ki int(e_theta) - kd q), +-max_e) (6.2.1)
//   altitude -> pitch  theta_c = sat(kp e_h + ki int(e_h) - kd h_dot, [theta_min, theta_max]) (6.2.2)
//   airspeed -> thr.   delta_t = sat(trim_t + kp e_V + ki int(e_V) - kd Va_dot, [min_t, max_t]) (6.2.3)
//
// Units: angles rad, rates rad/s, altitude m (up), airspeed m/s, throttle 0..1. Signs of the
// surfaces as the uavbook (positive delta_a rolls right, positive delta_e pitches nose down,
// positive delta_r yaws nose left). All gains are magnitudes (>= 0); the pitch loop applies the
// sign of C_m_delta_e < 0 itself, so pitch_kp = -k_p_theta of the book.
// Course errors are wrapped to [-pi, pi). Every loop saturates and clamps its integrator.
//
// Each gain struct names its fields as plugin parameters in describe() (tern/param_struct.hpp):
// the member initialiser is the parameter's one default, the name there is the one the mission
// config uses (ROSplane's name in parentheses in the description).
#pragma once

#include <limits>

#include "control_common/pid.hpp"
#include "tern/param.hpp"

namespace tern::control {

/// What the loops read of the vehicle state.
struct VehicleState {
  double phi = 0.0, theta = 0.0, chi = 0.0;  ///< roll, pitch, course over ground, rad
  double p = 0.0, q = 0.0, r = 0.0;          ///< body rates, rad/s
  double h = 0.0;                            ///< altitude (up), m
  double h_dot = 0.0;                        ///< climb rate, m/s
  double Va = 0.0;                           ///< airspeed, m/s
  /// Height above the ground from a downward range finder, m (NaN: none; flare and rollout then
  /// measure the height from the altitude estimate). Not part of finite().
  double h_agl = std::numeric_limits<double>::quiet_NaN();
  bool finite() const;
};

/// Surface deflections (rad) and throttle (0..1).
struct Surfaces {
  double delta_a = 0.0, delta_e = 0.0, delta_r = 0.0, delta_t = 0.0;
  bool finite() const;
};

struct LateralGains {
  // Defaults: ROSplane 2.0's Anaconda values where a ROSplane parameter maps (see
  // plugins/control_slc/README.md for the table).
  double course_kp = 2.0;      ///< rad roll / rad course error
  double course_ki = 0.0025;   ///< rad roll / (rad s)
  double course_kd = 0.0;      ///< rad roll / (rad/s) yaw rate
  double roll_max = 0.7854;    ///< rad
  double roll_rate_max = 0.0;  ///< slew limit of the roll command, rad/s; 0: none
  double roll_ff = 0.0;        ///< rad aileron / (rad/s) of commanded roll rate p_c (a_phi1/a_phi2)
  double roll_kp = 0.55;       ///< rad aileron / rad roll error
  double roll_ki = 0.0;        ///< rad aileron / (rad s)
  double roll_kd = 0.2;        ///< rad aileron / (rad/s) roll rate
  double trim_a = 0.0;         ///< rad
  double max_a = 0.6981;       ///< rad (the Anaconda's 40-degree servo limit; ROSplane: 0.8)
  double yaw_kr = 0.3;         ///< rad rudder / (rad/s) washed-out yaw rate
  double yaw_p_wo = 0.5;       ///< washout pole, rad/s
  double trim_r = 0.0;         ///< rad
  double max_r = 0.523;        ///< rad

  template <class V>
  static void describe(V& v) {
    using tern::ParamSpec;
    using G = LateralGains;
    v(&G::course_kp, "course_kp", ParamSpec("rad/rad", 0.0, 20.0, "course -> roll proportional gain (ROSplane c_kp)"));
    v(&G::course_ki, "course_ki", ParamSpec("rad/(rad s)", 0.0, 10.0, "course -> roll integral gain (c_ki)"));
    v(&G::course_kd, "course_kd", ParamSpec("rad/(rad/s)", 0.0, 10.0, "course -> roll derivative gain, on yaw rate r (c_kd)"));
    v(&G::roll_max, "roll_max", ParamSpec("rad", 0.05, 1.4, "roll command limit (max_roll)"));
    v(&G::roll_rate_max, "roll_rate_max", ParamSpec("rad/s", 0.0, 20.0, "slew limit of the roll command; 0: none (ROSplane has none)"));
    v(&G::roll_ff, "roll_ff", ParamSpec("rad/(rad/s)", 0.0, 2.0, "aileron per commanded roll rate, feed-forward (design: a_phi1/a_phi2)"));
    v(&G::roll_kp, "roll_kp", ParamSpec("rad/rad", 0.0, 10.0, "roll -> aileron proportional gain (r_kp)"));
    v(&G::roll_ki, "roll_ki", ParamSpec("rad/(rad s)", 0.0, 10.0, "roll -> aileron integral gain (r_ki)"));
    v(&G::roll_kd, "roll_kd", ParamSpec("rad/(rad/s)", 0.0, 5.0, "roll -> aileron gain on roll rate p (r_kd)"));
    v(&G::trim_a, "trim_a", ParamSpec("rad", -0.5, 0.5, "aileron trim (trim_a)"));
    v(&G::max_a, "max_a", ParamSpec("rad", 0.01, 1.5, "aileron limit (ROSplane max_a 0.8; default: the Anaconda servo limit)"));
    v(&G::yaw_kr, "yaw_damper_kr", ParamSpec("rad/(rad/s)", 0.0, 5.0, "yaw damper gain on washed-out yaw rate"));
    v(&G::yaw_p_wo, "yaw_damper_p_wo", ParamSpec("rad/s", 0.0, 10.0, "yaw damper washout pole"));
    v(&G::trim_r, "trim_r", ParamSpec("rad", -0.5, 0.5, "rudder trim (trim_r)"));
    v(&G::max_r, "max_r", ParamSpec("rad", 0.01, 1.5, "rudder limit (max_r)"));
  }
};

/// Course hold, roll hold and yaw damper.
class LateralLoops {
 public:
  LateralLoops() { set_gains({}); }
  void set_gains(const LateralGains& g);
  const LateralGains& gains() const { return g_; }

  /// Course hold: roll command, rad. chi_c, chi in rad (any wrap), r in rad/s, phi_ff in rad.
  double course(double chi_c, double chi, double r, double phi_ff, double dt);
  /// Roll command shaping: phi_c slew-limited to +-roll_rate_max from the previous shaped
  /// command (none when roll_rate_max is 0, and on the first call after reset()); its rate p_c
  /// (dirty derivative, tau 0.05 s) is fed forward by roll(). Returns the shaped command, rad.
  double shape_roll(double phi_c, double dt);
  /// Bumpless transfer: the shaped command restarts at phi_c, with p_c = 0.
  void initialise_shape(double phi_c);
  /// Rate of the shaped roll command, rad/s.
  double p_c() const { return p_c_; }
  /// Roll hold: aileron, rad (with the feed-forward roll_ff p_c of the shaped command).
  double roll(double phi_c, double phi, double p, double dt);
  /// Yaw damper: rudder, rad.
  double yaw_damper(double r, double dt);

  /// The roll command for which the roll loop's proportional and derivative terms (no
  /// integrator) give `delta_a`, limited to +-roll_max; used for bumpless transfer.
  double roll_command_for(double delta_a, double phi, double p) const;
  /// Bumpless transfer: sets the course integrator so that course() gives phi_c now.
  void initialise_course(double phi_c, double chi_c, double chi, double r, double phi_ff);
  /// Bumpless transfer: sets the roll integrator so that roll() gives delta_a now.
  void initialise_roll(double delta_a, double phi_c, double phi, double p);
  /// The course loop is not in use (wings level, roll override): its integrator is cleared.
  void idle_course() { course_.reset(); }
  /// Clears the roll integrator (on the ground, where the gear holds the wings level).
  void reset_roll_integrator() { roll_.reset(); }

  void reset();

 private:
  LateralGains g_;
  Pid course_, roll_;
  Washout washout_;
  DirtyDerivative phi_c_dot_{0.05};
  double phi_c_prev_ = 0.0;
  bool shaped_ = false;
  double p_c_ = 0.0;
};

struct PitchGains {
  double kp = 4.25;        ///< rad elevator / rad pitch error (magnitude)
  double ki = 0.0;         ///< rad elevator / (rad s)
  double kd = 0.6;         ///< rad elevator / (rad/s) pitch rate
  double trim_e = -0.075;  ///< elevator at trim, rad (uavbook sign: negative is nose up)
  double max_e = 0.61;     ///< rad

  template <class V>
  static void describe(V& v) {
    using tern::ParamSpec;
    v(&PitchGains::kp, "pitch_kp", ParamSpec("rad/rad", 0.0, 50.0, "pitch -> elevator proportional gain, magnitude (p_kp)"));
    v(&PitchGains::ki, "pitch_ki", ParamSpec("rad/(rad s)", 0.0, 50.0, "pitch -> elevator integral gain (p_ki)"));
    v(&PitchGains::kd, "pitch_kd", ParamSpec("rad/(rad/s)", 0.0, 10.0, "pitch -> elevator gain on pitch rate q (p_kd)"));
    v(&PitchGains::trim_e, "trim_e", ParamSpec("rad", -0.6, 0.6, "elevator trim, uavbook sign: negative is nose up (-trim_e of ROSplane)"));
    v(&PitchGains::max_e, "max_e", ParamSpec("rad", 0.01, 1.5, "elevator limit (max_e)"));
  }
};

/// Limits and trim both longitudinal laws use (SLC and TECS): one set of parameters.
struct LongitudinalLimits {
  double theta_max = 0.35;   ///< pitch command upper limit, rad
  double theta_min = -0.35;  ///< pitch command lower limit, rad
  double trim_t = 0.5;       ///< throttle at trim, 0..1
  double max_t = 1.0;        ///< throttle upper limit
  double min_t = 0.0;        ///< throttle lower limit

  template <class V>
  static void describe(V& v) {
    using tern::ParamSpec;
    using L = LongitudinalLimits;
    v(&L::theta_max, "theta_max", ParamSpec("rad", 0.0, 1.2, "pitch command upper limit"));
    v(&L::theta_min, "theta_min", ParamSpec("rad", -1.2, 0.0, "pitch command lower limit"));
    v(&L::trim_t, "trim_t", ParamSpec("", 0.0, 1.0, "throttle at trim (trim_t)"));
    v(&L::max_t, "max_t", ParamSpec("", 0.0, 1.0, "throttle upper limit (max_t)"));
    v(&L::min_t, "min_t", ParamSpec("", 0.0, 1.0, "throttle lower limit"));
  }
};

/// Pitch hold (pitch attitude -> elevator).
class PitchLoop {
 public:
  PitchLoop() { set_gains({}); }
  void set_gains(const PitchGains& g);
  const PitchGains& gains() const { return g_; }
  /// Elevator, rad.
  double update(double theta_c, double theta, double q, double dt);
  /// Pitch command for which the P and D terms give delta_e (bumpless transfer), unlimited.
  double pitch_command_for(double delta_e, double theta, double q) const;
  void initialise(double delta_e, double theta_c, double theta, double q);
  void reset() { pid_.reset(); }

 private:
  PitchGains g_;
  Pid pid_;
};

struct AltitudeGains {
  double kp = 0.015;                                  ///< rad pitch / m
  double ki = 0.001;                                  ///< rad pitch / (m s)
  double kd = 0.0;                                    ///< rad pitch / (m/s) climb rate
  double theta_max = LongitudinalLimits{}.theta_max;  ///< rad (parameter of LongitudinalLimits)
  double theta_min = LongitudinalLimits{}.theta_min;  ///< rad

  /// The gains only; the limits are LongitudinalLimits' parameters.
  template <class V>
  static void describe(V& v) {
    using tern::ParamSpec;
    v(&AltitudeGains::kp, "altitude_kp", ParamSpec("rad/m", 0.0, 5.0, "altitude -> pitch proportional gain (ROSplane a_kp)"));
    v(&AltitudeGains::ki, "altitude_ki", ParamSpec("rad/(m s)", 0.0, 5.0, "altitude -> pitch integral gain (a_ki)"));
    v(&AltitudeGains::kd, "altitude_kd", ParamSpec("rad/(m/s)", 0.0, 5.0, "altitude -> pitch gain on climb rate (a_kd)"));
  }
};

/// Altitude hold: one PI(D) loop from altitude error to pitch command (no zones).
class AltitudeLoop {
 public:
  AltitudeLoop() { set_gains({}); }
  void set_gains(const AltitudeGains& g);
  const AltitudeGains& gains() const { return g_; }
  double update(double h_c, double h, double h_dot, double dt);
  void initialise(double theta_c, double h_c, double h, double h_dot);
  void reset() { pid_.reset(); }

 private:
  AltitudeGains g_;
  Pid pid_;
};

struct AirspeedGains {
  double kp = 0.1;                              ///< throttle / (m/s)
  double ki = 0.02;                             ///< throttle / m
  double kd = 0.0;                              ///< throttle / (m/s^2)
  double trim_t = LongitudinalLimits{}.trim_t;  ///< (parameters of LongitudinalLimits)
  double max_t = LongitudinalLimits{}.max_t;
  double min_t = LongitudinalLimits{}.min_t;
  double tau_d = 0.05;  ///< dirty-derivative time constant for Va_dot, s

  /// The gains only; trim and limits are LongitudinalLimits' parameters.
  template <class V>
  static void describe(V& v) {
    using tern::ParamSpec;
    v(&AirspeedGains::kp, "airspeed_kp", ParamSpec("1/(m/s)", 0.0, 5.0, "airspeed -> throttle proportional gain (a_t_kp)"));
    v(&AirspeedGains::ki, "airspeed_ki", ParamSpec("1/m", 0.0, 5.0, "airspeed -> throttle integral gain (a_t_ki)"));
    v(&AirspeedGains::kd, "airspeed_kd", ParamSpec("1/(m/s^2)", 0.0, 5.0, "airspeed -> throttle gain on dVa/dt (a_t_kd)"));
    v(&AirspeedGains::tau_d, "derivative_tau", ParamSpec("s", 0.001, 10.0, "dirty-derivative time constant for dVa/dt"));
  }
};

/// Airspeed hold with throttle.
class AirspeedThrottleLoop {
 public:
  AirspeedThrottleLoop() { set_gains({}); }
  void set_gains(const AirspeedGains& g);
  const AirspeedGains& gains() const { return g_; }
  double update(double Va_c, double Va, double dt);
  void initialise(double delta_t, double Va_c, double Va);
  /// Throttle before saturation of the last update.
  double unsaturated() const { return pid_.last_unsaturated(); }
  void reset();

 private:
  AirspeedGains g_;
  Pid pid_;
  DirtyDerivative Va_dot_;
};

}  // namespace tern::control
