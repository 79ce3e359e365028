// tern/atmosphere.hpp: the International Standard Atmosphere's troposphere (ISO 2533:1975; the U.S.
// Standard Atmosphere 1976 agrees with it below 11 km), and the ROSflight firmware's variant of its
// pressure altitude. SI units: Pa, m, kg/m^3. Valid from about -500 to 11000 m (above, the
// stratosphere's isothermal layer); NaN stays NaN. Header only, no state.
#pragma once

#include <cmath>

namespace tern {

inline constexpr double kZeroCelsius = 273.15;            ///< K: 0 deg C (the kelvin's definition, SI Brochure sec. 2.3.1)
inline constexpr double kIsaSeaLevelPressure = 101325.0;  ///< Pa, p0
inline constexpr double kIsaSeaLevelDensity = 1.225;      ///< kg/m^3, rho0 (15 degC, p0)
/// The barometric formula p = p0 (1 - k h)^n: k = L / T0 (L = 0.0065 K/m, T0 = 288.15 K) and
/// n = g0 M / (R L), to the digits the world and the importers use.
inline constexpr double kIsaPressureLapse = 2.25577e-5;  ///< 1/m, k
inline constexpr double kIsaPressureExponent = 5.25588;  ///< n

/// Static pressure, Pa, at geopotential height h_m (m above mean sea level): p0 (1 - k h)^n.
inline double isa_pressure(double h_m) { return kIsaSeaLevelPressure * std::pow(1.0 - kIsaPressureLapse * h_m, kIsaPressureExponent); }

/// Pressure altitude, m, of a static pressure in Pa: h = (1 - (p / p0)^(1/n)) / k, with 1/k and 1/n
/// rounded to 44330.769 m and 0.190263 (the estimator's figures since it was written): within
/// 2.2 mm of isa_pressure's inverse from -300 to 8000 m.
inline double isa_pressure_altitude(double pressure_pa) {
  return 44330.769 * (1.0 - std::pow(pressure_pa / kIsaSeaLevelPressure, 0.190263));
}

namespace rosflight {
/// The ROSflight firmware's pressure altitude, m (lib/turbomath/turbomath.cpp alt(): ISA_PRESSURE,
/// ISA_EXPONENT 0.190326730028458, ISA_SCALE_FACTOR 44318.1386038261 m in turbomath.h), which
/// Sensors::correct_baro writes into its baro altitude (SMALL_BARO's altitude).
inline double pressure_altitude(double pressure_pa) {
  return (1.0 - std::pow(pressure_pa / kIsaSeaLevelPressure, 0.190326730028458)) * 44318.1386038261;
}
/// The firmware's indicated airspeed, m/s, from differential pressure in Pa, signed as the pressure
/// and +0 at +-0 (src/sensors.cpp Sensors::correct_diff_pressure: fsign(dp) sqrt(|dp| / (0.5 * 1.225));
/// lib/turbomath/turbomath.cpp fsign(y) = (0 < y) - (y < 0)).
inline double indicated_airspeed(double diff_pressure_pa) {
  const double sign = (0.0 < diff_pressure_pa) - (diff_pressure_pa < 0.0);
  return sign * std::sqrt(std::fabs(diff_pressure_pa) / (0.5 * kIsaSeaLevelDensity));
}
}  // namespace rosflight

}  // namespace tern
