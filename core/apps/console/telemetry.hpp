// core/apps/console/telemetry.hpp: what the console page shows, taken from a flight without
// slowing it down.
//
// TelemetryTap is a tick observer (Host::add_tick_observer): on the flight thread, at most every
// `period` of flight time (40 ms: 25 Hz, the 20-50 Hz), it copies the flight's watched
// topics (flight/flight_topics.hpp: the estimate, the controller's commands and internals, the
// actuators, the phase, the path and waypoints, the receiver) and the router's handovers (fallback
// engaged, why) into a Snapshot and hands it over under a mutex held only for the copy; the
// console's server thread takes the latest with latest() and never blocks the flight for longer
// than that copy. A topic nobody writes leaves its part of the snapshot invalid (has_* false).
#pragma once

#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "flight/flight_topics.hpp"
#include "tern/port.hpp"

namespace tern::core {

class Host;

/// Another vehicle of a multi-vehicle flight (fleet.hpp) as the console's vehicle sees it: its
/// estimate in the console vehicle's NED frame.
struct Traffic {
  std::string name;
  double p_n = 0, p_e = 0, h = 0;  ///< m (h = -p_d, above the console vehicle's origin)
  double psi = 0;                  ///< rad
};

/// What the page is shown: the watched topics and the safety side.
struct Snapshot : FlightTopics {
  std::uint64_t seq = 0;                ///< increases with every new snapshot (0: none yet)
  std::size_t handovers = 0;            ///< controller changes this flight
  std::string active, handover_reason;  ///< controller flying now ("": none); why the last change happened
  std::vector<Traffic> traffic;         ///< the other vehicles of a multi-vehicle flight
};

/// The snapshot as the page reads it: {"type":"telemetry", "t": s, "state": {...}, ...}, angles
/// in rad, altitude h = -p_d in m above the origin (p_d too, and the wind w = [w_n, w_e, w_d] in
/// m/s, for the 3-D view); waypoints only when `with_waypoints`.
nlohmann::json to_json(const Snapshot& s, bool with_waypoints);

class TelemetryTap {
 public:
  /// period: flight time between snapshots, ns (> 0).
  explicit TelemetryTap(Nanos period) : period_(period), topics_(period) {}
  /// The tick observer for `host`; valid while this tap lives.
  std::function<void(Nanos)> observer(const Host& host);
  /// A copy of the latest snapshot (seq 0: none yet). Any thread.
  Snapshot latest() const;
  /// The other vehicles of a multi-vehicle flight, asked on the flight thread with each snapshot
  /// (set it between flights).
  void set_traffic(std::function<std::vector<Traffic>()> source) { traffic_ = std::move(source); }

 private:
  void take(const Host& host);

  Nanos period_;
  TopicTap topics_;   // flight thread only
  Snapshot staging_;  // flight thread only
  std::function<std::vector<Traffic>()> traffic_;
  mutable std::mutex mu_;
  Snapshot latest_;  // under mu_
};

}  // namespace tern::core
