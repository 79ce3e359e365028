// core/apps/import/ulog_conversion.hpp: the conversion pass of `tern import ulog` (internal to
// ulog_import.cpp and ulog_conversion.cpp): the survey of which topics hold data, and the handlers
// that turn one PX4 topic's data messages into sensor-log rows (the mapping: ulog_import.hpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "import/import_support.hpp"
#include "import/sensor_log_writer.hpp"
#include "import/surface_commands.hpp"
#include "import/ulog_import.hpp"
#include "import/ulog_reader.hpp"
#include "tern/msg/control.hpp"
#include "tern/msg/estimator.hpp"
#include "tern/msg/sensors.hpp"

namespace tern::core::ulog_import {

/// Rows of an output topic are put in time order within this window (ReorderWindow).
inline constexpr Nanos kReorderWindow = kNanosPerSecond;

/// Which topics (multi-instance 0) hold data, and whether old sensor_combined carries mag/baro samples.
struct Survey {
  std::map<std::string, std::uint64_t> rows;
  std::uint64_t combined_mag = 0, combined_baro = 0;
};
/// Reads `file`'s data section once and counts. Throws ulog::UlogError.
Survey survey(const std::filesystem::path& file);

/// A resolved field list of one subscription: `need` throws if absent (the source was chosen for it).
struct Fields {
  const ulog::Subscription& sub;
  const ulog::Field* opt(const std::string& name) const { return sub.field(name); }
  const ulog::Field& need(const std::string& name) const {
    const ulog::Field* f = sub.field(name);
    if (!f) throw std::out_of_range("topic '" + sub.name + "' has no field '" + name + "'");
    return *f;
  }
  std::array<const ulog::Field*, 3> vec(const std::string& name) const {
    return {&need(name + "[0]"), &need(name + "[1]"), &need(name + "[2]")};
  }
  /// The first of `names` the format has, or nullptr.
  const ulog::Field* first_of(std::initializer_list<const char*> names) const {
    for (const char* n : names)
      if (const ulog::Field* f = sub.field(n)) return f;
    return nullptr;
  }
};

/// Whether `topic`'s format has every one of `names` (flattened field names).
bool has_fields(const std::map<std::string, ulog::Format>& formats, const std::string& topic, std::initializer_list<const char*> names);

/// Everything the conversion pass carries.
class Conversion {
 public:
  Conversion(const ulog::Reader& reader, SensorLogWriter& out, ImportReport& report)
      : origin_us_(reader.start_timestamp()),
        params_(reader.initial_parameters()),
        report_(report),
        imu_(kReorderWindow, [&out](const msg::Imu& m) { out.write("imu", m); }),
        mag_(kReorderWindow, [&out](const msg::Mag& m) { out.write("mag", m); }),
        baro_(kReorderWindow, [&out](const msg::Baro& m) { out.write("baro", m); }),
        dp_(kReorderWindow, [&out](const msg::DiffPressure& m) { out.write("diff_pressure", m); }),
        gnss_(kReorderWindow, [&out](const msg::Gnss& m) { out.write("gnss", m); }),
        ref_(kReorderWindow, [&out](const msg::Reference& m) { out.write("reference", m); }),
        act_(kReorderWindow, [&out](const msg::Actuators& m) { out.write("actuators", m); }) {}

  /// The handlers of one topic, built when its subscription (multi-instance 0) appears.
  using Handler = std::function<void(const ulog::DataMessage&)>;
  std::map<std::string, std::vector<std::function<Handler(const Fields&)>>> factories;
  std::map<std::uint16_t, std::vector<Handler>> handlers;

  void subscribe(const ulog::Subscription& s) {
    handlers.erase(s.msg_id);
    if (s.multi_id != 0) return;
    const auto it = factories.find(s.name);
    if (it == factories.end()) return;
    const Fields f{s};
    for (const auto& make : it->second) handlers[s.msg_id].push_back(make(f));
  }
  void data(const ulog::DataMessage& d) {
    const auto it = handlers.find(d.subscription().msg_id);
    if (it == handlers.end()) return;
    for (const auto& h : it->second) h(d);
  }

