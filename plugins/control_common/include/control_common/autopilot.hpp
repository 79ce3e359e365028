// control_common/autopilot.hpp: the complete fixed-wing autopilot around a pluggable
// longitudinal law: lateral loops (course -> roll -> aileron, yaw damper) and pitch ->
// elevator from loops.hpp, flight-phase behaviour (takeoff, climb, cruise), manual modes
// (pass-through, angle mode), command overrides, and bumpless transfer.
//
// control_slc plugs in SlcLongitudinal (altitude -> pitch PI, airspeed -> throttle PI);
// control_tecs plugs in its total-energy law. Plain C++: no tern host types.
//
// Phases (ROSplane 2.0's takeoff -> climb -> cruise):
//   takeoff  wings level (phi_c = 0), throttle = takeoff_throttle, pitch command 0 until the
//            airspeed reaches rotation_Va, then takeoff_pitch (latched for the phase). Before
//            rotation the pitch and roll integrators are held at zero (the gear holds the attitude).
//   climb    course hold (or wings level if climb_course_hold is false); the longitudinal law
//            climbs to h_c (its pitch limits bound the climb).
//   cruise   (and landing, loiter) course, altitude and airspeed hold.
//   approach a land item's glide path: as cruise (the follower's h_c descends the glide path).
//   flare    landing_laws.hpp: the sink-rate flare's pitch, throttle to idle above an airspeed floor, bank within
//            flare_roll_max; the course loop steers to the runway's course.
//   rollout  landing_laws.hpp: motor off, wings level, rudder/nose wheel steering, brakes.
// Manual modes: pass-through (surfaces from the sticks: delta_a = roll max_a, delta_e =
// -pitch max_e, delta_r = -yaw max_r, delta_t = throttle) and angle mode (phi_c = roll *
// angle_roll_max, theta_c = pitch * angle_pitch_max, throttle from the stick, rudder = yaw
// damper - yaw max_r).
// Bumpless transfer: after take_over(last), on every change of mode or override flag, and after
// reset(), the integrators are set from the last command (back-solving the cascade) and any
// remainder becomes an output offset that decays with time constant handover_tau. With a roll
// command slew limit (roll_rate_max > 0) the roll channel instead restarts its shaped roll
// command at the roll the last aileron implies and slews it to the new command, the course
// integrator clean (a course error at the transfer would otherwise wind it to its clamp, and
// the slow integrator would take tens of seconds to unwind). The first command after a
// transfer equals `last` (within the actuator limits).
#pragma once

#include <cstdint>

#include "control_common/landing_laws.hpp"
#include "control_common/loops.hpp"

namespace tern::control {

enum class Mode : std::uint8_t { takeoff, climb, cruise, manual_passthrough, manual_angle, approach, flare, rollout };

/// What the path follower commands (ROSplane's ControllerCommands).
struct Command {
  double Va_c = 0.0;     ///< m/s
  double h_c = 0.0;      ///< m
  double chi_c = 0.0;    ///< rad
  double phi_ff = 0.0;   ///< rad
  double phi_c = 0.0;    ///< rad, used when override_phi
  double theta_c = 0.0;  ///< rad, used when override_theta
  bool override_phi = false;
  bool override_theta = false;
  bool landing = false;  ///< on a land item's glide path: h_td is the touchdown altitude
  double h_td = 0.0;     ///< m (flare and rollout measure the height above the runway from it)
  bool finite() const;
};

/// Pilot sticks, normalised: roll, pitch, yaw in -1..1 (right, nose up, nose right positive),
/// throttle 0..1. Out-of-range values are clamped.
struct Sticks {
  double roll = 0.0, pitch = 0.0, yaw = 0.0, throttle = 0.0;
};

/// Longitudinal control law: pitch command and throttle from altitude and airspeed.
class LongitudinalLaw {
 public:
  struct Output {
    double theta_c = 0.0;    ///< rad
    double delta_t = 0.0;    ///< 0..1, saturated
    double delta_t_c = 0.0;  ///< before saturation
  };
  virtual ~LongitudinalLaw() = default;
  /// One step; `climb` is true in the climb phase.
  virtual Output update(const VehicleState& x, const Command& c, bool climb, double dt) = 0;
  /// Bumpless transfer: set the integrators so that update() would give theta_c and delta_t.
  virtual void initialise(const VehicleState& x, const Command& c, double theta_c, double delta_t) = 0;
  virtual void reset() = 0;
  /// Pitch-command limits of the law, rad.
  virtual double theta_min() const = 0;
  virtual double theta_max() const = 0;
};

/// Altitude -> pitch (one PI loop) and airspeed -> throttle (PI): uavbook sections 6.2.2, 6.2.3.
class SlcLongitudinal final : public LongitudinalLaw {
 public:
  void set_gains(const AltitudeGains& a, const AirspeedGains& v) {
    altitude_.set_gains(a);
    airspeed_.set_gains(v);
  }
  Output update(const VehicleState& x, const Command& c, bool climb, double dt) override;
  void initialise(const VehicleState& x, const Command& c, double theta_c, double delta_t) override;
  void reset() override {
    altitude_.reset();
    airspeed_.reset();
  }
  double theta_min() const override { return altitude_.gains().theta_min; }
  double theta_max() const override { return altitude_.gains().theta_max; }

