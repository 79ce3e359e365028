// core/apps/mavlink/flight_view.hpp: what the ground station's mission and command handlers
// (mission_protocol.hpp, gcs_commands.hpp) read of a flight, copied on the flight thread.
//
// A tick observer copies every 20 ms of flight time (the watched topics: flight/flight_topics.hpp)
// the estimate's position and origin (topic `state`: the estimate, never truth), the phase
// (`flight_phase`), the waypoint being flown (`current_path`) and, when the path planner has
// published a new one, its list (`waypoints`);
// the link's thread reads the latest copy (view()). It only reads topics: a flight flies the same
// bytes with or without it.
//
// Threads: the observer runs on the flight thread; view() from any thread (a mutex held for the copy).
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>

#include <Eigen/Core>

#include "flight/flight_topics.hpp"
#include "tern/geodesy.hpp"
#include "tern/msg/path.hpp"
#include "tern/msg/phase.hpp"
#include "tern/time.hpp"

namespace tern::core {

class Host;

namespace mavlink {

struct FlightView {
  bool flying = false;                              ///< a flight is running (Host::flying)
  bool has_state = false;                           ///< an estimate with a valid origin was seen (this flight or an earlier one)
  GeoPoint origin;                                  ///< the estimate's origin (home): lat, lon deg, alt m MSL
  Eigen::Vector3d p_ned = Eigen::Vector3d::Zero();  ///< the estimate's position, NED m about origin
  bool has_phase = false;
  msg::Phase phase = msg::Phase::preflight;
  std::int32_t waypoint_index = -1;               ///< index in `list` of the waypoint flown to (current_path), -1: none
  std::uint64_t list_seq = 0;                     ///< how many lists the planner has published this flight (0: none yet)
  std::shared_ptr<const msg::WaypointList> list;  ///< the latest (null: none since the link started)
  bool airborne() const {
    return flying && has_phase && phase != msg::Phase::preflight && phase != msg::Phase::stopped && phase != msg::Phase::rollout;
  }
};

class FlightWatch {
 public:
  /// Adds the observer to `host` (between flights).
  explicit FlightWatch(Host& host);
  ~FlightWatch();  ///< removes it (between flights)
  FlightWatch(const FlightWatch&) = delete;
  FlightWatch& operator=(const FlightWatch&) = delete;

  FlightView view() const;

 private:
  void observe(Nanos now);
  Host& host_;
  int id_ = 0;
  TopicTap topics_;             // flight thread
  std::uint64_t seen_seq_ = 0;  // flight thread: the `waypoints` sequence copied last
  mutable std::mutex mu_;
  FlightView view_;  // under mu_
};

}  // namespace mavlink
}  // namespace tern::core
