// The downward range finder. See tern_sim_aero/rangefinder.hpp.
#include "tern_sim_aero/rangefinder.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace tern::sim {

RangeFinder::RangeFinder(const SensorParams& p, std::uint64_t seed)
    : noise_near_(p.range_noise_near),
      noise_far_(p.range_noise_far),
      far_from_(p.range_far_from),
      min_range_(p.range_min),
      max_range_(p.range_max),
      position_(p.range_position),
      rng_(seed) {
  if (!(min_range_ < max_range_))
    throw std::invalid_argument("range_min (" + std::to_string(min_range_) + " m) must be below range_max (" + std::to_string(max_range_) +
                                " m)");
}

double RangeFinder::distance(const StateVector& x) {
  const double noise = n_(rng_);                             // drawn always: the stream stays aligned whatever the geometry
  const Eigen::Matrix3d R = attitude(x).toRotationMatrix();  // body -> NED
  const double h = -(x[PD] + (R * position_).z());           // the sensor's height above the ground
  const double cos_tilt = R(2, 2);                           // NED down component of body +z
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (!(cos_tilt > 0.0)) return kInf;
  const double d = h / cos_tilt;
  if (d > max_range_) return kInf;
  const double measured = d + (d < far_from_ ? noise_near_ : noise_far_) * noise;
  return measured < min_range_ ? -kInf : measured;
}

}  // namespace tern::sim
