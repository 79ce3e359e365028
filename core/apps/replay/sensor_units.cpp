// core/apps/replay/sensor_units.cpp: a sensor log's tables against their units (sensor_units.hpp).
#include "replay/sensor_units.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "config/error.hpp"
#include "tern/atmosphere.hpp"
#include "tern/math.hpp"
#include "tern/msg/sensors.hpp"

namespace tern::core {

namespace {

/// The finite values' element at `rank` (0 .. 1) of their sorted order: rank 0.5 the median (the
/// upper of the two middle ones), 0.05 the 5th percentile; nullopt when there is none.
std::optional<double> finite_rank(std::vector<double> v, double rank) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return std::nullopt;
  const auto at = v.begin() + static_cast<std::ptrdiff_t>(rank * static_cast<double>(v.size()));
  std::nth_element(v.begin(), std::min(at, v.end() - 1), v.end());
  return *std::min(at, v.end() - 1);
}
std::optional<double> finite_median(std::vector<double> v) { return finite_rank(std::move(v), 0.5); }

/// m/s^2: the range of the specific force's median magnitude (header)
constexpr double kMinMedianAccel = 0.5 * kStandardGravity, kMaxMedianAccel = 3.0 * kStandardGravity;
/// m/s^2: below this a median |f| is no accelerometer in g (1 g at rest and in level flight) but one
/// with gravity taken out (a phone's or a ROS driver's linear acceleration)
constexpr double kMinMedianAccelInG = 0.7;
/// rad/s: the RMS angular rate above which the gyros are not in rad/s (header)
constexpr double kMaxGyroRms = 4.0;

/// Pa: the barometer's median pressure's range (header)
constexpr double kMinPressure = 10e3, kMaxPressure = 120e3;
/// T: the magnetometer's median field's bound (header); the Earth's field at its surface (the
/// World Magnetic Model's range, equator to poles) and a typical value the units are named by
constexpr double kMaxField = 1e-3, kMinEarthField = 22e-6, kMaxEarthField = 67e-6, kEarthField = 50e-6;
/// Pa per pound-force per square inch and per inch of mercury (NIST SP 811, appendix B.8)
constexpr double kPaPerPsi = 6894.757, kPaPerInHg = 3386.389;

/// Pa: the pitot's reversed reading that no flight the right way round leaves (9 m/s backwards)
constexpr double kMinPitotQuantile = -50.0;

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

void require_imu_magnitudes(const std::filesystem::path& file, std::vector<double> specific_force, const std::vector<double>& rate) {
  if (const std::optional<double> mid = finite_median(std::move(specific_force));
      mid && !(*mid >= kMinMedianAccel && *mid <= kMaxMedianAccel)) {
    const char* likely = *mid > kMaxMedianAccel       ? "mg or cm/s^2 logged as m/s^2?"
                         : *mid >= kMinMedianAccelInG ? "g logged as m/s^2?"
                                                      : "gravity taken out (a linear acceleration)? the estimator needs the specific force";
    throw ConfigError(
        fmt::format("{}: the specific force's median magnitude is {:.4g} m/s^2: an accelerometer reads about {:.1f} at "
                    "rest and in level flight; {} (docs/sensor-log.md, imu: m/s^2)",
                    file.string(), *mid, kStandardGravity, likely));
  }
  double sum = 0.0;
  std::size_t n = 0;
  for (const double w : rate)
    if (std::isfinite(w)) sum += w * w, ++n;
  const double rms = n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
  if (!(rms > kMaxGyroRms)) return;
  throw ConfigError(
      fmt::format("{}: the gyros' RMS rate is {:.1f} rad/s ({:.0f} deg/s): no fixed wing turns that fast through a whole flight "
                  "(tern's aerobatics: 0.96 rad/s); deg/s logged as rad/s? (docs/sensor-log.md, imu)",
                  file.string(), rms, rms / kRadPerDeg));
}

void require_pressure_unit(const std::filesystem::path& file, std::vector<double> pressure) {
  const std::optional<double> mid = finite_median(std::move(pressure));
  if (!mid || (*mid >= kMinPressure && *mid <= kMaxPressure)) return;
  const std::string unit =
      likely_unit(*mid, kIsaSeaLevelPressure, {{"hPa (mbar)", 1e-2}, {"kPa", 1e-3}, {"psi", 1.0 / kPaPerPsi}, {"inHg", 1.0 / kPaPerInHg}});
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
      fmt::format("{}: the field's median magnitude is {:.4g} T: the Earth's is {:g}-{:g} uT ({:g} .. {:g} T){} "
                  "(docs/sensor-log.md, mag: T)",
                  file.string(), *mid, kMinEarthField * 1e6, kMaxEarthField * 1e6, kMinEarthField, kMaxEarthField,
                  unit.empty() ? "" : fmt::format("; {} logged as T?", unit)));
}

void require_gnss_units(const std::filesystem::path& file, GnssFixes fixes) {
  // each column's median against the estimator's range, with the units a log beyond it is in
  const auto require = [&](const char* column, std::vector<double> v, double lo, double hi, const char* unit, const char* likely) {
    const std::optional<double> mid = finite_median(std::move(v));
    if (!mid || (*mid >= lo && *mid <= hi)) return;
    throw ConfigError(
        fmt::format("{}: {}'s median over the fixes is {:.6g} {}: the estimator takes {:g} .. {:g} {} and refuses every "
                    "fix beyond; {} logged as {}? (docs/sensor-log.md, gnss)",
                    file.string(), column, *mid, unit, lo, hi, unit, likely, unit));
  };
  for (double& x : fixes.lat) x = std::fabs(x);
  for (double& x : fixes.lon) x = std::fabs(x);
  require("|lat|", std::move(fixes.lat), 0.0, msg::kGnssMaxAbsLat, "deg", "degrees * 1e7 (PX4's and ArduPilot's integer latitude)");
  require("|lon|", std::move(fixes.lon), 0.0, msg::kGnssMaxAbsLon, "deg", "degrees * 1e7 (PX4's and ArduPilot's integer longitude)");
  require("alt", std::move(fixes.alt), msg::kGnssMinAlt, msg::kGnssMaxAlt, "m", "mm or cm");
  require("the ground speed", std::move(fixes.speed), 0.0, msg::kGnssMaxSpeed, "m/s", "mm/s or cm/s");
}

void require_pitot_sign(const std::filesystem::path& file, std::vector<double> pressure) {
  const std::optional<double> low = finite_rank(pressure, 0.05), high = finite_rank(std::move(pressure), 0.95);
  if (!low || *low >= kMinPitotQuantile || -*low <= std::max(*high, 0.0)) return;
  throw ConfigError(
      fmt::format("{}: the pressure's 5th percentile is {:.4g} Pa and its 95th {:.4g} Pa: a pitot reads the dynamic pressure, "
                  "positive in flight; its tubes are swapped (the static port on the total) or the column negated: log "
                  "total minus static (docs/sensor-log.md, diff_pressure)",
                  file.string(), *low, *high));
}

}  // namespace tern::core
