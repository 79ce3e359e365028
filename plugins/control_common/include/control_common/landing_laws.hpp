// control_common/landing_laws.hpp: the flare and rollout laws of the autopilot's landing phases
// (autopilot.hpp: Mode::flare, Mode::rollout). Plain C++, no host types.
//
// Flare (the sink-rate flare of automatic landing systems: Stevens, Lewis & Johnson, *Aircraft
// Control and Simulation*, 3rd ed., sec. 4.7 "flare control": the commanded sink rate proportional
// to the height, h_dot_c = -h / tau, an exponential path to the ground; here with a touchdown sink
// rate so that the path meets the ground in finite time, as PX4's flare does with
// FW_LND_FL_SINK):
//   h_dot_c(h) = -(sink_td + (sink_0 - sink_td) h / h_0)   for 0 <= h <= h_0, -sink_td below 0,
// with h the height above the touchdown point, h_0 and sink_0 the height and sink rate at the
// flare's start: the command is continuous at the start (tau = h_0 / (sink_0 - sink_td)).
// The pitch command tracks it with a PI loop from the pitch at the flare's start, within
// [pitch_min, pitch_max]; the throttle winds down from its value at the flare's start to idle at
// the touchdown height (delta_t = delta_t_0 h / h_0: the energy to arrest the sink is not cut at
// the flare's first metre, as with a throttle chopped at once), but never below what holds the
// airspeed above flare_airspeed_ratio times the approach's commanded airspeed (a PI loop on the
// deficit: a flare begun too high, on an altitude estimate metres off, would otherwise float at
// idle until it stalls and drops; a pilot adds power), and the bank is limited to roll_max
// (wings near level close to the ground: the Anaconda's tips strike at ~7 deg on its mains).
// Rollout: motor off, wings level, the elevator at the pitch loop's command for pitch 0, the
// rudder (and with it the nose wheel) steers the course to the runway's, and the brakes come on
// brake_delay s after the touchdown (the nose wheel on the ground first).
#pragma once

#include "tern/param.hpp"

namespace tern::control {

struct LandingSettings {
  double flare_sink_td = 0.3;         ///< sink rate at touchdown, m/s (PX4 FW_LND_FL_SINK: 0.25)
  double flare_kp = 0.3;              ///< pitch per sink-rate error, rad/(m/s)
  double flare_ki = 0.2;              ///< rad/m
  double flare_pitch_min = -0.05;     ///< rad
  double flare_pitch_max = 0.2;       ///< rad (11.5 deg: below a tricycle's tail-strike attitude; PX4 FW_LND_FL_PMAX 15 deg)
  double flare_roll_max = 0.0524;     ///< bank limit in the flare, rad (3 deg)
  double flare_airspeed_ratio = 0.8;  ///< the flare's airspeed floor, times the approach's Va_c
  double flare_throttle_kp = 0.1;     ///< throttle per m/s below the floor
  double flare_throttle_ki = 0.1;     ///< throttle per m below the floor (integrated deficit)
  double rollout_steer_kp = 1.0;      ///< rudder per course error on the rollout, rad/rad
  double rollout_brake = 1.0;         ///< brake command on the rollout, 0..1
  double rollout_brake_delay = 1.0;   ///< s after the touchdown

  template <class V>
  static void describe(V& v) {
    using tern::ParamSpec;
    using S = LandingSettings;
    v(&S::flare_sink_td, "flare_sink_td", ParamSpec("m/s", 0.0, 3.0, "flare: sink rate commanded at touchdown"));
    v(&S::flare_kp, "flare_kp", ParamSpec("rad/(m/s)", 0.0, 2.0, "flare: pitch per sink-rate error"));
    v(&S::flare_ki, "flare_ki", ParamSpec("rad/m", 0.0, 2.0, "flare: pitch per integrated sink-rate error"));
    v(&S::flare_pitch_min, "flare_pitch_min", ParamSpec("rad", -0.5, 0.5, "flare: lowest pitch command"));
    v(&S::flare_pitch_max, "flare_pitch_max", ParamSpec("rad", -0.5, 0.6, "flare: highest pitch command"));
    v(&S::flare_roll_max, "flare_roll_max", ParamSpec("rad", 0.0, 0.8, "flare: bank limit"));
    v(&S::flare_airspeed_ratio, "flare_airspeed_ratio",
      ParamSpec("", 0.0, 1.0, "flare: airspeed floor held by the throttle, times the approach's commanded airspeed (0: none)"));
    v(&S::flare_throttle_kp, "flare_throttle_kp", ParamSpec("1/(m/s)", 0.0, 2.0, "flare: throttle per m/s below the airspeed floor"));
    v(&S::flare_throttle_ki, "flare_throttle_ki", ParamSpec("1/m", 0.0, 2.0, "flare: throttle per integrated m/s below the floor"));
    v(&S::rollout_steer_kp, "rollout_steer_kp", ParamSpec("rad/rad", 0.0, 10.0, "rollout: rudder (nose wheel) per course error"));
    v(&S::rollout_brake, "rollout_brake", ParamSpec("", 0.0, 1.0, "rollout: brake command"));
    v(&S::rollout_brake_delay, "rollout_brake_delay", ParamSpec("s", 0.0, 30.0, "rollout: brakes on this long after the touchdown"));
  }
};

/// The flare's pitch command (see the file comment).
class FlareLaw {
 public:
  /// The flare begins at height h0 (m above the touchdown point) sinking at sink0 (m/s, > 0
  /// down) with pitch theta0 (rad) and throttle delta_t0 (0..1).
  void start(double h0, double sink0, double theta0, double delta_t0);
  /// Throttle at height h flying at airspeed Va (m/s) after dt s: delta_t0 h / h0 (0 at and
  /// below the touchdown point), raised by the floor loop while Va < Va_floor (m/s).
  double throttle(double h, double Va, double Va_floor, double dt, const LandingSettings& s);
  /// Commanded climb rate at height h, m/s (negative: sinking).
  double h_dot_command(double h, const LandingSettings& s) const;
  /// Pitch command at height h climbing at h_dot, after dt s.
  double update(double h, double h_dot, double dt, const LandingSettings& s);

 private:
  double h0_ = 1.0, sink0_ = 0.0, theta0_ = 0.0, delta_t0_ = 0.0, integral_ = 0.0, deficit_integral_ = 0.0;
};

}  // namespace tern::control
