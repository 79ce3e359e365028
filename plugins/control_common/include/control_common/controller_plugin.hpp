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

 protected:
  /// Declares the law's parameters (use declare_gain so that changes take effect).
  virtual void declare_law_params() = 0;
  /// Copies the law's parameter values into the law; may throw ParamError on inconsistent values.
  virtual void apply_law_params() = 0;
  virtual LongitudinalLaw& law() = 0;

  /// Declares a real parameter whose changes are applied before the next step.
  void declare_gain(Param<double>& p, std::string name, double default_value, ParamSpec spec);

  /// Shared longitudinal limits (both laws use them).
  Param<double> theta_max_, theta_min_, trim_t_, max_t_, min_t_;
  /// The lower throttle limit, never above max_t (a runtime change cannot invert the limits).
  double min_t() const { return min_t_() < max_t_() ? min_t_() : max_t_(); }

 private:
  void apply_params();
  Mode select_mode(const msg::State& s);
  Autopilot& autopilot();

  Input<msg::State> state_;
  Input<msg::ControllerCommand> command_;
  Input<msg::FlightPhase> phase_;
  Input<msg::Rc> rc_;
  Input<msg::FcuStatus> fcu_;
  Output<msg::Actuators> actuators_;
  Output<msg::ControllerInternals> internals_;

  Param<double> course_kp_, course_ki_, course_kd_, roll_max_, roll_rate_max_, roll_ff_;
  Param<double> roll_kp_, roll_ki_, roll_kd_, trim_a_, max_a_;
  Param<double> yaw_kr_, yaw_p_wo_, trim_r_, max_r_;
  Param<double> pitch_kp_, pitch_ki_, pitch_kd_, trim_e_, max_e_;
  Param<double> takeoff_throttle_, takeoff_pitch_, rotation_Va_, handover_tau_;
  Param<bool> climb_course_hold_;
  Param<std::string> manual_mode_;
  Param<std::int64_t> angle_mode_aux_;
  Param<double> angle_roll_max_, angle_pitch_max_;

  std::optional<Autopilot> autopilot_;
  bool dirty_ = true;
  std::optional<Nanos> last_step_;
  std::optional<Command> hold_command_;
  bool holding_ = false;
  std::uint64_t held_steps_ = 0;
  std::uint64_t manual_steps_ = 0;
};

}  // namespace tern::control
