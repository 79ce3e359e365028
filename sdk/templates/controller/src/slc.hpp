// slc.hpp: a successive-loop-closure autopilot (plain C++, no tern host types) after Beard & McLain,
// *Small Unmanned Aircraft*, ch. 6. Outer loops make attitude commands, inner loops surfaces:
//   course -> roll      phi_c   = phi_ff + kp_chi e_chi + ki_chi int(e_chi)   e_chi = wrap(chi_c - chi)
//                       |phi_c| <= roll_max                                    (sec. 6.1.1.2)
//   roll -> aileron     delta_a = trim_a + kp_phi (phi_c - phi) - kd_phi p     (sec. 6.1.1.1)
//   altitude -> pitch   theta_c = kp_h (h_c - h) + ki_h int(h_c - h), |theta_c| <= theta_max
//                                                                              (sec. 6.1.2.2)
//   pitch -> elevator   delta_e = trim_e - kp_theta (theta_c - theta) + kd_theta q  (sec. 6.1.2.1)
//   airspeed -> throttle delta_t = trim_t + kp_V (Va_c - Va) + ki_V int(Va_c - Va), 0..1
//                                                                              (sec. 6.1.2.3)
// Anti-windup: an integrator stops growing while its loop's output is saturated in the direction
// the error pushes it. Signs follow tern's actuators (uavbook 4.2): positive delta_a rolls right,
// positive delta_e pitches the nose down. The default gains are those tern designs for the
// Anaconda at 17 m/s (share/tern/configs/gains/anaconda.yaml, control_slc's design: roll loop
// natural frequency 16 rad/s, course loop 2.9 rad/s, pitch loop DC gain 0.7; roll_kd 0.05
// instead of 0 takes the roll damping ratio from 0.8 to 1.0), trims from `tern aero trim --Va 17`
// (delta_e 0.168 rad, delta_t 0.568).
#pragma once

#include "tern/param.hpp"  // ParamSpec only: the parameters' names, units and ranges sit with the defaults

namespace tern_@NAME@ {

/// The gains, trims and limits. Each is a plugin parameter, declared once: describe() gives its
/// name (what the mission config and `tern fly --set` write), unit, range and description; the
/// member initialiser is its default. The plugin declares them all with declare_struct(gains_)
/// and the struct always holds the parameters' values (also after a change in flight).
struct Gains {
  double course_kp = 5.05;      ///< roll command per course error, rad/rad
  double course_ki = 0.202;     ///< roll command per integrated course error, rad/(rad s)
  double roll_max = 0.785;      ///< roll command limit, rad (45 deg)
  double roll_kp = 1.86;        ///< aileron per roll error, rad/rad
  double roll_kd = 0.05;        ///< aileron per roll rate p, rad/(rad/s)
  double trim_a = 0.0;          ///< aileron at trim, rad
  double max_a = 0.698;         ///< aileron limit, rad (the Anaconda's servo limit, 40 deg)
  double altitude_kp = 0.156;   ///< pitch command per altitude error, rad/m
  double altitude_ki = 0.0727;  ///< pitch command per integrated altitude error, rad/(m s)
  double theta_max = 0.35;      ///< pitch command limit, rad (20 deg)
  double pitch_kp = 6.46;       ///< elevator per pitch error, rad/rad
  double pitch_kd = 0.368;      ///< elevator per pitch rate q, rad/(rad/s)
  double trim_e = 0.168;        ///< elevator at trim, rad
  double max_e = 0.61;          ///< elevator limit, rad
  double airspeed_kp = 0.161;   ///< throttle per airspeed error, 1/(m/s)
  double airspeed_ki = 0.147;   ///< throttle per integrated airspeed error, 1/m
  double trim_t = 0.568;        ///< throttle at trim, 0..1

