// core/host/graph/remote_queue.hpp: parameter changes and mission edits from other threads, applied
// between ticks.
//
// The command line (`tern serve`), the DDS bridge and the host API queue them from any thread;
// the flight thread applies them at the start of the next tick (apply()), so a plugin never
// sees a value change during its step. Parameter values arrive validated (the parameter's
// ParamSpec) and are applied in arrival order; every change is recorded with the tick's time
// and its source ("cli", "dds"). Mission edits are published on topic `mission_edit` by the
// host's own output, one per tick (a port holds one message), in arrival order; the path
// planner applies them. Requests queued between flights are applied at the first tick of the
// next flight. Pilot input (the console's sticks and switches) is a latest-value slot: the newest
// msg::Rc set before a tick is published on topic `pilot` at its start (sim_aero reports it on
// `rc`); older ones are dropped, as a receiver drops stale frames.
// The queues are bounded (kMaxQueued each): a request beyond is refused, not held, so that a
// ground station or a DDS client flooding requests between flights (nothing drains the queue then)
// cannot grow the host's memory without bound (fuzz_mission_protocol).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/fwd.h>

#include "tern/msg/mission.hpp"
#include "tern/msg/sensors.hpp"
#include "tern/param.hpp"
#include "tern/port.hpp"

namespace tern::core {

class RemoteQueue {
 public:
  /// The most parameter changes, and the most mission edits, waiting for the next flight's ticks.
  /// A tick applies every parameter change and publishes one edit; the planner keeps
  /// msg::MissionEdit::kQueue of them.
  static constexpr std::size_t kMaxQueued = 1000;

  /// Records one applied change: flight time, qualified name ("slc.roll_kp"), the parameter
  /// (holding its new value), source.
  using ParamRecorder = std::function<void(Nanos, const std::string&, const ParamBase&, const std::string&)>;

  /// Queues `param` = `value` (already validated by param.validate()). Any thread. Throws
  /// ConfigError when kMaxQueued changes already wait.
  void request_param(ParamBase& param, std::string qualified_name, ParamValue value, std::string source);
  /// Whether the port graph took the output for mission edits (some plugin reads `mission_edit`).
  bool takes_mission_edits() const { return mission_edit_out_ != nullptr; }
  /// Queues a mission edit (takes_mission_edits() first). Any thread. Throws ConfigError when
  /// kMaxQueued edits already wait, unless `own` (the host's own edits, a failsafe's loiter or
  /// return: never refused).
  void edit_mission(const msg::MissionEdit& edit, bool own = false);
  /// Mission edits waiting for their tick (one is published per tick). Any thread.
  std::size_t queued_edits() const;

  /// Queues the operator's go-around, from `source` (any thread); the flight thread takes it with
  /// take_go_around() and hands it to the phase machine.
  void request_go_around(std::string source);
  std::optional<std::string> take_go_around();

  /// Whether the port graph took the output for pilot input (some plugin reads `pilot`).
  bool takes_pilot() const { return pilot_out_ != nullptr; }
  /// Replaces the pending pilot input (takes_pilot() first). Any thread.
  void set_pilot(const msg::Rc& rc);
  /// A fresh output for topic `pilot`, to offer to the next port graph; keep_pilot_output as below.
  const OutputBase* renew_pilot_output();
  void keep_pilot_output(bool taken);

  /// A fresh output for topic `mission_edit` (sequence 0), to offer to the next port graph.
  const OutputBase* renew_mission_edit_output();
  /// After the graph is built: whether it took the output (else it is dropped).
  void keep_mission_edit_output(bool taken);

  /// On the flight thread, at the start of a tick at flight time `now`: publishes the pending
  /// pilot input and the first queued mission edit and applies every queued parameter change, recording each with
  /// `record`. A value the parameter refuses now is logged as an error and not applied.
  void apply(Nanos now, const ParamRecorder& record, spdlog::logger& log);
  /// Before a flight's start(): applies every queued parameter change (asked for between
  /// flights), start-only and live alike, recorded at t = 0: the flight is then the one a host
  /// built with those values flies (a plugin may read a live parameter in start() too, as
  /// sim_aero's wind sets its trim).
  void apply_before_start(const ParamRecorder& record, spdlog::logger& log);

  /// `param`'s value, read from any thread (a ground station's or the DDS bridge's): apply() and
  /// apply_before_start() change values under the same lock. The flight thread, which is the only
  /// writer, reads its parameters directly.
  ParamValue value_of(const ParamBase& param) const;

 private:
  struct ParamRequest {
    ParamBase* param;
    std::string name;
    ParamValue value;
    std::string source;
  };
  /// Sets one queued change under values_mu_ (throws what the parameter's set() throws).
  void set_value(const ParamRequest& rq);
  mutable std::mutex mu_;
  mutable std::mutex values_mu_;          // held while a queued change is set, and by value_of()
  std::vector<ParamRequest> params_;      // under mu_
  std::vector<msg::MissionEdit> edits_;   // under mu_
  std::optional<msg::Rc> pilot_;          // under mu_
  std::optional<std::string> go_around_;  // under mu_
  std::atomic<bool> go_around_pending_{false};
  std::atomic<bool> pending_{false};  // something is queued
  std::unique_ptr<Output<msg::MissionEdit>> mission_edit_out_;
  std::unique_ptr<Output<msg::Rc>> pilot_out_;
};

}  // namespace tern::core