 private:
  AltitudeLoop altitude_;
  AirspeedThrottleLoop airspeed_;
};

struct AutopilotSettings {
  double takeoff_throttle = 1.0;   ///< 0..1
  double takeoff_pitch = 0.1745;   ///< rad
  double rotation_Va = 12.0;       ///< m/s
  bool climb_course_hold = true;   ///< false: wings level in climb
  double handover_tau = 1.0;       ///< decay of the bumpless offset, s
  double angle_roll_max = 0.7854;  ///< angle mode: roll at full stick, rad
  double angle_pitch_max = 0.35;   ///< angle mode: pitch at full stick, rad

  template <class V>
  static void describe(V& v) {
    using tern::ParamSpec;
    using S = AutopilotSettings;
    v(&S::takeoff_throttle, "takeoff_throttle", ParamSpec("", 0.0, 1.0, "throttle during takeoff (max_takeoff_throttle)"));
    v(&S::takeoff_pitch, "takeoff_pitch", ParamSpec("rad", 0.0, 0.6, "pitch command after rotation in takeoff"));
    v(&S::rotation_Va, "rotation_Va", ParamSpec("m/s", 0.0, 100.0, "airspeed at which takeoff rotates to takeoff_pitch"));
    v(&S::handover_tau, "handover_tau", ParamSpec("s", 0.0, 60.0, "decay time of the bumpless-transfer offset"));
    v(&S::climb_course_hold, "climb_course_hold", ParamSpec("", 0, 0, "climb phase: hold the commanded course (false: wings level)"));
    v(&S::angle_roll_max, "angle_roll_max", ParamSpec("rad", 0.0, 1.4, "angle mode: roll command at full stick"));
    v(&S::angle_pitch_max, "angle_pitch_max", ParamSpec("rad", 0.0, 1.0, "angle mode: pitch command at full stick"));
  }
};

struct AutopilotOutput {
  Surfaces surfaces;
  double phi_c = 0.0;      ///< roll command used, rad
  double theta_c = 0.0;    ///< pitch command used, rad
  double delta_t_c = 0.0;  ///< throttle before saturation
  double brake = 0.0;      ///< wheel brakes, 0..1 (rollout)
  bool held = false;       ///< input was not finite: the previous command was held
};

class Autopilot {
 public:
  /// `law` must outlive the autopilot.
  explicit Autopilot(LongitudinalLaw& law) : law_(law) {}
  void set_lateral_gains(const LateralGains& g) { lateral_.set_gains(g); }
  void set_pitch_gains(const PitchGains& g) { pitch_.set_gains(g); }
  void set_settings(const AutopilotSettings& s) { s_ = s; }
  void set_landing_settings(const LandingSettings& s) { land_ = s; }
  const LateralGains& lateral_gains() const { return lateral_.gains(); }
  const PitchGains& pitch_gains() const { return pitch_.gains(); }
  const AutopilotSettings& settings() const { return s_; }

  /// One control step, dt in s since the previous step. A non-finite state or command (NaN,
  /// Inf) holds the previous output (held = true) and leaves every integrator untouched.
  AutopilotOutput update(Mode mode, const VehicleState& x, const Command& c, const Sticks& sticks, double dt);
  /// The next update starts from `last` (bumpless transfer).
  void take_over(const Surfaces& last);
  /// Integrators and filters clean; the next update starts from trim.
  void reset();
  const Surfaces& last() const { return f_.last.surfaces; }

 private:
  Surfaces limit(const Surfaces& u) const;
  Surfaces trim() const;
  static double runway_height(const VehicleState& x, const Command& c);
  /// Flare and rollout: pitch command, throttle, and on the rollout the rudder and brakes.
  struct LandingLongitudinal {
    double theta_c = 0.0, delta_t = 0.0, delta_r = 0.0, brake = 0.0;
  };
  LandingLongitudinal landing_step(Mode mode, const VehicleState& x, const Command& c, double dt);
  // update()'s steps (autopilot.cpp)
  void enter_mode(Mode mode, const VehicleState& x, const Command& c, bool override_phi, bool override_theta);
  AutopilotOutput passthrough(const VehicleState& x, const Sticks& st);
  AutopilotOutput loops(Mode mode, const VehicleState& x, const Command& c, const Sticks& st, double dt);
  struct LateralOut {
    double phi_c, delta_a, delta_r;  ///< rad
  };
  LateralOut lateral_step(Mode mode, const VehicleState& x, const Command& c, const Sticks& st, bool init, double h);
  struct LongitudinalOut {
    double theta_c, delta_t, delta_t_c, delta_e;  ///< rad, throttle 0..1, rad
  };
  LongitudinalOut longitudinal_step(Mode mode, const VehicleState& x, const Command& c, const Sticks& st, bool init, double h,
                                    double& delta_r, double& brake);

  LongitudinalLaw& law_;
  LateralLoops lateral_;
  PitchLoop pitch_;
  AutopilotSettings s_;
  LandingSettings land_;
  /// Everything a flight changes besides the loops' integrators: reset() replaces it wholesale.
  struct Flight {
    AutopilotOutput last;
    Surfaces offset;         ///< bumpless-transfer offset, decaying with handover_tau
    Surfaces handover_from;  ///< the surfaces to start from at the next mode change
    bool pending_handover = false;
    bool have_last = false;
    bool rotated = false;  ///< takeoff: rotated to takeoff_pitch
    FlareLaw flare;
    double rollout_time = 0.0;  ///< s on the rollout
    double rollout_chi = 0.0;   ///< course when the rollout began, rad
    Mode mode = Mode::cruise;
    bool override_phi = false, override_theta = false;
  } f_;
};

}  // namespace tern::control