  template <class V> static void describe(V& v) {
    using tern::ParamSpec;
    v(&Gains::course_kp, "course_kp", ParamSpec("rad/rad", 0.0, 20.0, "roll command per course error"));
    v(&Gains::course_ki, "course_ki", ParamSpec("rad/(rad s)", 0.0, 5.0, "roll command per integrated course error"));
    v(&Gains::roll_max, "roll_max", ParamSpec("rad", 0.05, 1.2, "roll command limit"));
    v(&Gains::roll_kp, "roll_kp", ParamSpec("rad/rad", 0.0, 10.0, "aileron per roll error"));
    v(&Gains::roll_kd, "roll_kd", ParamSpec("rad/(rad/s)", 0.0, 2.0, "aileron per roll rate p"));
    v(&Gains::trim_a, "trim_a", ParamSpec("rad", -0.3, 0.3, "aileron at trim"));
    v(&Gains::max_a, "max_a", ParamSpec("rad", 0.01, 0.7, "aileron limit (the host's max_deflection is 0.7)"));
    v(&Gains::altitude_kp, "altitude_kp", ParamSpec("rad/m", 0.0, 1.0, "pitch command per altitude error"));
    v(&Gains::altitude_ki, "altitude_ki", ParamSpec("rad/(m s)", 0.0, 1.0, "pitch command per integrated altitude error"));
    v(&Gains::theta_max, "theta_max", ParamSpec("rad", 0.05, 0.8, "pitch command limit (both signs)"));
    v(&Gains::pitch_kp, "pitch_kp", ParamSpec("rad/rad", 0.0, 20.0, "elevator per pitch error"));
    v(&Gains::pitch_kd, "pitch_kd", ParamSpec("rad/(rad/s)", 0.0, 2.0, "elevator per pitch rate q"));
    v(&Gains::trim_e, "trim_e", ParamSpec("rad", -0.5, 0.5, "elevator at trim (positive: nose down)"));
    v(&Gains::max_e, "max_e", ParamSpec("rad", 0.01, 0.7, "elevator limit"));
    v(&Gains::airspeed_kp, "airspeed_kp", ParamSpec("1/(m/s)", 0.0, 2.0, "throttle per airspeed error"));
    v(&Gains::airspeed_ki, "airspeed_ki", ParamSpec("1/m", 0.0, 2.0, "throttle per integrated airspeed error"));
    v(&Gains::trim_t, "trim_t", ParamSpec("", 0.0, 1.0, "throttle at trim"));
  }
};

/// What the path follower asks for: course chi_c (rad), altitude h_c (m above the origin),
/// airspeed Va_c (m/s), roll feed-forward phi_ff (rad, orbits).
struct Command {
  double chi_c = 0.0, h_c = 0.0, Va_c = 17.0, phi_ff = 0.0;
};

/// The estimated state the loops use: phi, theta, chi (rad), p, q (rad/s), h (m), Va (m/s).
struct State {
  double phi = 0.0, theta = 0.0, chi = 0.0, p = 0.0, q = 0.0, h = 0.0, Va = 0.0;
};

/// Surfaces delta_a, delta_e (rad, within +-max_a, +-max_e), throttle delta_t (0..1), and the
/// inner commands phi_c, theta_c (rad) and the throttle before saturation delta_t_c.
struct Output {
  double delta_a = 0.0, delta_e = 0.0, delta_t = 0.0;
  double phi_c = 0.0, theta_c = 0.0, delta_t_c = 0.0;
};

/// PI loop u = sat(ff + kp e + ki I, lo, hi) with I the integral of e (conditional integration).
struct PiLoop {
  double I = 0.0;      ///< integral of the error
  double u_raw = 0.0;  ///< last output before saturation
  double update(double e, double dt, double kp, double ki, double ff, double lo, double hi);
};

class Slc {
 public:
  Slc() = default;
  explicit Slc(const Gains& g) : g_(g) {}
  void set_gains(const Gains& g) { g_ = g; }
  const Gains& gains() const { return g_; }

  /// One step of length dt (s; 0 on a first step: nothing integrates). A non-finite command or
  /// state, or a negative dt, gives the trim surfaces and leaves the integrators unchanged.
  Output update(const Command& c, const State& x, double dt);
  /// Integrators clean (start of a flight, controller handover): the whole loop state replaced,
  /// as constructed with the current gains.
  void reset() { *this = Slc(g_); }
  /// Bumpless throttle: after reset(), sets the airspeed integrator so that the next throttle
  /// equals delta_t at airspeed error Va_error (m/s). Course and altitude integrators start at 0.
  void take_over(double delta_t, double Va_error);
  /// The trim surfaces (what update() gives for bad input).
  Output trim() const;

 private:
  Gains g_;
  PiLoop course_, altitude_, airspeed_;
};

}  // namespace tern_@NAME@
