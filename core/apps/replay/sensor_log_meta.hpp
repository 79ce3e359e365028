// core/apps/replay/sensor_log_meta.hpp: a sensor log's sensor_log.yaml (docs/sensor-log.md), read
// for `tern replay`: what the log says of its sensors becomes settings of the estimator(s) that
// replay it.
//
//   tern_sensor_log: 1          required, the format version (1)
//   date: YYYY-MM-DD            UTC date of the flight -> the estimator's mag_model_date
//   estimator: {name: value}    estimator_ekf parameters the log implies (delays, rho, installation)
//   airborne: [start_s, end_s]  optional: the airborne part, for the replay report
// Other keys (source, aircraft, notes) are for people. A log without the file (a tern flight
// log) gives an empty SensorLogSettings.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include <yaml-cpp/yaml.h>

#include "config/config.hpp"

namespace tern::core {

struct SensorLogSettings {
  std::filesystem::path file;                   ///< sensor_log.yaml ("" if the log has none)
  std::map<std::string, YAML::Node> estimator;  ///< parameter name -> value (date included)
};

/// Reads LOG_DIR/sensor_log.yaml if present. Throws ConfigError, one line naming file:line:col and
/// the field: not YAML, a missing or unknown tern_sensor_log version, a date that is not YYYY-MM-DD,
/// an `estimator:` that is not a map of scalars and lists.
SensorLogSettings read_sensor_log_settings(const std::filesystem::path& log_dir);

/// Sets `s` on every estimator_ekf instance of `mc`, as its params: would (the error location is
/// sensor_log.yaml's line), over the replay config's own values; apply --set afterwards (it wins).
/// Values are checked when the plugin configures. Another estimator plugin gets none of them (its
/// parameters have other names): give them with --set.
void apply_sensor_log_settings(MissionConfig& mc, const SensorLogSettings& s);

/// The airborne part a log declares: sensor_log.yaml's `airborne: [start_s, end_s]` (s, the log's t).
struct AirborneWindow {
  double start_s = 0.0, end_s = 0.0;
};

/// `file`'s `airborne`, if the file and the key are there (the replay report's window; the airborne
/// samples of `tern sysid` and `tern validate`). Throws ConfigError "file:line:col: airborne: ..."
/// when the file is not YAML or the value is not two finite numbers with start before end.
std::optional<AirborneWindow> read_airborne_window(const std::filesystem::path& file);

}  // namespace tern::core
