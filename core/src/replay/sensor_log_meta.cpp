#include "replay/sensor_log_meta.hpp"

#include <fmt/format.h>

#include "config/error.hpp"

namespace tern::core {

namespace {

std::string where(const std::filesystem::path& file, const YAML::Node& n, const std::string& field) {
  return fmt::format("{}:{}:{}: {}", file.string(), n.Mark().line + 1, n.Mark().column + 1, field);
}

/// "2014-02-11" -> 2014.11 (the fraction of the year at 00:00 UTC that day).
double decimal_year_of(const std::string& text, const std::string& location) {
  int y = 0, m = 0, d = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%4d-%2d-%2d%c", &y, &m, &d, &tail) != 3 || m < 1 || m > 12 || d < 1 || d > 31)
    throw ConfigError(location + ": '" + text + "' is not a date YYYY-MM-DD");
  static constexpr int kDaysBefore[12] = {0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334};
  const bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  const int day_of_year = kDaysBefore[m - 1] + (leap && m > 2 ? 1 : 0) + d - 1;
  return y + day_of_year / (leap ? 366.0 : 365.0);
}

}  // namespace

SensorLogSettings read_sensor_log_settings(const std::filesystem::path& log_dir) {
  SensorLogSettings s;
  const auto file = log_dir / "sensor_log.yaml";
  if (!std::filesystem::exists(file)) return s;
  s.file = file;
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::Exception& e) {
    throw ConfigError(fmt::format("{}:{}:{}: not YAML: {}", file.string(), e.mark.line + 1, e.mark.column + 1, e.msg));
  }
  if (!root.IsMap()) throw ConfigError(file.string() + ": not a map of keys (docs/sensor-log.md)");
  const YAML::Node version = root["tern_sensor_log"];
  if (!version || !version.IsScalar() || version.as<std::string>() != "1")
    throw ConfigError(file.string() + ": tern_sensor_log: expected format version 1 (docs/sensor-log.md), got '" +
                      (version && version.IsScalar() ? version.as<std::string>() : std::string("(none)")) + "'");
  if (const YAML::Node est = root["estimator"]) {
    if (!est.IsMap()) throw ConfigError(where(file, est, "estimator") + ": expected a map of parameter: value");
    for (const auto& kv : est) {
      const auto name = kv.first.as<std::string>();
      if (!kv.second.IsScalar() && !kv.second.IsSequence())
        throw ConfigError(where(file, kv.second, "estimator." + name) + ": expected a value or a list");
      s.estimator[name] = kv.second;
    }
  }
  if (const YAML::Node date = root["date"]) {
    if (!date.IsScalar()) throw ConfigError(where(file, date, "date") + ": expected YYYY-MM-DD");
    if (!s.estimator.count("mag_model_date"))
      s.estimator["mag_model_date"] = YAML::Node(decimal_year_of(date.as<std::string>(), where(file, date, "date")));
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

}  // namespace tern::core
