// coord_rendezvous: timed rendezvous of every vehicle of a multi-vehicle mission at one point,
// vertically separated. The plan is tern/coordination/rendezvous.hpp's; this class binds it to
// ports (fleet.hpp), parameters and mission edits.
//
// Vehicle i (its place in the mission's vehicles: list, from 0) is sent to the point raised by
// i * altitude_spacing: "slot i". Once every vehicle is ready (fleet.hpp, start_phase) the
// plugin plans the arrival time T and sends each vehicle a new list (set_current):
//   [waypoint at slot i, Va_d]  [loiter at slot i, loiter_radius, no time limit]
// or, for a vehicle that would be early even at Va_min,
//   [loiter on a circle it is already on, Va_min]  [waypoint at slot i, Va_nominal]  [loiter at slot i]
// and ends the hold (a new list) at the first step from which the point at Va_nominal is reached
// no earlier than T - time_tolerance (the circle's loiter_time, hold_time plus one circle, is the
// manager's own way out).
// Every replan_period it replans the vehicles in transit from fresh estimates: a new list goes
// out only when the vehicle's predicted arrival with its current command misses T by more than
// time_tolerance (no thrashing of the path manager); a vehicle that cannot make T even at Va_max
// moves T later (every vehicle is then replanned). A vehicle has arrived when its estimate is
// within arrival_radius (horizontally) of the point; it then loiters over its slot (the list's
// last item) and is not replanned again.
//
// Summary (summary.json, <instance>.*): rendezvous_T (s, the final planned arrival time; -1 if
// never planned), rendezvous_T_initial (s), arrival_<vehicle> (s, -1: not arrived),
// arrival_spread (s, max - min over the arrived vehicles), arrival_error_max (s, max |arrival -
// T|), vehicles_arrived, replans (lists sent), mission_edits.
// Per-flight state (tern/plugin.hpp) in `flight_` (and the fleet's), replaced by reset().
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fleet.hpp"
#include "tern/coordination/rendezvous.hpp"

namespace tern::coord {

class RendezvousPlugin final : public FleetPlugin {
 public:
  void configure() override;
  void start() override;
  void step(Nanos now) override;
  void reset() override;
  std::vector<std::pair<std::string, double>> summary() const override;

 private:
  RendezvousConfig config() const;
  Eigen::Vector3d slot(std::size_t i) const;
  Vec2 point2() const;
  bool plan_all(double t, const std::vector<std::optional<Observed>>& obs);
  void detect_arrivals(double t, const std::vector<std::optional<Observed>>& obs);
  void replan(double t, const std::vector<std::optional<Observed>>& obs);
  void end_holds(double t, const std::vector<std::optional<Observed>>& obs);
  void command(std::size_t i, double t, const Observed& o);
  static VehicleKinematics kinematics(const Observed& o);

  Param<std::vector<double>> point_;
  Param<double> altitude_spacing_, Va_min_, Va_max_, Va_nominal_, arrival_radius_, replan_period_, turn_radius_, loiter_radius_,
      time_tolerance_;

  struct Vehicle {
    bool commanded = false;
    bool arrived = false;
    double arrival_t = -1.0;                                     ///< s
    double closest = std::numeric_limits<double>::infinity();    ///< m: within arrival_radius, the least distance yet
    double closest_t = -1.0;                                     ///< s: when
    double Va_sent = 0.0;                                        ///< m/s, to the point
    double hold_end = -std::numeric_limits<double>::infinity();  ///< s: holding until then
  };
  struct Flight {
    std::vector<Vehicle> v;
    std::optional<double> T;  ///< s, the planned arrival time
    double T_initial = -1.0;
    double last_replan = -std::numeric_limits<double>::infinity();
    bool waiting_logged = false;
    std::uint64_t replans = 0;
  } flight_;
  static bool passing(const Vehicle& v);
};

}  // namespace tern::coord
