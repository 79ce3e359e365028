// The world's magnetic field (see tern_sim_aero/earth_field.hpp).
#include "tern_sim_aero/earth_field.hpp"

#include <cmath>

namespace tern::sim {

tern::MagneticField earth_field(const SensorParams& p) {
  const bool all_set = std::isfinite(p.mag_declination) && std::isfinite(p.mag_inclination) && std::isfinite(p.mag_intensity);
  tern::MagneticField f;
  if (all_set) {
    f.model = "mag_* settings";
  } else {
    // origin_alt is MSL; the model wants the height above the ellipsoid: the geoid's undulation
    // (tens of m) changes the field by well under 1 nT.
    f = tern::world_magnetic_field(p.origin_lat, p.origin_lon, p.origin_alt, p.date);
  }
  const double D = std::isfinite(p.mag_declination) ? p.mag_declination : f.declination;
  const double I = std::isfinite(p.mag_inclination) ? p.mag_inclination : f.inclination;
  const double F = std::isfinite(p.mag_intensity) ? p.mag_intensity : f.intensity;
  f.declination = D;
  f.inclination = I;
  f.intensity = F;
  f.ned = F * Eigen::Vector3d(std::cos(I) * std::cos(D), std::cos(I) * std::sin(D), std::sin(I));
  return f;
}

SensorParams with_earth_field(SensorParams p) {
  const tern::MagneticField f = earth_field(p);
  p.mag_declination = f.declination;
  p.mag_inclination = f.inclination;
  p.mag_intensity = f.intensity;
  return p;
}

}  // namespace tern::sim
