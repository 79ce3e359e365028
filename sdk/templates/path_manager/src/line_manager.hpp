// line_manager.hpp: waypoint-to-waypoint straight-line path manager (plain C++, no tern types),
// Beard & McLain, *Small Unmanned Aircraft*, sec. 11.2.1, Algorithm 5 (Follow Waypoints:
// Straight-Line): the aircraft follows the line from w_{i-1} to w_i and switches to the next
// segment when it enters the half plane H(w_i, n_i), n_i = (q_{i-1} + q_i) / |q_{i-1} + q_i|,
// q_{i-1} = (w_i - w_{i-1}) / |w_i - w_{i-1}| (eq. 11.1-11.3).
// Positions are NED in m relative to the origin. With fewer than two waypoints, or after the
// last one of a mission that does not loop, the manager orbits (the only waypoint, the last
// one, or the origin at `loiter_altitude` when there is none).
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace tern_@NAME@ {

struct Segment {
  enum Type { line, orbit } type = line;
  Eigen::Vector3d r = Eigen::Vector3d::Zero();  ///< line: start point w_{i-1}, NED m
  Eigen::Vector3d q = Eigen::Vector3d::UnitX(); ///< line: unit direction
  Eigen::Vector3d c = Eigen::Vector3d::Zero();  ///< orbit: centre, NED m
  double rho = 0.0;                             ///< orbit radius, m
  int lambda = 1;                               ///< orbit direction, 1 clockwise
  int index = -1;                               ///< waypoint flown to (i), -1 for none
};

class LineManager {
 public:
  /// A new mission: waypoints w (NED, m), loop after the last one or not. Consecutive duplicate
  /// waypoints (closer than 1 m) are dropped. The first segment is w_0 -> w_1.
  void set_waypoints(std::vector<Eigen::Vector3d> w, bool loop);
  /// Segment to follow from position p (NED, m); advances through the waypoints as p crosses
  /// each switching half plane (at most one switch per call).
  Segment update(const Eigen::Vector3d& p);

  double orbit_radius = 50.0;     ///< m, radius of the loiter orbit
  double loiter_altitude = 100.0; ///< m above the origin, for the orbit when there are no waypoints
  std::size_t target() const { return i_; }  ///< index of w_i

 private:
  Segment orbit_at(const Eigen::Vector3d& c, int index) const;
  std::vector<Eigen::Vector3d> w_;
  bool loop_ = true;
  bool done_ = false;
  std::size_t i_ = 1;  ///< target waypoint w_i (the segment is w_{i-1} -> w_i)
};

}  // namespace tern_@NAME@
