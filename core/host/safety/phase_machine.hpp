// core/host/safety/phase_machine.hpp: the host's flight-phase machine (ROSplane 2.0's takeoff ->
// climb -> altitude hold, here takeoff -> climb -> cruise).
//
// A built-in plugin instance named `phase_machine`, present when the config has `phases:`.
// It steps whenever `state` updates and publishes `flight_phase`. Altitude h = -p_d (above the
// origin, m); commanded altitude h_c from `controller_command` (h_c = h when none).
//   preflight -> takeoff when the arming checks (preflight.hpp: FCU armed and error-free,
//              estimator aligned and consistent with every sensor alive, GNSS fix, aircraft at
//              rest, RC heard when required) have all passed for preflight_time; no controller
//              runs before (motor off). One line per failing check every report_interval; after
//              preflight_timeout (counted once the FCU is armed) the flight ends (failure():
//              "preflight_failed: ..."). With `preflight: false` (tern fly --skip-preflight) the
//              flight starts in takeoff.
//   takeoff -> climb   when h >= alt_toz
//   climb   -> cruise  when |h_c - h| < alt_hz
//   cruise  -> climb   when h_c - h > alt_hz for min_phase_time (lost altitude)
//   climb/cruise -> takeoff when h < alt_toz for min_phase_time (lost altitude near the ground)
//   after preflight: disarmed when the optional `fcu_status` says the FCU is not armed: the host then
//              steps no controller (no takeoff, no integrators running) until
//   disarmed -> takeoff  the FCU is armed and error-free (the controller is reset on handover)
// Landing (a land item's glide path on the optional `current_path`, landing_checks.hpp):
//   climb/cruise -> approach  when a new approach begins (current_path.landing, a new attempt)
//   approach -> flare     when the height above the runway (landing_checks.hpp runway_height: a
//                         range finder's, else the estimate's above the touchdown point) is below
//                         its flare height, or past the touchdown point below the decision height
//                         (the glide path, on the estimate's altitude, ended above the runway)
//   approach -> climb     go-around: below the decision height while not stabilised (the
//                         criterion named), or the glide path was left (the mission changed, a
//                         failsafe); the path manager comes round for another approach
//   approach/flare -> climb  the operator's go-around (request_go_around: tern go-around, the DDS
//                         service go_around), also from the flare (a balked landing)
//   flare -> rollout      on the wheels: the sink stopped within land_ground_band of the touchdown point
//   rollout -> stopped    ground speed < land_stopped_speed for land_stopped_time: the flight
//                         ends complete (landed(): end_reason "landed", summary.json)
// Takeoff abort (takeoff_checks.hpp; a takeoff begun at rest, below takeoff_safe_height):
//   takeoff/climb -> rollout  the run or the attitude criterion (named); once stopped the flight
//                         ends with failure() "takeoff_aborted: <criterion>"
// Preflight also refuses a takeoff in more wind than preflight_max_wind (preflight.hpp).
// Without `fcu_status` the flight never waits (sim_aero's reports disarmed only during its boot
// calibration, a failing preflight check). The published phase
// stays `takeoff` while disarmed (FlightPhase has no disarmed value); disarmed() tells the host.
// Every transition is recorded with its time and reason. The phase router also reads
// max_deflection: a controller commanding more (or a throttle outside [0, 1]) is replaced by the
// fallback.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "safety/landing_checks.hpp"
#include "safety/preflight.hpp"
#include "safety/safety_monitor.hpp"
#include "safety/state_loss_recovery.hpp"
#include "safety/takeoff_checks.hpp"
#include "tern/plugin.hpp"

namespace tern::core {

struct PhaseTransition {
  Nanos t = 0;
  msg::Phase from = msg::Phase::takeoff;
  msg::Phase to = msg::Phase::takeoff;
  std::string reason;
};

class PhaseMachine final : public Plugin {
 public:
  void configure() override;
  void start() override;
  void step(Nanos now) override;
  void reset() override;

  msg::Phase phase() const { return f_.phase; }
  /// The flight waits for the FCU to be armed and error-free: no controller runs.
  bool disarmed() const { return f_.disarmed; }
  /// Largest surface deflection a controller may command before the router replaces it, rad.
  double max_deflection() const { return max_deflection_(); }
  const std::vector<PhaseTransition>& transitions() const { return f_.transitions; }
  /// The phase a flight starts in: preflight, or takeoff when it is skipped.
  msg::Phase first_phase() const { return preflight_() ? msg::Phase::preflight : msg::Phase::takeoff; }
  /// The phase router's safety monitor's limits (safety_* parameters; safety_monitor.hpp).
  SafetyLimits safety_limits() const;
  /// The safety monitor may hand control back to the phase's controller on the next phase change.
  bool safety_hand_back() const { return safety_hand_back_(); }
  /// Whether the router's state-loss recovery flies while the estimate is invalid, and its gains.
  bool state_loss_recovery() const { return recovery_(); }
  RecoveryGains recovery_gains() const;
  /// The estimate the machine steps on (nullptr before the first one).
  const msg::State* estimate() const { return state_.has_value() ? &state_.get() : nullptr; }
  /// The commanded altitude h_c, m (none before the first controller_command).
  std::optional<double> commanded_altitude() const;
  /// The commanded airspeed Va_c, m/s (none before the first controller_command).
  std::optional<double> commanded_airspeed() const;
  /// Why the flight must end ("preflight_failed: ..."), empty while it may go on.
  const std::string& failure() const { return f_.failure; }
  /// The aircraft landed and stopped: the flight is complete (landed_detail() says how).
  bool landed() const { return f_.phase == msg::Phase::stopped && f_.abort_reason.empty(); }
  const std::string& landed_detail() const { return f_.landed_detail; }
  /// The operator's go-around (from `source`, e.g. "DDS"), taken at the next step on the approach
  /// or in the flare and counted like the automatic ones (the path manager's land_attempts bound
  /// them). Host thread, between ticks. Returns "" when it will be taken, else why not (the phase).
  std::string request_go_around(const std::string& source);
  std::vector<std::pair<std::string, double>> summary() const override;

