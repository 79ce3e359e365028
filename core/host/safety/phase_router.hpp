// core/host/safety/phase_router.hpp: the phase router: which controller flies, and when the fallback
// takes over.
//
// The config's `phases:` table names a controller instance per flight phase (a phase it does
// not name is flown by cruise's). Those controllers are "routed": only the active one steps,
// and the topics they write (`actuators`, `controller_internals`) are bound to its outputs
// alone. A controller instance that the table and the fallback do not name is "idle"
// (Instance::idle): it is configured, but never steps and its ports stay out of the port graph,
// so it writes nothing (a research controller kept in the file while the stock one flies). The router follows the phase machine
// (phase_machine.hpp):
//   preflight, or the FCU disarmed   no controller runs (routed topics unbound)
//   a new phase                      its controller takes over (take_over() gets the last good
//                                    actuator command, so there is no jump)
// The fallback (`fallback:`, default: cruise's controller) takes over for the rest of the
// flight, in the same tick, when the active controller
//   - throws from step() or take_over(),
//   - commands a non-finite actuator value,
//   - commands a surface beyond phase_machine.max_deflection (rad) or a throttle outside [0, 1].
// fallback_reason() is the one place that decides this. If the fallback itself is the one
// failing, or it is engaged already, the flight ends with an error.
// The safety monitor (safety_monitor.hpp, limits from the phase machine's safety_* parameters)
// also engages the fallback, when a controller whose commands are all finite and within the
// limits is silent, flies the aircraft out of the envelope, or holds a surface at its stop while
// its error grows. It watches the phase's controller, not the fallback: with no other controller
// to hand over to, the cause is logged (once) and the flight goes on. With safety_hand_back, the
// next phase change after a safety engagement hands back to the phase's controller.
// While the estimate is invalid in climb or cruise, the built-in state-loss recovery
// (state_loss_recovery.hpp) flies instead of any controller: `actuators` is bound to the
// router's own output until the estimate is valid again, then the active controller takes over
// from the recovery's last command. Every handover (the recovery's too, as controller
// "state_loss_recovery") is recorded (time, from, to, reason) for summary.json and logged.
// When the graph is built, every controller the table or `fallback:` names must be a plugin of
// kind controller: ConfigError naming file, field and value otherwise.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/fwd.h>

#include "config/config.hpp"
#include "graph/instances.hpp"
#include "graph/port_graph.hpp"
#include "safety/safety_monitor.hpp"
#include "safety/state_loss_recovery.hpp"
#include "tern/msg/control.hpp"

namespace tern::core {

class PhaseMachine;

struct Handover {
  Nanos t;
  std::string from, to, reason;
};

class PhaseRouter {
 public:
  /// Steps a controller now; returns what it threw ("" if nothing).
  using StepFn = std::function<std::string(Instance&)>;

  /// Routes among `instances` (indices name them) by rebinding the routed topics of `graph`.
  /// Both are the host's and outlive the router.
  PhaseRouter(const std::vector<std::unique_ptr<Instance>>& instances, PortGraph& graph, std::shared_ptr<spdlog::logger> log);

  // ---- the table (when the graph is built, between flights)
  /// Reads `config.phases` and `config.fallback`: marks the controllers they name as routed
  /// and the other controllers idle, when there is a table (Instance::routed, Instance::idle:
  /// set before the port graph is built), picks the fallback and makes
  /// takeoff's controller the active one. Throws ConfigError when one of them is not a
  /// controller.
  void assign(const MissionConfig& config, PhaseMachine* phase_machine);
  std::optional<std::size_t> active() const { return active_; }
  std::optional<std::size_t> fallback() const { return fallback_; }
  /// Whether instance `idx` may step: it is not idle, and not routed or the active controller.
  bool may_step(std::size_t idx) const;

  // ---- a flight
  /// Before the plugins start: no handovers yet, no last command, fallback not engaged.
  void prepare_flight();
  /// After the plugins started: in preflight no controller runs.
  void start_flight();
  /// After the active controller `idx` stepped (`step_error`: what it threw, "" if nothing):
  /// keeps its command as the last good one, or engages the fallback and steps it with `step`
  /// in this same tick. Returns "" or the error that ends the flight.
  std::string after_controller_step(Nanos now, std::size_t idx, const std::string& step_error, const StepFn& step);
  /// After the phase machine stepped: on a new phase, routes to its controller (not once the
  /// fallback is engaged).
  void follow_phase(Nanos now);

  bool fallback_engaged() const { return fallback_engaged_; }
  const std::vector<Handover>& handovers() const { return handovers_; }

 private:
  /// Why controller `c` must give way to the fallback after its step, "" when it may go on:
  /// a hard failure (thrown, non-finite, beyond the limits), else the safety monitor's cause.
  struct Cause {
    std::string why;      // "" : none
    bool safety = false;  // the safety monitor's (the commands themselves were fine)
  };
  Cause fallback_reason(const Instance& c, const std::string& step_error, Nanos now);
  /// The safety monitor's verdict on the step that just ended, "" when none.
  std::string safety_cause(Nanos now);
  /// Starts or ends the state-loss recovery as the estimate turns invalid or valid again, and
  /// publishes its command while it flies.
  void update_recovery(Nanos now);
  /// Points the routed topics at the active controller, or `actuators` at the recovery.
  void rebind();
  /// A safety cause with no other controller to hand over to: logged once per cause kind.
  void log_unanswered(Nanos now, const std::string& why);
  void route_to(std::size_t idx, Nanos now, const std::string& reason, bool from_failure);
  /// No controller runs (the flight waits on the ground); routed topics lose their writer.
  void route_none(Nanos now, const std::string& reason);
  void engage_fallback(Nanos now, const std::string& why, bool may_hand_back = false);
  /// The active controller's `actuators` output, or nullptr.
  const OutputBase* find_actuators() const;
  std::optional<std::size_t> index_of(const std::string& instance) const;
  void require_controller(const std::string& instance, const std::string& at) const;

  const std::vector<std::unique_ptr<Instance>>& instances_;
  PortGraph& graph_;
  std::shared_ptr<spdlog::logger> log_;
  PhaseMachine* phase_machine_ = nullptr;
  std::map<msg::Phase, std::string> table_;  // phase -> controller instance
  std::optional<std::size_t> active_;
  std::optional<std::size_t> fallback_;
  const OutputBase* actuators_ = nullptr;  // the active controller's actuators (checked after each step)
  std::uint64_t phase_seen_ = 0;           // sequence of the last flight_phase message routed on
  bool fallback_engaged_ = false;
  bool hand_back_ = false;  // the fallback may hand back on the next phase change
  SafetyMonitor monitor_;
  StateLossRecovery recovery_;
  Output<msg::Actuators> recovery_out_;  // the recovery's command (a host output, bound while it flies)
  const OutputBase* imu_ = nullptr;      // the raw `imu` topic's writer (nullptr: none)
  std::uint64_t imu_seen_ = 0;
  std::uint64_t actuators_seen_ = 0;  // sequence of the active controller's actuators after its last step
  std::string safety_logged_;         // a safety cause with nobody to hand over to, logged once
  std::vector<Handover> handovers_;
  msg::Actuators last_good_{};
};

}  // namespace tern::core
