// core/apps/replay/sensor_units.hpp: a sensor log's barometer and magnetometer tables against their
// columns' units (docs/sensor-log.md: pressure in Pa, field in T), before `tern replay` plays
// them. A table in another unit parses and plays, and every sample of it is refused by the
// estimator as out of range: a barometer in hPa gave one warning ("baro: invalid sample
// rejected ... further ones are only counted") and an estimate without its height sensor.
// Each check is on the median over the table, a statistic no flight in the right unit leaves, and
// throws ConfigError, one line naming the file, the median and the likely unit (sysid's checks of
// the IMU and the commands: sysid/log_units.hpp).
#pragma once

#include <filesystem>
#include <vector>

namespace tern::core {

/// baro.csv's `pressure` (Pa): the median of the finite values within 10 kPa (16 km up) ..
/// 120 kPa (above any sea-level pressure measured); else ConfigError naming hPa, kPa, psi or inHg
/// by the ratio to the standard atmosphere's 101325 Pa.
void require_pressure_unit(const std::filesystem::path& file, std::vector<double> pressure);

/// mag.csv's field magnitude (T): the median of the finite values at most 1 mT (the Earth's field
/// is 22-67 uT, a motor's or a battery's beside the magnetometer a few hundred); else ConfigError
/// naming gauss, milligauss, microtesla or nanotesla by the ratio to 50 uT.
void require_field_unit(const std::filesystem::path& file, std::vector<double> magnitude);

}  // namespace tern::core
