// core/host/safety/failsafe_station.hpp: the failsafes (failsafe.hpp) in the host: what the monitor
// sees, and what becomes of its verdicts.
//
// Each tick, after every instance stepped, tick() reads
//   `state`   the estimate (a writer of msg::State on that topic, else none),
//   `gnss`    a new message with fix_3d and finite lat/lon is a valid fix (no writer: the GNSS
//             loss failsafe never engages),
//   the ground link: the count of ground_link_heard() calls (any thread: the DDS bridge on
//             every request and heartbeat, or a test) changed since the last tick,
// and runs the monitor. Each event is logged (warning: engagements; info: a cause that
// cleared) as "t=... s: failsafe <cause>: <detail>" and kept for summary.json (`failsafes`:
// t_s, cause, action, detail) and tern plot's markers. A loiter or return_home becomes a mission
// edit (add with set_current: the path planner flies that one item now, path manager's loiter
// or return_home) queued on the RemoteQueue, so it reaches the planner at the next tick. A
// termination binds `actuators` to the station's own output (the termination command) for the
// rest of the flight, rebinding it every tick in case the phase router routed the topic since.
// With no instance reading `mission_edit` an engagement is logged as an error and not flown.
//
// A ground station's geofence and rally points (MAVLink's FENCE and RALLY, set_zones / set_rally
// from its thread) replace the config's from the next tick on, for this flight and the next ones;
// geometry() and fence_status() read them from any thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include <spdlog/fwd.h>

#include "safety/failsafe.hpp"
#include "graph/port_graph.hpp"
#include "graph/remote_queue.hpp"
#include "tern/port.hpp"

namespace tern::core {

class PhaseMachine;

class FailsafeStation {
 public:
  explicit FailsafeStation(std::shared_ptr<spdlog::logger> log);

  /// Before the first tick: the config, the `state` and `gnss` writers of `graph`.
  void start_flight(const FailsafeConfig& config, const PortGraph& graph);
  /// The config's failsafes, before a flight (what geometry() gives until a ground station uploads).
  void configure(const FailsafeConfig& config);
  /// A ground station's geofence zones (any thread; empty: none, the config's distance and
  /// altitude limits stay), in force from the next tick on. An upload turns the geofence on.
  void set_zones(std::vector<FenceZone> zones);
  /// A ground station's rally points (n, e, altitude above home; m), as set_zones.
  void set_rally(std::vector<Eigen::Vector3d> rally);
  /// The zones and rally points in force, the config's or a ground station's (any thread).
  struct Geometry {
    std::vector<FenceZone> zones;
    std::vector<Eigen::Vector3d> rally;
  };
  Geometry geometry() const;
  /// The geofence has a limit and is on; the estimate is beyond it now (any thread).
  struct FenceStatus {
    bool enabled = false;
    bool breached = false;
  };
  FenceStatus fence_status() const;
  /// The ground station was heard (any thread).
  void ground_link_heard() { heard_.fetch_add(1, std::memory_order_relaxed); }
  /// At the end of a tick at flight time `now`. The failsafes engage only in the air: the phase
  /// machine's climb, cruise, loiter or landing (never without a phase machine); a termination
  /// sets the surfaces to its max_deflection.
  void tick(Nanos now, const PhaseMachine* phase_machine, RemoteQueue& remote, PortGraph& graph);
  const std::vector<FailsafeEvent>& events() const { return events_; }

 private:
  void act(const FailsafeEvent& e, double max_deflection, RemoteQueue& remote);
  /// The config with a ground station's zones and rally points (under mu_).
  FailsafeConfig effective() const;

  std::shared_ptr<spdlog::logger> log_;
  FailsafeMonitor monitor_;
  const OutputBase* state_ = nullptr;
  const OutputBase* gnss_ = nullptr;
  std::uint64_t gnss_seen_ = 0;
  std::optional<Nanos> last_fix_, link_heard_;
  std::atomic<std::uint64_t> heard_{0};
  std::uint64_t heard_seen_ = 0;
  std::vector<FailsafeEvent> events_;
  bool terminated_ = false;
  Output<msg::Actuators> terminate_out_;
  mutable std::mutex mu_;  // guards the four below
  FailsafeConfig base_;
  std::optional<std::vector<FenceZone>> zones_;
  std::optional<std::vector<Eigen::Vector3d>> rally_;
  bool changed_ = false;  // an upload the monitor has not taken yet
  std::atomic<bool> fence_enabled_{false}, fence_breached_{false};
};

}  // namespace tern::core
