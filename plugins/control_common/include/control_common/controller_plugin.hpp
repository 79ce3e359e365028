// control_common/controller_plugin.hpp: the thin tern plugin adapter shared by control_slc and
// control_tecs. It binds the Autopilot (autopilot.hpp) to ports and parameters; a derived
// plugin supplies the longitudinal law and its parameters.
//
// Ports
//   in  state               msg::State               required; the loops use phi theta chi p q r,
//                                                    h = -p_d, h_dot = -v_d, Va
//   in  controller_command  msg::ControllerCommand   required (until the first command arrives the
//                                                    controller holds the altitude, course and
//                                                    airspeed of its first state)
//   in  flight_phase        msg::FlightPhase         optional (absent: cruise; landing, loiter: as cruise)
//   in  rc                  msg::Rc                  optional (manual modes)
//   in  fcu_status          msg::FcuStatus           optional (rc_override: manual modes)
//   out actuators           msg::Actuators           rad, throttle 0..1, every step once a state arrived
//   out controller_internals msg::ControllerInternals phi_c, theta_c, delta_t_c, alt_zone = phase
// A state or command with NaN/Inf, or a state with valid == false, holds the previous actuator
// command (before any: trim surfaces, throttle 0); logged once per episode.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "control_common/autopilot.hpp"
#include "tern/plugin.hpp"

namespace tern::control {

class ControllerPlugin : public Plugin {
 public:
  void configure() final;
  void step(Nanos now) final;
  void reset() override;
  void take_over(const msg::Actuators& last_command) override;
  std::vector<std::pair<std::string, double>> summary() const override;
  /// Steps that held the previous command or flew the pilot's sticks, when there were any.
  std::string health() const override;

 protected:
  /// Declares the law's parameters (with declare_gains, so that changes take effect).
  virtual void declare_law_params() = 0;
  /// Copies the law's parameter values into the law; may throw ParamError on inconsistent values.
  virtual void apply_law_params() = 0;
  virtual LongitudinalLaw& law() = 0;

  /// Declares the fields of a described gain struct (S::describe) as parameters; a change is
  /// applied before the next step.
  template <class S>
  void declare_gains(S& gains) {
    declare_struct(gains, [this] { dirty_ = true; });
  }

  /// Shared longitudinal limits and trim (both laws use them).
  LongitudinalLimits limits_;
  /// The lower throttle limit, never above max_t (a runtime change cannot invert the limits).
  double min_t() const { return limits_.min_t < limits_.max_t ? limits_.min_t : limits_.max_t; }

 private:
  void apply_params();
  Mode select_mode(const msg::State& s);
  Autopilot& autopilot();

  Input<msg::State> state_;
  Input<msg::ControllerCommand> command_;
  Input<msg::FlightPhase> phase_;
  Input<msg::Rc> rc_;
  Input<msg::Range> range_;
  Input<msg::FcuStatus> fcu_;
  Output<msg::Actuators> actuators_;
  Output<msg::ControllerInternals> internals_;

  /// Pilot override: which manual mode, and the aux switch that selects angle mode.
  struct ManualMode {
    std::string mode = "passthrough";
    std::int64_t angle_aux = -1;
    template <class V>
    static void describe(V& v) {
      v(&ManualMode::mode, "manual_mode",
        ParamSpec("", 0, 0, "when the pilot overrides: surfaces from the sticks, or roll and pitch angles from the sticks")
            .one_of({"passthrough", "angle"}));
      v(&ManualMode::angle_aux, "angle_mode_aux",
        ParamSpec("", -1, 3, "rc aux channel (0..3) whose value > 0.5 selects angle mode in override; -1: none"));
    }
  };

  LateralGains lateral_;
  PitchGains pitch_;
  AutopilotSettings settings_;
  LandingSettings landing_;
  ManualMode manual_;

  std::optional<Autopilot> autopilot_;
  bool dirty_ = true;
  /// Everything one flight changes besides the autopilot's loops: reset() replaces it wholesale.
  struct Flight {
    std::optional<Nanos> last_step;
    std::optional<Command> hold_command;  ///< before the first command: hold the first state's
    bool holding = false;                 ///< the last step held the previous command
    bool state_valid_once = false;        ///< the estimator's state has been valid in this flight
    std::uint64_t held_steps = 0;
    std::uint64_t manual_steps = 0;
  } flight_;
};

}  // namespace tern::control
