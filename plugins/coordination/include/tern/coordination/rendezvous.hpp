// tern/coordination/rendezvous.hpp: timed rendezvous of several fixed-wing aircraft at one point
// (ROSplane 2.0's "a multi-agent coordination algorithm might specify a rendezvous point as a
// single waypoint"). Plain C++ (Eigen), no host types.
//
// The plan, from every vehicle's estimated position, course and wind at time t (common frame,
// path_estimate.hpp):
//   1. L_i = turn_then_line_length(p_i, chi_i, point, R): the remaining path to the point, a turn
//      of radius R onto the straight line to it (the CS tail of a Dubins path, uavbook
//      sec. 11.2.3).
//   2. The common arrival time T = t + max_i L_i / Vg_i(Va_nominal): the vehicle farthest in time
//      flies at the nominal airspeed (Vg_i: ground speed along the line in vehicle i's wind
//      estimate, the wind triangle of uavbook sec. 2.3).
//   3. Each vehicle's command: the ground speed L_i / (T - t) it needs, turned into the airspeed
//      Va_i = |Vg q - w| (airspeed_for) and clamped to [Va_min, Va_max].
//   4. A vehicle for which even Va_min arrives more than time_tolerance early holds first: it
//      loiters on a circle of radius R that it is already on (centre R to the side of its course,
//      clockwise: to the right), for hold_time = (T - t) - |point - centre| / Vg(Va_nominal), then
//      flies to the point at Va_nominal (the leg after a loiter starts from its centre, uavbook
//      sec. 10.3 orbit, sec. 11.2 leg). A hold leaves Va_nominal so that later replans can both
//      slow down and speed up.
// Replans with fresh estimates (the plugin's replan_period) repeat step 3-4 for vehicles in
// transit; a vehicle that cannot make T even at Va_max pushes T later (arrival_time_slip).
// Errors: RendezvousConfig::validate throws std::invalid_argument for an inconsistent config.
#pragma once

#include <vector>

#include "tern/coordination/path_estimate.hpp"

namespace tern::coord {

struct RendezvousConfig {
  double Va_min = 13.0;         ///< m/s, > 0
  double Va_nominal = 17.0;     ///< m/s, in [Va_min, Va_max]
  double Va_max = 22.0;         ///< m/s
  double turn_radius = 50.0;    ///< m, > 0: the vehicles' path manager's turn radius (R_min)
  double time_tolerance = 2.0;  ///< s, >= 0: an arrival this early or late needs no new command
  /// Throws std::invalid_argument naming the field when a value is out of range.
  void validate() const;
};

/// What the plan knows of one vehicle (the estimate, in the common frame).
struct VehicleKinematics {
  Vec2 p = Vec2::Zero();     ///< north, east, m
  double chi = 0.0;          ///< course over ground, rad
  Vec2 wind = Vec2::Zero();  ///< estimated wind north, east, m/s
};

/// One vehicle's command.
struct VehicleCommand {
  double path_length = 0.0;         ///< m, L_i (from the vehicle, or from the hold centre when holding)
  double Va_d = 0.0;                ///< m/s: to the point (Va_nominal after a hold)
  double hold_time = 0.0;           ///< s, > 0: loiter this long first
  Vec2 hold_center = Vec2::Zero();  ///< m, valid when hold_time > 0
  double eta = 0.0;                 ///< s, predicted arrival time with this command
};

/// Remaining path length (m) of a vehicle to `point`.
double path_length(const VehicleKinematics& k, const Vec2& point, const RendezvousConfig& cfg);
/// Time (s) to fly `length` towards `point` at airspeed Va in the vehicle's wind.
double time_to_go(const VehicleKinematics& k, const Vec2& point, double length, double Va);
/// Step 2: the arrival time T for vehicles `ks` at time t (s); t when ks is empty.
double arrival_time(double t, const std::vector<VehicleKinematics>& ks, const Vec2& point, const RendezvousConfig& cfg);
/// The latest arrival time any of `ks` can make at Va_max: max(T, t + L_i / Vg_i(Va_max)).
double arrival_time_slip(double t, double T, const std::vector<VehicleKinematics>& ks, const Vec2& point, const RendezvousConfig& cfg);
/// Steps 3-4: the command for one vehicle to arrive at T (s, > t).
VehicleCommand command_for(double t, double T, const VehicleKinematics& k, const Vec2& point, const RendezvousConfig& cfg);
/// Predicted arrival time (s) of a vehicle in transit commanded airspeed Va.
double predicted_arrival(double t, const VehicleKinematics& k, const Vec2& point, double Va, const RendezvousConfig& cfg);

}  // namespace tern::coord
