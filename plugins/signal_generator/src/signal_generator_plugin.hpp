// signal_generator: takes over one loop's command while the rest of the stack flies, with a test
// signal (signal.hpp), for tuning that loop; after ROSplane 2.0's rosplane_tuning signal
// generator, which publishes every command itself. Here the path follower keeps flying the other
// loops: its command is read on `follower_command` (remap the follower's `controller_command`
// output there) and republished on `controller_command` with the chosen loop replaced.
//
// Ports
//   in  follower_command      msg::ControllerCommand    required; passed through, one field replaced
//   in  flight_phase          msg::FlightPhase          optional; start_phase cruise waits for it
//   in  controller_internals  msg::ControllerInternals  optional; base of roll and pitch (reference command)
//   out controller_command    msg::ControllerCommand    every step once a follower command arrived
// Before the signal engages the follower's command passes unchanged. At engagement (start_time s
// after the start of the flight, or of the first cruise phase) the base is latched and from then
// on the loop's command is base + offset + amplitude * w(t - t_engage). Roll and pitch also set
// override_phi / override_theta, so the controller (control_common's Autopilot) uses phi_c /
// theta_c instead of its course / altitude loop. The signal stays engaged to the end of the flight.
#pragma once

#include <optional>

#include "tern/plugin.hpp"
#include "tern/signal_generator/signal.hpp"

namespace tern::signal {

class SignalGeneratorPlugin final : public Plugin {
 public:
  void configure() override;
  void step(Nanos now) override;
  void start() override { flight_ = {}; }
  void reset() override { flight_ = {}; }
  std::vector<std::pair<std::string, double>> summary() const override;

 private:
  /// What lives one flight.
  struct Flight {
    std::optional<Nanos> anchor;   ///< flight time start_time counts from
    std::optional<Nanos> engaged;  ///< flight time the signal engaged
    double base = 0.0;             ///< loop units
  };
  void try_engage(Nanos now, const msg::ControllerCommand& follower);
  double latched_base(const msg::ControllerCommand& follower) const;

  Input<msg::ControllerCommand> follower_;
  Input<msg::FlightPhase> phase_;
  Input<msg::ControllerInternals> internals_;
  Output<msg::ControllerCommand> command_;
  Param<std::string> loop_, waveform_, reference_, start_phase_;
  Param<double> amplitude_, period_, offset_, start_time_;
  Loop loop_value_ = Loop::roll;
  Reference reference_value_ = Reference::command;
  Flight flight_;
};

}  // namespace tern::signal
