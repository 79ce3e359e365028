// gather.hpp: the geometry of a gathering of several aircraft over one point (plain C++, Eigen,
// no tern types): each vehicle's stacked loiter slot, whether a vehicle has arrived, and the
// closest approach of any two vehicles. Positions are NED, m, in one frame common to every
// vehicle (the plugin converts each vehicle's estimate into it); times s.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace tern_@NAME@ {

/// Vehicle i's loiter centre: `point` raised by i * spacing (m, >= 0), so that the vehicles
/// orbiting it are vertically separated.
Eigen::Vector3d slot(const Eigen::Vector3d& point, std::size_t i, double spacing);

/// True when p is within `radius` (m) of `point` horizontally (north, east).
bool within(const Eigen::Vector3d& p, const Eigen::Vector3d& point, double radius);

/// The smallest 3-D distance between any two vehicles seen so far.
class Separation {
 public:
  /// One sample of every vehicle's position; non-finite positions are left out.
  void add(const std::vector<Eigen::Vector3d>& positions);
  /// m; 0 before any pair was seen.
  double min() const { return seen_ ? min_ : 0.0; }

 private:
  double min_ = 0.0;
  bool seen_ = false;
};

}  // namespace tern_@NAME@
