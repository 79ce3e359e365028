// core/apps/replay/sensor_units.hpp: a sensor log's GNSS, barometer, pitot and magnetometer tables
// against their columns' units and signs (docs/sensor-log.md), before `tern replay` plays them.
// A table in another unit parses and plays, and the estimator refuses every sample of it as out
// of range: a barometer in hPa gave one warning ("baro: invalid sample rejected ... further ones
// are only counted") and an estimate without its height sensor; a GNSS altitude in cm one
// warning and an estimate that never started. Each check is on a statistic over the table that
// no flight in the right unit leaves, and throws ConfigError, one line naming the file, the value
// and the likely unit (sysid's checks of the IMU and the commands: sysid/log_units.hpp).
#pragma once

#include <filesystem>
#include <vector>

namespace tern::core {

/// imu.csv's magnitudes, one per finite row: the specific force's |f| (m/s^2) and the rates' |w|
/// (rad/s). Refused (ConfigError) when the median |f| lies outside 0.5 g .. 3 g (g at rest, g
/// times the load factor in flight: tern's aerobatics 1.0-1.1 g), naming g, a gravity-removed
/// (linear) acceleration, or mg and cm/s^2; or when the RMS |w| exceeds 4 rad/s (tern's aerobatics
/// 0.96, its sysid manoeuvres 0.24), naming deg/s. Any rotation of the IMU's axes keeps both:
/// they hold before its mounting is known.
void require_imu_magnitudes(const std::filesystem::path& file, std::vector<double> specific_force, const std::vector<double>& rate);

/// baro.csv's `pressure` (Pa): the median of the finite values within 10 kPa (16 km up) ..
/// 120 kPa (above any sea-level pressure measured); else ConfigError naming hPa, kPa, psi or inHg
/// by the ratio to the standard atmosphere's sea-level pressure (tern/atmosphere.hpp).
void require_pressure_unit(const std::filesystem::path& file, std::vector<double> pressure);

/// mag.csv's field magnitude (T): the median of the finite values at most 1 mT (the Earth's field
/// is 22-67 uT, a motor's or a battery's beside the magnetometer a few hundred); else ConfigError
/// naming gauss, milligauss, microtesla or nanotesla by the ratio to 50 uT.
void require_field_unit(const std::filesystem::path& file, std::vector<double> magnitude);

/// gnss.csv's fixes (rows with a 2-D or 3-D fix; finite values): the medians of |lat|, |lon|,
/// alt and the ground speed |(vel_n, vel_e, vel_d)| within the ranges the estimator holds a fix
/// to (tern/msg/sensors.hpp kGnssMaxAbsLat ..: 90 deg, 180 deg, -1000 .. 20000 m, 200 m/s; outside
/// them every fix is refused and the estimate never starts: sysid then stopped at "no airborne
/// samples"); else ConfigError naming deg * 1e7 (PX4's and ArduPilot's integer lat, lon), mm or cm,
/// mm/s or cm/s by the ratio.
struct GnssFixes {
  std::vector<double> lat, lon, alt, speed;  ///< deg, deg, m, m/s
};
void require_gnss_units(const std::filesystem::path& file, GnssFixes fixes);

/// diff_pressure.csv's `pressure` (Pa) read the right way round: refused (ConfigError naming
/// swapped tubes or a negated column) when its 5th percentile is below -50 Pa (a 9-m/s airspeed
/// the wrong way) and further below 0 than its 95th percentile above: a pitot whose total and
/// static ports are swapped reads minus the dynamic pressure in flight, and sysid identified
/// nothing from it ("0 of 29", exit 0).
void require_pitot_sign(const std::filesystem::path& file, std::vector<double> pressure);

}  // namespace tern::core
