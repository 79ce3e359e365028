// signal_generator: a test signal on one loop's command (tuning, after ROSplane 2.0's
// rosplane_tuning signal generator), or excitation manoeuvres added to the surfaces' commands
// (system identification, after ArduPilot's AP_SystemID), with the waveforms of signal.hpp.
//
// Loop mode (`axis` empty): the path follower's command is read on `follower_command` (remap
// the follower's `controller_command` there) and republished on `controller_command` with the
// chosen loop's command replaced, so the follower keeps flying the other loops.
//   in  follower_command      msg::ControllerCommand    required; passed through, one field replaced
//   in  flight_phase          msg::FlightPhase          optional; start_phase cruise waits for it
//   in  controller_internals  msg::ControllerInternals  optional; base of roll and pitch (reference command)
//   out controller_command    msg::ControllerCommand    every step once a follower command arrived
// Before the signal engages the follower's command passes unchanged. At engagement (start_time s
// after the start of the flight, or of the first cruise phase) the base is latched and from then
// on the loop's command is base + offset + amplitude * w(t - t_engage). Roll and pitch also set
// override_phi / override_theta, so the controller (control_common's Autopilot) uses phi_c /
// theta_c instead of its course / altitude loop. The signal stays engaged to the end of the flight.
//
// Surface mode (`axis` names surfaces: a list of manoeuvres, README.md): the controller's
// actuator command is read on `controller_actuators` (remap the controller's `actuators` output
// there) and republished on `actuators` (what sim_aero and fcu_serial read) with the manoeuvre's
// excitation added, the surfaces clamped to the aircraft file's max_delta_a/e/r (rad) and the
// throttle to [0, 1]. Outside a manoeuvre the command passes unchanged (bit for bit).
//   in  controller_actuators  msg::Actuators     required; the controller's command
//   in  state                 msg::State         required; the envelope and the airspeed sequence
//   in  flight_phase          msg::FlightPhase   optional; start_phase cruise; a change aborts
//   in  rc                    msg::Rc            optional; rc_channel's switch engages and aborts
//   in  mission_edit          msg::MissionEdit   optional; an edit (a failsafe's loiter or return
//                                                home, an operator's) aborts
//   out actuators             msg::Actuators     every step once a controller command arrived
//   out excitation            msg::Actuators     the increments added this step (rad, throttle
//                                                fraction; 0 outside a manoeuvre)
// Engagement: the mission (start_time after start_phase, then each airspeed of Va_sequence once
// the estimate has held it steady), the `engage` parameter at run time (now / off) or the RC
// switch. Abort (the rest of the sequence is dropped, the command passes unchanged at once, one
// warning line): the estimate invalid or out of the envelope (phi_max, theta_max, Va_min,
// h_min), a phase change, a mission edit, the RC switch off, RC failsafe or override, or
// engage: off. The host's own failsafes act downstream as well: a flight termination and the
// state-loss recovery bind `actuators` to their own command (core/host/safety).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "tern/plugin.hpp"
#include "tern/signal_generator/signal.hpp"

namespace tern::signal {

/// A surface axis of msg::Actuators.
enum class Surface { delta_a = 0, delta_e = 1, delta_r = 2, delta_t = 3 };

/// The system-identification shapes (surface mode).
enum class Shape { chirp, multisine, input_3211, doublet };

/// One manoeuvre of the list: the surfaces it excites at once and how.
struct Manoeuvre {
  std::vector<Surface> axes;
  Shape shape = Shape::chirp;
  std::vector<double> magnitude;  ///< per axis: rad (delta_a, delta_e, delta_r), throttle fraction (delta_t)
  Chirp chirp;                    ///< chirp: band, record, fades; multisine: band and record
  double pulse_width = 0.0;       ///< 3211, doublet: T_p, s
  std::vector<Multisine> multisine;
  double duration() const;
  std::array<double, 4> excitation(double t) const;  ///< increments per Surface, t s into the manoeuvre
  std::string describe() const;                      ///< "delta_a+delta_r multisine 0.3..3 Hz"
};

class SignalGeneratorPlugin final : public Plugin {
 public:
  void configure() override;
  void step(Nanos now) override;
  void start() override { flight_ = {}; }
  void reset() override { flight_ = {}; }
  std::vector<std::pair<std::string, double>> summary() const override;

  /// The manoeuvre list from the parameters (surface mode). Throws ParamError naming the
  /// parameter and its value.
  std::vector<Manoeuvre> plan() const;

 private:
  enum class Run { idle, settling, flying, gap };
  /// What lives one flight.
  struct Flight {
    std::optional<Nanos> anchor;   ///< flight time start_time counts from
    std::optional<Nanos> engaged;  ///< loop mode: flight time the signal engaged
    double base = 0.0;             ///< loop mode: loop units
    // surface mode
    Run run = Run::idle;
    bool mission_started = false;  ///< the mission's sequence began (it runs once)
    bool gated = false;            ///< the run waits for each airspeed of Va_sequence
    std::size_t block = 0;         ///< index into Va_sequence
    std::size_t item = 0;          ///< index into the manoeuvre list
    Nanos t0 = 0;                  ///< the manoeuvre's start, or the gap's end
    std::optional<Nanos> steady_since;
    msg::Phase phase_at_start = msg::Phase::cruise;
    std::vector<Manoeuvre> list;
    std::string engage_seen = "mission";
    bool rc_high = false;
    int flown = 0, aborts = 0;
    std::vector<std::pair<std::string, double>> marks;  ///< summary figures
  };
  void configure_loop_mode();
  void configure_surface_mode();
  void step_loop(Nanos now);
  void step_surfaces(Nanos now);
  void begin_run(Nanos now, bool gated, const std::string& why);
  void begin_manoeuvre(Nanos now);
  void end_manoeuvre(Nanos now);
  void abort(Nanos now, const std::string& why);
  std::optional<std::string> envelope_violation() const;
  bool active() const { return flight_.run != Run::idle; }
  /// "instance.param", as the host names a parameter in its errors.
  std::string qname(const std::string& p) const { return context().instance_name() + "." + p; }
  void try_engage(Nanos now, const msg::ControllerCommand& follower);
  double latched_base(const msg::ControllerCommand& follower) const;

  bool surface_mode_ = false;
  std::array<double, 3> max_delta_{};  ///< rad: the aircraft file's max_delta_a, _e, _r

  Input<msg::ControllerCommand> follower_;
  Input<msg::FlightPhase> phase_;
  Input<msg::ControllerInternals> internals_;
  Output<msg::ControllerCommand> command_;
  Input<msg::Actuators> controller_actuators_;
  Input<msg::State> state_;
  Input<msg::Rc> rc_;
  Input<msg::MissionEdit> mission_edit_;
  Output<msg::Actuators> actuators_, excitation_;

  Param<std::string> loop_, waveform_, reference_, start_phase_, axis_, engage_;
  Param<double> amplitude_, period_, offset_, start_time_;
  Param<std::vector<double>> magnitude_, f_start_hz_, f_stop_hz_, t_rec_, pulse_width_, Va_sequence_;
  Param<double> t_fade_in_, t_fade_out_, t_gap_, Va_tolerance_, t_settle_, phi_settle_;
  Param<double> phi_max_, theta_max_, Va_min_, h_min_;
  Param<std::int64_t> rc_channel_;
  Loop loop_value_ = Loop::roll;
  Reference reference_value_ = Reference::command;
  Flight flight_;
};

}  // namespace tern::signal
