// core/apps/replay/table_limits.cpp: what replay accepts of a sensor log's table (table_limits.hpp).
#include "replay/table_limits.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "config/error.hpp"
#include "tern/input_file.hpp"

namespace tern::core {

void check_table_file(const std::filesystem::path& file) {
  if (const std::string p = input_file_problem(file, kMaxTableBytes); !p.empty())
    throw ConfigError(fmt::format("{}: the table {}", printable(file.string()), p));
}

const std::vector<std::string>& required_columns(const std::string& topic) {
  // docs/sensor-log.md: every column of a sensor's table but those marked optional
  static const std::map<std::string, std::vector<std::string>> kRequired = {
      {"imu", {"stamp", "accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"}},
      {"gnss", {"stamp", "fix_type", "lat", "lon", "alt", "vel_n", "vel_e", "vel_d"}},
      {"baro", {"stamp", "pressure"}},
      {"diff_pressure", {"stamp", "pressure"}},
      {"mag", {"stamp", "field_x", "field_y", "field_z"}},
      {"actuators", {"stamp", "delta_a", "delta_e", "delta_r", "delta_t"}}};
  static const std::vector<std::string> kNone;
  const auto it = kRequired.find(topic);
  return it == kRequired.end() ? kNone : it->second;
}

std::optional<Nanos> parse_log_time(const std::string& s) {
  const bool negative = !s.empty() && s[0] == '-';
  const char* begin = s.data() + (negative ? 1 : 0);
  const char* end = s.data() + s.size();
  const char* dot = std::find(begin, end, '.');
  long long sec = 0;
  const auto [p, ec] = std::from_chars(begin, dot, sec);
  // one sign at most: "--5" would come back from from_chars as -5, and its negation as 5 past the bound
  if (ec != std::errc() || p != dot || sec < 0 || sec > static_cast<long long>(kMaxLogTime)) return std::nullopt;
  long long frac = 0;
  if (dot != end) {
    std::string f(dot + 1, end);
    if (f.size() > 9 || f.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
    f.resize(9, '0');
    std::from_chars(f.data(), f.data() + 9, frac);
  }
  const Nanos t = sec * kNanosPerSecond + frac;
  if (t > static_cast<Nanos>(kMaxLogTime) * kNanosPerSecond) return std::nullopt;
  return negative ? -t : t;
}

void RowTimes::check(const std::filesystem::path& file, std::size_t line, Nanos t) {
  const Nanos bound = static_cast<Nanos>(kMaxLogTime) * kNanosPerSecond;
  if (t > bound || t < -bound)
    throw ConfigError(fmt::format("{}:{}: {} {} s is more than {} s from the log's origin (docs/hostile-inputs.md)",
                                  printable(file.string()), line, column_, to_seconds(t), kMaxLogTime));
  const Nanos gap = static_cast<Nanos>(kMaxRowGap) * kNanosPerSecond;
  if (last_ && t > *last_ && t - *last_ > gap)
    throw ConfigError(
        fmt::format("{}:{}: {} {} s is {} s after the row before ({} s): more than the {} s a table may pause "
                    "(docs/hostile-inputs.md)",
                    printable(file.string()), line, column_, to_seconds(t), to_seconds(t - *last_), to_seconds(*last_), kMaxRowGap));
  if (!last_ || t > *last_) last_ = t;
}

}  // namespace tern::core
