// core/apps/replay/sensor_units.cpp: the barometer's and magnetometer's units (sensor_units.hpp).
#include "replay/sensor_units.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "config/error.hpp"
#include "tern/atmosphere.hpp"

namespace tern::core {

namespace {

/// The median of the finite values (the upper of the two middle ones); nullopt when there is none.
std::optional<double> finite_median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return std::nullopt;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// Pa: the barometer's median pressure's range (header)
constexpr double kMinPressure = 10e3, kMaxPressure = 120e3;
/// T: the magnetometer's median field's bound (header), and the Earth's field the units are named by
constexpr double kMaxField = 1e-3, kEarthField = 50e-6;

/// Of `units` (name, the reading in that unit of what the documented unit reads as 1), the one
/// whose reading of `reference` is nearest (in log ratio) `median`; "" when none is within 2x.
std::string likely_unit(double median, double reference, std::initializer_list<std::pair<const char*, double>> units) {
  std::string best;
  double nearest = std::log(2.0);
  for (const auto& [name, per_si] : units) {
    const double off = std::fabs(std::log(median / (reference * per_si)));
    if (off < nearest) nearest = off, best = name;
  }
  return best;
}

}  // namespace

void require_pressure_unit(const std::filesystem::path& file, std::vector<double> pressure) {
  const std::optional<double> mid = finite_median(std::move(pressure));
  if (!mid || (*mid >= kMinPressure && *mid <= kMaxPressure)) return;
  const std::string unit =
      likely_unit(*mid, kIsaSeaLevelPressure, {{"hPa (mbar)", 1e-2}, {"kPa", 1e-3}, {"psi", 1.0 / 6894.757}, {"inHg", 1.0 / 3386.389}});
  throw ConfigError(fmt::format(
      "{}: the pressure's median is {:.4g} Pa: a barometer reads about {:.0f} Pa at sea level and {:.0f} at "
      "5000 m{} (docs/sensor-log.md, baro: Pa)",
      file.string(), *mid, kIsaSeaLevelPressure, isa_pressure(5000.0), unit.empty() ? "" : fmt::format("; {} logged as Pa?", unit)));
}

void require_field_unit(const std::filesystem::path& file, std::vector<double> magnitude) {
  const std::optional<double> mid = finite_median(std::move(magnitude));
  if (!mid || *mid <= kMaxField) return;
  const std::string unit = likely_unit(*mid, kEarthField, {{"gauss", 1e4}, {"milligauss", 1e7}, {"microtesla", 1e6}, {"nanotesla", 1e9}});
  throw ConfigError(
      fmt::format("{}: the field's median magnitude is {:.4g} T: the Earth's is 22-67 uT (2.2e-05 .. 6.7e-05 T){} "
                  "(docs/sensor-log.md, mag: T)",
                  file.string(), *mid, unit.empty() ? "" : fmt::format("; {} logged as T?", unit)));
}

}  // namespace tern::core
