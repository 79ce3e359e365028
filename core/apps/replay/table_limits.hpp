// core/apps/replay/table_limits.hpp: what `tern replay` (and sysid, validate, which replay first)
// accepts of a sensor log's table before playing it (docs/hostile-inputs.md): a regular file of at
// most kMaxTableBytes (tern/input_file.hpp), the columns its topic needs (docs/sensor-log.md), times that are numbers on
// the log's clock within kMaxLogTime of its origin, and no pause longer than kMaxRowGap between two
// rows of a table, in `t` or in `stamp`. A log outside them is refused with one line naming the
// table, the row and the value, before any flight time is spent on it.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tern/input_file.hpp"
#include "tern/time.hpp"

namespace tern::core {

/// The longest pause between two rows of one table (s): no flight's sensor pauses for ten minutes
/// and is still replayed; a stamp jumping by 1e18 ns would have the replay fly 30 years.
inline constexpr double kMaxRowGap = 600.0;
/// The latest (and, negated, earliest) time of a row on the log's clock (s): one day, beyond any
/// small UAV's flight, whose replay still ends in minutes.
inline constexpr double kMaxLogTime = 86400.0;

/// Throws ConfigError "<file>: <why>" when `file` is a directory, a device (/dev/zero, a link to
/// it), a FIFO or larger than kMaxTableBytes.
void check_table_file(const std::filesystem::path& file);

/// The columns a table of `topic` must have besides `t` (docs/sensor-log.md's tables, without the
/// optional ones): imu's accel_x..gyro_z, baro's pressure, ...; none for truth and reference.
const std::vector<std::string>& required_columns(const std::string& topic);

/// `t [s]`'s text ("12.345000000", "-0.5", "5.640075e+02") as ns: exactly to 9 decimals, more
/// rounded to the nearest ns (half up: "564.0074999999999" is 564007500000); nullopt when it is not
/// a decimal number of seconds (one sign, digits before any point, an exponent of at most 20)
/// within kMaxLogTime.
std::optional<Nanos> parse_log_time(const std::string& text);

/// What to add to an error naming a time of `seconds` on the log's clock that is beyond
/// kMaxLogTime: where it looks like seconds since the Unix epoch (2001 .. 2100, a ROS bag's
/// header stamps exported as they are), that and how to bring the clock to the log's start;
/// else "".
std::string unix_time_hint(double seconds);

/// The most a row's `stamp` may lie from its `t` (s): both are the time the sample reached the
/// estimator on the log's clock (docs/sensor-log.md), in s and in ns; a sensor's own latency
/// belongs in sensor_log.yaml's delays or the GNSS's time_of_validity.
inline constexpr double kMaxStampFromT = 1.0;

/// Throws ConfigError "<file>:<line>: stamp ... is ... s from t ..." (with the units their ratio
/// points to: t in ms or stamp in us, ...) when `stamp` lies more than kMaxStampFromT from `t`
/// (both ns): a log with its stamps in microseconds replayed with 219858 IMU time-out warnings.
void check_stamp_at_t(const std::filesystem::path& file, std::size_t line, Nanos t, Nanos stamp);

/// The times of one table's rows, checked in file order: throws ConfigError "<file>:<line>: <column>
/// <value>: ... after the row before (...): more than the 600 s a table may pause" for a pause
/// longer than kMaxRowGap, or a time beyond kMaxLogTime.
class RowTimes {
 public:
  explicit RowTimes(std::string column) : column_(std::move(column)) {}
  void check(const std::filesystem::path& file, std::size_t line, Nanos t);

 private:
  std::string column_;
  std::optional<Nanos> last_;
};

}  // namespace tern::core
