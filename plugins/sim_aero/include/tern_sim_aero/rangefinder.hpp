// tern_sim_aero/rangefinder.hpp: a downward range finder over flat ground (the runway), after
// Garmin's LIDAR-Lite v3 (Operation Manual and Technical Specifications, "Specifications"): range
// 5 cm to 40 m, accuracy +-2.5 cm below 5 m and +-10 cm beyond (typical; taken here as 1 sigma),
// the figures of SensorParams' range_* fields (sensors.hpp).
// The sensor looks along its body +z axis (down, FRD) from range_position (body FRD, m); it measures
// the slant distance to the ground plane, h / cos(tilt). No return (+inf) beyond max_range or
// with the axis at or above the horizon; -inf nearer than min_range (sensor_msgs/Range's
// conventions, tern/msg/sensors.hpp Range).
//
// Its noise comes from a generator of its own (seeded from the flight's seed): the other sensors'
// draws, and with them every flight's log, do not change with the range finder on or off.
#pragma once

#include <cstdint>
#include <random>

#include <Eigen/Core>
#include <boost/random/normal_distribution.hpp>

#include "tern/aero/model.hpp"
#include "tern_sim_aero/sensors.hpp"

namespace tern::sim {

class RangeFinder {
 public:
  /// Throws std::invalid_argument when range_min is not below range_max.
  RangeFinder(const SensorParams& p, std::uint64_t seed);
  /// The distance measured at the true state x (sim::StateVector), m (+-inf: none, see above).
  double distance(const StateVector& x);

 private:
  double noise_near_, noise_far_, far_from_, min_range_, max_range_;
  Eigen::Vector3d position_;
  Rng rng_;
  boost::random::normal_distribution<double> n_{0.0, 1.0};
};

}  // namespace tern::sim
