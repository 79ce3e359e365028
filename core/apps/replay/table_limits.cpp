// core/apps/replay/table_limits.cpp: what replay accepts of a sensor log's table (table_limits.hpp).
#include "replay/table_limits.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <map>
#include <string>
#include <string_view>

#include <fmt/chrono.h>
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

namespace {

/// The digits of a decimal number with one point at most ("12.5": "125", 2 before the point);
/// nullopt for anything else, an empty integer part included.
struct Decimal {
  std::string digits;
  long point = 0;  ///< digits before the decimal point
};
std::optional<Decimal> decimal_digits(std::string_view v) {
  const auto dot = v.find('.');
  const std::string_view whole = v.substr(0, dot), frac = dot == std::string_view::npos ? std::string_view() : v.substr(dot + 1);
  const auto digits_only = [](std::string_view d) { return d.find_first_not_of("0123456789") == std::string_view::npos; };
  if (whole.empty() || !digits_only(whole) || !digits_only(frac)) return std::nullopt;
  return Decimal{std::string(whole) + std::string(frac), static_cast<long>(whole.size())};
}

/// The exponent of "...e+02" / "...E-3": |exponent| at most kMaxTimeExponent (a time of up to a day
/// needs no more; a bound keeps "1e999999999" from spelling out a billion digits).
constexpr long kMaxTimeExponent = 20;
std::optional<long> exponent(std::string_view v) {
  if (!v.empty() && v[0] == '+') v.remove_prefix(1);
  long x = 0;
  const auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
  if (v.empty() || ec != std::errc() || p != v.data() + v.size() || x > kMaxTimeExponent || x < -kMaxTimeExponent) return std::nullopt;
  return x;
}

}  // namespace

std::optional<Nanos> parse_log_time(const std::string& s) {
  std::string_view v(s);
  const bool negative = !v.empty() && v[0] == '-';
  if (negative) v.remove_prefix(1);
  long exp10 = 0;
  if (const auto e = v.find_first_of("eE"); e != std::string_view::npos) {
    const std::optional<long> x = exponent(v.substr(e + 1));
    if (!x) return std::nullopt;
    exp10 = *x;
    v = v.substr(0, e);
  }
  std::optional<Decimal> d = decimal_digits(v);  // one sign at most: "--5" is not a number
  if (!d) return std::nullopt;
  // the point moved by the exponent, the digits padded with zeros to reach it
  long point = d->point + exp10;
  if (point < 0) d->digits.insert(0, static_cast<std::size_t>(-point), '0'), point = 0;
  if (point > static_cast<long>(d->digits.size())) d->digits.append(static_cast<std::size_t>(point) - d->digits.size(), '0');
  const std::string whole = d->digits.substr(0, static_cast<std::size_t>(point));
  std::string frac = d->digits.substr(static_cast<std::size_t>(point));
  const auto first = whole.find_first_not_of('0');
  if (first != std::string::npos && whole.size() - first > 6) return std::nullopt;  // beyond kMaxLogTime's 86400 s
  long long sec = 0;
  if (first != std::string::npos) std::from_chars(whole.data() + first, whole.data() + whole.size(), sec);
  // nanoseconds: more than 9 decimals (a float's shortest form, 564.0074999999999) round to the nearest
  const bool round_up = frac.size() > 9 && frac[9] >= '5';
  frac.resize(9, '0');
  long long ns = 0;
  std::from_chars(frac.data(), frac.data() + 9, ns);
  const Nanos t = sec * kNanosPerSecond + ns + (round_up ? 1 : 0);
  if (t > static_cast<Nanos>(kMaxLogTime) * kNanosPerSecond) return std::nullopt;
  return negative ? -t : t;
}

std::string unix_time_hint(double seconds) {
  constexpr double kYear2001 = 978307200.0, kYear2100 = 4102444800.0;  // s since 1970-01-01 UTC
  if (!(seconds >= kYear2001 && seconds < kYear2100)) return "";
  const auto when = std::chrono::sys_seconds(std::chrono::seconds(static_cast<long long>(seconds)));
  return fmt::format(
      ": seconds since 1970 ({:%Y-%m-%d %H:%M:%S} UTC)? the log's clock starts near its first row: subtract the first row's t from "
      "every table's t (and its stamp from every stamp and time_of_validity)",
      when);
}

void check_stamp_at_t(const std::filesystem::path& file, std::size_t line, Nanos t, Nanos stamp) {
  const double t_s = to_seconds(t), stamp_s = to_seconds(stamp);
  if (std::fabs(stamp_s - t_s) <= kMaxStampFromT) return;
  std::string unit;  // stamp over t 1e-3, 1e-6, 1e-9 (within a factor of 3): which of the two is in another unit
  for (const auto& [which, ratio] : {std::pair{"t in milliseconds or stamp in microseconds", 1e-3},
                                     {"t in microseconds or stamp in milliseconds", 1e-6},
                                     {"t in nanoseconds or stamp in seconds", 1e-9}})
    if (t_s != 0.0 && std::fabs(std::log10(stamp_s / (t_s * ratio))) < 0.5) unit = fmt::format("; {}?", which);
  throw ConfigError(
      fmt::format("{}:{}: stamp {} ns is {:.6g} s from t {} s: both are the time the sample reached the estimator, t in s "
                  "and stamp in ns (docs/sensor-log.md){}",
                  printable(file.string()), line, stamp, stamp_s - t_s, t_s, unit));
}

void RowTimes::check(const std::filesystem::path& file, std::size_t line, Nanos t) {
  const Nanos bound = static_cast<Nanos>(kMaxLogTime) * kNanosPerSecond;
  if (t > bound || t < -bound)
    throw ConfigError(fmt::format("{}:{}: {} {} s is more than {} s from the log's origin{} (docs/hostile-inputs.md)",
                                  printable(file.string()), line, column_, to_seconds(t), kMaxLogTime, unix_time_hint(to_seconds(t))));
  const Nanos gap = static_cast<Nanos>(kMaxRowGap) * kNanosPerSecond;
  if (last_ && t > *last_ && t - *last_ > gap)
    throw ConfigError(
        fmt::format("{}:{}: {} {} s is {} s after the row before ({} s): more than the {} s a table may pause "
                    "(docs/hostile-inputs.md)",
                    printable(file.string()), line, column_, to_seconds(t), to_seconds(t - *last_), to_seconds(*last_), kMaxRowGap));
  if (!last_ || t > *last_) last_ = t;
}

}  // namespace tern::core
