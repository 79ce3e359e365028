#include "replay/sensor_log_meta.hpp"

#include <cmath>

#include <fmt/format.h>

#include "config/error.hpp"
#include "tern/magnetic_model.hpp"

namespace tern::core {

namespace {

std::string where(const std::filesystem::path& file, const YAML::Node& n, const std::string& field) {
  return fmt::format("{}:{}:{}: {}", file.string(), n.Mark().line + 1, n.Mark().column + 1, field);
}

}  // namespace

SensorLogSettings read_sensor_log_settings(const std::filesystem::path& log_dir) {
  SensorLogSettings s;
  const auto file = log_dir / "sensor_log.yaml";
  if (!std::filesystem::exists(file)) return s;
  s.file = file;
  const YAML::Node root = load_yaml(file, "sensor log description");  // bounded (tern/input_file.hpp)
  if (!root.IsMap()) throw ConfigError(file.string() + ": not a map of keys (docs/sensor-log.md)");
  const YAML::Node version = root["tern_sensor_log"];
  if (!version || !version.IsScalar() || version.as<std::string>() != "1")
    throw ConfigError(file.string() + ": tern_sensor_log: expected format version 1 (docs/sensor-log.md), got '" +
                      (version && version.IsScalar() ? version.as<std::string>() : std::string("(none)")) + "'");
  if (const YAML::Node est = root["estimator"]) {
    if (!est.IsMap()) throw ConfigError(where(file, est, "estimator") + ": expected a map of parameter: value");
    for (const auto& kv : est) {
      // a key that is a list or a map (`{[1, 2]: 3}`): yaml-cpp's bare "bad conversion" otherwise
      if (!kv.first.IsScalar())
        throw ConfigError(where(file, kv.first, "estimator") + ": a parameter name is expected as key, got a " +
                          (kv.first.IsSequence() ? "list"
                           : kv.first.IsMap()    ? "map"
                                                 : "null"));
      const auto name = kv.first.as<std::string>();
      if (!kv.second.IsScalar() && !kv.second.IsSequence())
        throw ConfigError(where(file, kv.second, "estimator." + name) + ": expected a value or a list");
      s.estimator[name] = kv.second;
    }
  }
  if (const YAML::Node date = root["date"]) {
    if (!date.IsScalar()) throw ConfigError(where(file, date, "date") + ": expected YYYY-MM-DD");
    if (!s.estimator.count("mag_model_date")) try {
        s.estimator["mag_model_date"] = YAML::Node(tern::decimal_year(date.as<std::string>()));
      } catch (const std::invalid_argument& e) {
        throw ConfigError(where(file, date, "date") + ": " + e.what() + " (expected YYYY-MM-DD)");
      }
  }
  return s;
}

void apply_sensor_log_settings(MissionConfig& mc, const SensorLogSettings& s) {
  for (auto& ic : mc.plugins) {
    if (ic.plugin != "estimator_ekf") continue;
    for (const auto& [name, value] : s.estimator) {
      const std::string field = "estimator." + name;
      ic.params[name] = ParamSetting{value, s.file, field, true, ""};
    }
  }
}

std::optional<AirborneWindow> read_airborne_window(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) return std::nullopt;
  const YAML::Node root = load_yaml(file, "sensor log description");  // bounded (tern/input_file.hpp)
  const YAML::Node a = root.IsMap() ? root["airborne"] : YAML::Node();
  if (!a) return std::nullopt;
  AirborneWindow w;
  try {
    if (!a.IsSequence() || a.size() != 2) throw YAML::Exception(a.Mark(), "");
    w.start_s = a[0].as<double>();
    w.end_s = a[1].as<double>();
  } catch (const YAML::Exception&) {
    throw ConfigError(where(file, a, "airborne") + ": expected [start_s, end_s] (two numbers, s of the log's t)");
  }
  if (!(std::isfinite(w.start_s) && std::isfinite(w.end_s) && w.start_s < w.end_s))
    throw ConfigError(where(file, a, "airborne") + fmt::format(": [{}, {}]: start must be before end", w.start_s, w.end_s));
  return w;
}

}  // namespace tern::core