  /// us since boot -> the log's clock, ns; nullopt (counted) before the log's start. Throws
  /// std::out_of_range for a time no int64 ns clock holds (a corrupt file; import_ulog names the
  /// file, as for a missing field: fuzz_ulog_conversion found a std::runtime_error escaping it),
  /// never overflows.
  std::optional<Nanos> stamp(std::int64_t t_us) {
    if (t_us < origin()) {
      ++before_start_;
      return std::nullopt;
    }
    const std::int64_t span_us = t_us - origin();  // both >= 0: no overflow
    if (span_us > std::numeric_limits<std::int64_t>::max() / 1000)
      throw std::out_of_range("timestamp " + std::to_string(t_us) + " us: beyond any clock's range after the log's start (" +
                              std::to_string(origin_us_) + " us): a corrupt file?");
    return span_us * 1000;
  }
  /// The header's start timestamp (us) as an int64, saturated (a corrupt header's 2^63 and more:
  /// fuzz_ulog_conversion found stamp()'s subtraction overflowing).
  std::int64_t origin() const {
    return static_cast<std::int64_t>(std::min<std::uint64_t>(origin_us_, std::numeric_limits<std::int64_t>::max()));
  }
  /// timestamp + relative (us) without overflow: saturated, for stamp() to refuse.
  static std::int64_t offset_us(std::uint64_t timestamp, std::int64_t relative) {
    const auto t = static_cast<std::int64_t>(std::min<std::uint64_t>(timestamp, std::numeric_limits<std::int64_t>::max()));
    std::int64_t out = 0;
    if (__builtin_add_overflow(t, relative, &out))
      return relative > 0 ? std::numeric_limits<std::int64_t>::max() : std::numeric_limits<std::int64_t>::min();
    return out;
  }
  /// The sample's time: timestamp_sample if the format has it, else timestamp.
  std::optional<Nanos> sample_stamp(const ulog::DataMessage& d, const ulog::Field* timestamp_sample) {
    return stamp(timestamp_sample ? d.integer(*timestamp_sample) : static_cast<std::int64_t>(d.timestamp()));
  }
  /// A PX4 parameter's value; nullopt if the log has none. Throws std::out_of_range (import_ulog
  /// names the file) for one that is not a number (fuzz_ulog_conversion: Value::number()'s
  /// std::invalid_argument escaped import_ulog).
  std::optional<double> param(const std::string& name) const {
    const auto it = params_.find(name);
    if (it == params_.end()) return std::nullopt;
    try {
      return it->second.number();
    } catch (const std::invalid_argument& e) {
      throw std::out_of_range("parameter '" + name + "': " + e.what());
    }
  }

  /// An integer PX4 parameter (MAV_TYPE, CA_SV_CS_COUNT, ...); nullopt if the log has none. Throws
  /// std::out_of_range for a value that is no int (a float parameter of NaN or 1e20: converting it
  /// was undefined behaviour, fuzz_ulog_conversion).
  std::optional<int> integer_param(const std::string& name) const {
    const std::optional<double> v = param(name);
    if (!v) return std::nullopt;
    if (!(*v >= std::numeric_limits<int>::min() && *v <= std::numeric_limits<int>::max()) || *v != std::trunc(*v))
      throw std::out_of_range("parameter '" + name + "': " + fmt_number(*v) + " is not an integer");
    return static_cast<int>(*v);
  }
  static std::string fmt_number(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }

  // Each registers the handler factory of one output's source topic.
  void add_imu();
  void add_mag(const std::string& source);
  void add_baro(const std::string& source);
  void add_diff_pressure(const std::string& source);
  void add_gnss(const std::string& source);
  void add_attitude(const std::string& source);
  void add_position(const std::string& source);
  void add_velocity(const std::string& source);
  void add_wind(const std::string& source);
  /// actuator_controls_N's control[0..3] (roll, pitch, yaw, throttle) through `mapping`, stamped
  /// with the message's timestamp (its publication).
  void add_actuators(const std::string& source, const CommandMapping& mapping);
  /// PX4 v1.13+'s control allocation: actuator_servos' positions (-1..1) weighted by each surface's
  /// torque effectiveness (CA_SV_CS<i>_TRQ_R/P/Y), per axis sum_i E_i s_i / sum_i |E_i|: two ailerons
  /// of effectiveness -0.5 and +0.5 give the mean of their antisymmetric deflection, an elevator of
  /// any effectiveness its own position; throttle: the mean of actuator_motors' `motors` (indices),
  /// the latest message in force. Rows at actuator_servos' timestamps.
  void add_servo_actuators(const std::array<std::vector<double>, 3>& effectiveness, const std::vector<int>& motors,
                           const CommandMapping& mapping);
  /// Releases the rows still held and reports what was dropped.
  void finish(const std::string& file, std::vector<std::string>& notes);

  std::string date;  ///< of the first GNSS fix with a UTC time
  IntervalStats imu_intervals, gnss_intervals, actuator_intervals;

 private:
  void write_mag(Nanos t, double x, double y, double z);
  std::uint64_t origin_us_;
  const std::map<std::string, ulog::Value>& params_;
  ImportReport& report_;
  ReorderWindow<msg::Imu> imu_;
  ReorderWindow<msg::Mag> mag_;
  ReorderWindow<msg::Baro> baro_;
  ReorderWindow<msg::DiffPressure> dp_;
  ReorderWindow<msg::Gnss> gnss_;
  ReorderWindow<msg::Reference> ref_;
  ReorderWindow<msg::Actuators> act_;
  std::uint64_t before_start_ = 0, nan_rows_ = 0, no_temperature_ = 0, course_velocity_ = 0;
  std::int64_t max_accel_relative_us_ = 0;
  std::string actuator_source_;
  double motor_throttle_ = 0.0;
  std::uint64_t nan_actuator_rows_ = 0, control_latency_count_ = 0;
  std::int64_t control_latency_sum_us_ = 0, control_latency_max_us_ = 0;
  Nanos last_combined_mag_ = -1, last_combined_baro_ = -1;
};

}  // namespace tern::core::ulog_import
