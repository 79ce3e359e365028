// fleet.hpp: what the two coordination plugins share (adapter side, host types): the per-vehicle
// ports of a coordination plugin, the common frame, the wait for every vehicle, and the mission
// edits sent to the vehicles.
//
// Ports, for each vehicle v of Context::vehicles() (the host binds "v/T" to vehicle v's topic T):
//   in  v/state          msg::State, the vehicle's estimate in its own NED frame (origin_*)
//   in  v/flight_phase   msg::FlightPhase, optional: with start_phase = cruise, a vehicle counts
//                        once it is in cruise (not connected: once its state is valid, warned)
//   out v/mission_edit   msg::MissionEdit, to the vehicle's path planner: at most one edit per
//                        vehicle per step (the planner applies one edit per tick); more wait in
//                        a queue, in order
// Parameters: origin [lat deg, lon deg, alt m MSL] of the common frame; start_phase.
// Frames: a vehicle's position goes through its own origin to geodetic and into the common frame
// (tern/geodesy.hpp); its course and wind are taken as they are (the frames' axes differ by the
// angle between the origins' meridians, ~1e-4 rad for origins km apart). Waypoints go out as
// lat/lon/alt (lla), which each vehicle's planner converts into its own frame.
// Never the truth: only the estimate (`state`) is read.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tern/coordination/path_estimate.hpp"
#include "tern/geodesy.hpp"
#include "tern/plugin.hpp"

namespace tern::coord {

/// One vehicle's estimate in the common frame.
struct Observed {
  Eigen::Vector3d ned = Eigen::Vector3d::Zero();  ///< m, common frame
  double chi = 0.0;                               ///< course, rad
  Vec2 wind = Vec2::Zero();                       ///< m/s
};

class FleetPlugin : public Plugin {
 protected:
  /// In configure(): the ports of every vehicle and the shared parameters. Throws ParamError when
  /// there are no vehicles (not a multi-vehicle mission) or the origin is out of range.
  void declare_fleet();
  std::size_t vehicle_count() const { return names_.size(); }
  const std::string& vehicle(std::size_t i) const { return names_[i]; }
  /// Index of vehicle `name`, or nullopt.
  std::optional<std::size_t> index_of(const std::string& name) const;
  /// Vehicle i's estimate in the common frame, or nullopt while it is not usable: no state yet,
  /// not valid, no origin, or a non-finite field (warned once); with `for_start`, also while it
  /// is not in cruise (start_phase = cruise: the gate of the start only, not of what follows).
  std::optional<Observed> observe(std::size_t i, bool for_start);
  /// The common frame (from the `origin` parameter).
  GeoOrigin frame() const;
  /// A waypoint at `ned` (common frame, m) as lat/lon/alt.
  msg::Waypoint lla_waypoint(const Eigen::Vector3d& ned) const;
  /// Queues an add edit of `wp` for vehicle i (set_current: it starts a new list, now).
  void queue_add(std::size_t i, const msg::Waypoint& wp, bool set_current);
  /// Publishes the next queued edit of every vehicle (one each). Call at the end of step().
  void send_queued(Nanos now);
  /// Mission edits published so far this flight.
  std::uint64_t edits_sent() const { return fleet_.sent; }
  /// Between flights: queues, ids and warnings of the flight gone.
  void reset_fleet() { fleet_ = FleetFlight(names_.size()); }

 private:
  struct VehiclePorts {
    Input<msg::State> state;
    Input<msg::FlightPhase> phase;
    Output<msg::MissionEdit> edit;
  };
  struct FleetFlight {
    explicit FleetFlight(std::size_t n = 0) : pending(n), warned_nan(n, false), warned_phase(n, false) {}
    std::vector<std::deque<msg::MissionEdit>> pending;
    std::vector<bool> warned_nan, warned_phase;
    std::uint32_t next_id = 1;
    std::uint64_t sent = 0;
  };
  bool phase_ok(std::size_t i);
  std::vector<std::string> names_;
  std::vector<std::unique_ptr<VehiclePorts>> ports_;
  Param<std::vector<double>> origin_;
  Param<std::string> start_phase_;
  FleetFlight fleet_;
};

}  // namespace tern::coord
