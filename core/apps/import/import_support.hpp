// core/apps/import/import_support.hpp: what every importer needs besides its own columns: finding
// the input's directory, dropping rows whose time goes backwards (counted, one warning per file),
// the sample intervals for the notes, and the air-data conversions of docs/sensor-log.md.
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "import/sensor_log_writer.hpp"
#include "tern/time.hpp"
#include "tern/atmosphere.hpp"
#include "tern/msg/sensors.hpp"

namespace tern::core {

/// `in` if it holds a file whose name ends with one of `suffixes` ("IMU.txt",
/// "-mavros-imu-data_raw.csv"), else its only subdirectory that does. Throws ImportError naming
/// `in` and the first suffix otherwise.
std::filesystem::path directory_holding(const std::filesystem::path& in, const std::vector<std::string>& suffixes);
/// The file in `dir` whose name ends with `suffix` (ALFA: "<bag>-mavros-imu-mag.csv"); "" if
/// none. Throws ImportError if several do.
std::filesystem::path file_ending_with(const std::filesystem::path& dir, const std::string& suffix);

/// Rows whose stamp is earlier than the previous accepted row's: dropped and counted.
class StampOrder {
 public:
  bool accept(Nanos stamp) {
    if (stamp < last_) {
      ++dropped_;
      return false;
    }
    last_ = stamp;
    return true;
  }
  /// One warning in `report` if rows of `file` were dropped.
  void report(const std::filesystem::path& file, ImportReport& report) const;

 private:
  Nanos last_ = std::numeric_limits<Nanos>::min();
  std::uint64_t dropped_ = 0;
};

/// Sample intervals of a topic: count, min, median-free summary (mean, max), in ms.
class IntervalStats {
 public:
  void add(Nanos stamp);
  std::uint64_t count() const { return n_; }
  double mean_s() const { return n_ > 1 ? static_cast<double>(last_ - first_) * 1e-9 / static_cast<double>(n_ - 1) : 0.0; }
  double max_s() const { return static_cast<double>(max_) * 1e-9; }
  /// "1234 samples, 145.2 Hz mean, intervals 5.5 to 20.2 ms"
  std::string describe() const;

 private:
  std::uint64_t n_ = 0;
  Nanos first_ = 0, last_ = 0, min_ = 0, max_ = 0;
};

/// The airborne part of a flight for sensor_log.yaml's `airborne` (the replay report's window):
/// from the first to the last GNSS fix (its stamp) whose horizontal speed reaches 5 m/s, the rule
/// the report applies to a log without one (replay/replay_report.hpp), written down so that a
/// reader sees it and may narrow it.
class AirborneWindow {
 public:
  static constexpr double kSpeed = 5.0;  ///< m/s, horizontal GNSS speed
  void add(Nanos stamp, double vel_n, double vel_e) {
    if (!(std::hypot(vel_n, vel_e) >= kSpeed)) return;
    if (!first_) first_ = stamp;
    last_ = stamp;
  }
  /// Sets meta.airborne and a note saying where it came from; nothing without such a fix.
  void write_to(SensorLogMeta& meta) const;

 private:
  std::optional<Nanos> first_, last_;
};

/// A log's sensor temperature in deg C as the message's kelvin: celsius + 273.15 within -100 to
/// 150 deg C; else (not a number, a sensor's "none" code) counted in `missing` and the message's
/// default (msg::Baro's 288.15 K, the ISA's sea level), which a note then says was written.
inline double kelvin_from_celsius(double celsius, std::uint64_t& missing) {
  if (std::isfinite(celsius) && celsius > -100.0 && celsius < 150.0) return celsius + kZeroCelsius;
  ++missing;
  return msg::Baro{}.temperature;
}

/// Pitot differential pressure from an equivalent airspeed (EAS is defined at sea-level
/// density): 0.5 * 1.225 kg/m^3 * EAS^2, Pa.
inline double diff_pressure_from_eas(double eas_m_s) { return 0.5 * kIsaSeaLevelDensity * eas_m_s * eas_m_s; }
/// Static pressure of an ISA pressure altitude h (m, against 1013.25 hPa), troposphere:
/// 101325 (1 - 2.25577e-5 h)^5.25588, Pa.
inline double isa_pressure_from_height(double h_m) { return isa_pressure(h_m); }

}  // namespace tern::core
