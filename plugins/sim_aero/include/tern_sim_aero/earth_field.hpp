// tern_sim_aero/earth_field.hpp: the Earth's magnetic field of the simulated world. By default the
// World Magnetic Model's (tern/magnetic_model.hpp) at the world's origin (origin_lat, origin_lon,
// origin_alt) on the world's date; each of mag_declination, mag_inclination and mag_intensity
// that is set (finite) replaces the model's value: an explicit override, e.g. a measured local
// field. The field is the one at the origin over the whole flight (it changes by well under 1 nT
// over a few km: the sensors' own errors are 100x that).
#pragma once

#include "tern/magnetic_model.hpp"
#include "tern_sim_aero/sensors.hpp"

namespace tern::sim {

/// The world's field: ned (T), declination, inclination (rad), intensity (T). `model` names the
/// WMM release used ("WMM-2025"), or "mag_* settings" when all three components are set (the
/// model is then not evaluated); `extrapolated` says p.date is outside that release's span.
/// Throws std::invalid_argument for an origin or date the model refuses (tern/magnetic_model.hpp).
tern::MagneticField earth_field(const SensorParams& p);

/// p with every unset (NaN) mag_declination / mag_inclination / mag_intensity filled in from
/// earth_field(p): the values the world will use.
SensorParams with_earth_field(SensorParams p);

}  // namespace tern::sim
