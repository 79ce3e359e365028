#include "gather.hpp"

#include <algorithm>

namespace tern_@NAME@ {

Eigen::Vector3d slot(const Eigen::Vector3d& point, std::size_t i, double spacing) {
  return point - Eigen::Vector3d(0.0, 0.0, static_cast<double>(i) * spacing);  // up is -d
}

bool within(const Eigen::Vector3d& p, const Eigen::Vector3d& point, double radius) {
  return (p.head<2>() - point.head<2>()).norm() <= radius;
}

void Separation::add(const std::vector<Eigen::Vector3d>& positions) {
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!positions[i].allFinite()) continue;
    for (std::size_t j = i + 1; j < positions.size(); ++j) {
      if (!positions[j].allFinite()) continue;
      const double d = (positions[i] - positions[j]).norm();
      min_ = seen_ ? std::min(min_, d) : d;
      seen_ = true;
    }
  }
}

}  // namespace tern_@NAME@
