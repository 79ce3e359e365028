// core/apps/import/sensor_log_writer.hpp: writes a sensor log (docs/sensor-log.md), the
// directory `tern replay` reads, for `tern import`'s converters.
//
//   <out_dir>/sensor_log.yaml     the metadata (finish())
//   <out_dir>/topics/<topic>.csv  one table per topic, written by the flight log's own writer
//                                 (record/flight_log.hpp), so that the tables are byte for byte
//                                 what a tern flight log holds: header "t [s],stamp [ns],...",
//                                 doubles in shortest round-trip form
//
// Streaming: rows are formatted and written as they come. Memory is bounded by the flight log's
// buffers (256 KiB per topic waiting for its writer thread, at most 64 MiB queued to it), not by
// the length of the input. A row's time `t` is the message's `stamp`; a topic whose stamps go
// backwards is an ImportError (the importers check their inputs' order and report it first).
#pragma once

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "import/sensor_log_notes.hpp"
#include "record/flight_log.hpp"
#include "tern/reflect.hpp"

namespace tern::core {

/// An input that cannot be imported, or an output that cannot be written: one line, naming the
/// file (and line and field, for an input).
struct ImportError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What an importer did: rows written per topic, and what the user must know about the input
/// (low rates, dropped rows, assumptions), one line each.
struct ImportReport {
  std::map<std::string, std::uint64_t> rows;
  std::vector<std::string> warnings;
};

/// sensor_log.yaml's content (docs/sensor-log.md).
struct SensorLogMeta {
  std::string source;    ///< the original log and the converter, free text
  std::string aircraft;  ///< free text
  std::string date;      ///< UTC date of the flight, ISO 8601 ("2014-02-11"); "" if unknown (omitted)
  YAML::Node estimator;  ///< estimator settings the log implies: parameter name -> value
  /// s of log time: the airborne part, for the replay report's window (omitted when unset)
  std::optional<std::pair<double, double>> airborne;
  std::vector<std::string> notes;  ///< what the converter assumed, one line each
};

/// estimator_ekf's IMU timing for an IMU whose longest interval is `max_interval`: the defaults
/// (400 Hz: imu_max_dt 0.05 s, imu_timeout 0.02 s, imu_reinit_gap 0.5 s) where they hold, else
/// 1.5x (integrate every interval whole), 2x (no time-out between two samples) and 5x it. What
/// `tern import` writes into sensor_log.yaml, and what `tern replay` takes for a log from elsewhere
/// that does not set them (commands/estimator_replay.hpp).
YAML::Node imu_timing_settings(Nanos max_interval);

class SensorLogWriter {
 public:
  /// Creates out_dir (and its parents). Throws ImportError if out_dir exists and is not an
  /// empty directory, or cannot be created.
  explicit SensorLogWriter(const std::filesystem::path& out_dir);
  ~SensorLogWriter();
  SensorLogWriter(const SensorLogWriter&) = delete;
  SensorLogWriter& operator=(const SensorLogWriter&) = delete;

  /// Appends msg to topics/<topic>.csv (declared with T's reflect layout on first use) at row
  /// time msg.stamp (ns). Throws ImportError if msg.stamp is earlier than the topic's last row.
  template <class T>
  void write(std::string_view topic, const T& msg) {
    Topic& t = topic_slot(topic, reflect::layout<T>(), sizeof(T), reflect::fingerprint<T>());
    check_order(topic, t, msg.stamp);
    log_.capture(t.index, msg.stamp, &msg);
    if (t.rows > 0) t.max_interval = std::max(t.max_interval, msg.stamp - t.last_stamp);
    if (t.rows == 0) t.first_stamp = msg.stamp;
    t.last_stamp = msg.stamp;
    ++t.rows;
  }

  /// Writes sensor_log.yaml and flushes every table. Throws ImportError if anything could not
  /// be written (disk full, ...). Call once. The IMU's timing settings the estimator needs for
  /// this log (imu_max_dt, imu_timeout, imu_reinit_gap: imu_timing_settings(), above) are added to
  /// meta.estimator where the importer did not set them, and so is the time-out of every other
  /// sensor slower than 2.5 Hz (slow_sensor_timeouts()).
  /// `warnings` (the import's, ImportReport::warnings) are kept beside the notes, each as
  /// "import warning: ...", so that the log says later what the import said once (a table not
  /// written and why: tern sysid names it when the table is missing).
  void finish(const SensorLogMeta& meta, const std::vector<std::string>& warnings = {});

  /// The input's name (the archive or directory imported), written as `origin:` by finish().
  void set_origin(std::string origin) { origin_ = std::move(origin); }
  /// How a warning names the input as the user gave it (an archive's unpacked files: its own name).
  void set_readable(std::function<std::string(const std::string&)> readable) { readable_ = std::move(readable); }
  /// Rows written so far per topic.
  std::map<std::string, std::uint64_t> rows() const;
  const std::filesystem::path& dir() const { return dir_; }

 private:
  struct Topic {
    std::size_t index = 0;
    std::uint64_t fingerprint = 0;
    Nanos first_stamp = 0;
    Nanos last_stamp = 0;
    std::uint64_t rows = 0;
    Nanos max_interval = 0;  ///< longest interval between consecutive rows
  };
  Topic& topic_slot(std::string_view topic, std::vector<reflect::Column> columns, std::size_t size, std::uint64_t fingerprint);
  static void check_order(std::string_view topic, const Topic& t, Nanos stamp);
  /// `<sensor>_timeout` (gnss, baro, diff_pressure, mag) for each such topic whose mean interval
  /// is longer than 0.4 s (slower than 2.5 Hz: estimator_ekf's time-outs, 0.5-1 s, would report
  /// gaps between two samples): 2.5 mean intervals, always longer than the default. A faster
  /// sensor keeps the default, so a real drop-out is still reported.
  YAML::Node slow_sensor_timeouts() const;

  std::filesystem::path dir_;
  FlightLog log_;
  std::map<std::string, Topic, std::less<>> topics_;
  std::string origin_;
  std::function<std::string(const std::string&)> readable_;
  bool finished_ = false;
};

}  // namespace tern::core
