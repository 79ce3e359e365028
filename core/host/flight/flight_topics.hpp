// core/host/flight/flight_topics.hpp: the topics an application watching a flight shows (the
// console's telemetry, the ground station's snapshot and its mission side), copied on the flight
// thread: one list of the topics watched, one gate of the copies.
//
// A watcher's tick observer (Host::add_tick_observer) calls TopicTap::take at every tick: at a
// flight's first tick and then every `period` of flight time it copies the latest message of each
// topic (has_* false for a topic nothing writes, or nothing wrote yet) and returns
// true; the watcher hands its copy to its own thread. It only reads topics: a flight flies the
// same bytes with or without it.
#pragma once

#include <cstdint>

#include "tern/msg/all.hpp"
#include "tern/time.hpp"

namespace tern::core {

class Host;

/// The latest message of each watched topic at flight time t.
struct FlightTopics {
  Nanos t = 0;  ///< flight time of the copy, ns
  bool has_state = false, has_command = false, has_internals = false, has_actuators = false;
  bool has_phase = false, has_path = false, has_rc = false, has_gnss = false, has_waypoints = false;
  msg::State state;                    ///< `state`: the estimate, never truth
  msg::ControllerCommand command;      ///< `controller_command`: Va_c, h_c, chi_c
  msg::ControllerInternals internals;  ///< `controller_internals`: phi_c, theta_c
  msg::Actuators actuators;            ///< `actuators`
  msg::FlightPhase phase;              ///< `flight_phase`
  msg::CurrentPath path;               ///< `current_path`: the path flown and its waypoint
  msg::Rc rc;                          ///< `rc`: the receiver (manual override, failsafe)
  msg::Gnss gnss;                      ///< `gnss`
  msg::WaypointList waypoints;         ///< `waypoints`: the planner's list
  std::uint64_t waypoints_seq = 0;     ///< lists its writer has published this flight (0: none)
};

class TopicTap {
 public:
  /// period: flight time between copies, ns (> 0).
  explicit TopicTap(Nanos period) : period_(period) {}
  /// At the tick at flight time `now`, on the flight thread: true with topics() copied anew at a
  /// flight's first tick (now 0) and every `period` after it; false between.
  bool take(const Host& host, Nanos now);
  /// The latest copy (flight thread).
  const FlightTopics& topics() const { return topics_; }

 private:
  Nanos period_;
  Nanos next_ = 0;
  FlightTopics topics_;
};

}  // namespace tern::core