 private:
  void enter(Nanos now, msg::Phase to, std::string reason);
  /// Enters or leaves the disarmed wait from `fcu_status`; true while waiting.
  bool wait_for_arming(Nanos now);
  /// Runs the arming checks in preflight; enters takeoff once they held for preflight_time.
  void run_preflight(Nanos now);
  PreflightInputs preflight_inputs(Nanos now) const;
  PreflightLimits limits() const;
  void declare_preflight();
  void declare_safety();
  void declare_recovery();
  void declare_landing();
  LandingLimits landing_limits() const;
  /// The landing transitions (approach, flare, rollout, stopped, go-around); true when it decided.
  bool step_landing(Nanos now, const msg::State& s);
  void step_rollout(Nanos now, const msg::State& s);
  void declare_takeoff();
  TakeoffLimits takeoff_limits() const;
  /// Aborts the takeoff (-> rollout) on takeoff_checks.hpp's criteria; true when it did.
  bool step_takeoff_checks(Nanos now, const msg::State& s);
  void go_around(Nanos now, const std::string& why);
  Input<msg::State> state_;
  Input<msg::ControllerCommand> command_;
  Input<msg::FcuStatus> fcu_;
  Input<msg::Innovations> innovations_;
  Input<msg::Gnss> gnss_;
  Input<msg::Rc> rc_;
  Input<msg::CurrentPath> path_;
  Input<msg::Range> range_;
  Output<msg::FlightPhase> phase_out_;
  Param<double> alt_toz_, alt_hz_, min_phase_time_, max_deflection_;
  Param<bool> preflight_, require_rc_;
  Param<double> preflight_time_, preflight_timeout_, report_interval_;
  Param<double> max_tilt_sigma_, max_yaw_sigma_, max_gyro_bias_sigma_, max_position_sigma_, max_h_acc_, max_v_acc_, max_ground_speed_,
      max_rc_age_, max_wind_;
  Param<std::int64_t> min_sats_;
  Param<bool> safety_, safety_hand_back_, recovery_;
  Param<double> recovery_trim_tau_, recovery_throttle_up_, recovery_roll_kp_, recovery_roll_kd_;
  Param<std::int64_t> safety_silent_periods_;
  Param<double> land_max_cross_track_, land_max_glide_error_, land_max_airspeed_deficit_, land_ground_band_, land_stopped_speed_,
      land_stopped_time_;
  Param<double> takeoff_run_length_, takeoff_min_airspeed_, takeoff_max_roll_, takeoff_max_pitch_, takeoff_min_pitch_, takeoff_safe_height_;
  Param<double> safety_hold_, safety_roll_max_, safety_pitch_max_, safety_pitch_min_, safety_floor_, safety_airspeed_min_,
      safety_airspeed_max_, safety_sink_max_, safety_saturation_, safety_error_growth_;
  /// Everything one flight changes: reset() replaces it wholesale.
  struct Flight {
    msg::Phase phase = msg::Phase::takeoff;
    bool disarmed = false;
    Nanos since = 0;
    Nanos condition_since = -1;  ///< when a transition-back condition became true (-1: not true)
    std::vector<PhaseTransition> transitions;
    Nanos checks_passed_since = -1;  ///< preflight: when every check last began to pass (-1: failing)
    Nanos last_report = -1;          ///< preflight: when the failing checks were last logged
    Nanos preflight_since = -1;      ///< preflight: first check after the last disarmed wait (timeout base)
    std::string failure;
    int approach_seen = 0;  ///< current_path.attempt of the last approach entered
    int go_arounds = 0;
    std::string go_around_request;  ///< the operator's go-around, by its source ("": none pending)
    std::string landed_detail;
    std::optional<Eigen::Vector3d> takeoff_start;  ///< estimated position where the takeoff began
    bool takeoff_checked = false;                  ///< the takeoff's abort criteria are watched
    std::string abort_reason;                      ///< why the takeoff was aborted ("" : it was not)
  } f_;
  /// The host's flights have skipped preflight since the last one that did not (the warning is
  /// given once, then kept at info: a learning environment's thousands of resets repeat it).
  bool preflight_skip_warned_ = false;
};

}  // namespace tern::core
