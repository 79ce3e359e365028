// core/host/record/flight_log.hpp: the flight log directory.
//
//   <run>/config.yaml       the resolved config (every parameter's effective value)
//   <run>/definitions.json  what the log's codes and defaults mean (log_definitions.hpp)
//   <run>/topics/<t>.csv    one table per logged topic: a header row "name [unit]", then one row
//                           per published message (t [s] = flight time of the tick): csv_rows.hpp
//   <run>/flight.mcap       the same topics in one MCAP file (log.format mcap or both): a channel
//                           "/<t>" per topic, ROS 2 CDR messages with tern_msgs/msg/<Name> ros2msg
//                           schemas (cdr_columns.hpp), log_time = flight time (ns), messages in
//                           the order captured; chunked and zstd-compressed, the open chunk on
//                           disk at every flush (mcap_writer.hpp); config.yaml, definitions.json,
//                           params.csv and summary.json attached at the end; a topic tern also speaks in a ROS
//                           type has a second channel in it (/tern/estimated_state as
//                           rosplane_msgs/msg/State, ...: ros_channels.hpp), and the 3-D scene
//                           the topics truth, state, waypoints and current_path draw (/tf and
//                           markers, for Foxglove's 3-D panel: scene_channels.hpp)
//   <run>/params.csv        every parameter value at start and every change, with time and source
//   <run>/tern.log          the host's text log
//   <run>/summary.json      what the flight did (deterministic: same config + seed, same bytes)
//   <run>/timing.json       how long it took (wall-clock: differs from run to run)
//
// Capturing a message costs one memcpy of the message into a per-topic buffer on the flight
// thread; a writer thread formats rows and writes them (write(2): in the kernel, so a killed
// process keeps them) whenever the host flushes, at least every kFlushPeriodNs of wall time, and
// on close. Records are never dropped: when the writer falls behind, capture waits for it.
//
// Write errors (disk full, read-only directory, file-size limit) never throw and never end the
// flight: the first one is reported once through the error handler, one line, and the log stops
// writing (see log_file.hpp); summary.json and timing.json are still attempted. The small files
// are replaced atomically (temp file + rename).
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "files/log_file.hpp"
#include "mcap/mcap_writer.hpp"
#include "ros/cdr_columns.hpp"
#include "ros/scene_channels.hpp"
#include "tern/port.hpp"
#include "tern/reflect.hpp"
#include "tern/time.hpp"

namespace spdlog::sinks {
class sink;
}

namespace tern::core {

namespace fs = std::filesystem;

/// Which files hold a flight log's topics (log.format: csv, mcap or both).
struct FlightLogFormat {
  bool csv = true;
  bool mcap = false;
  std::size_t mcap_chunk_bytes = McapWriter::Options{}.chunk_bytes;
  bool mcap_ros_channels = true;  ///< the ROS-typed copies of the topics that have one (ros_channels.hpp)
  /// ns of flight time: the least between two ROS-typed copies of one topic (0: a copy of every
  /// message). The copies are a convenience for ROS tools; tern's own channel keeps every message.
  std::int64_t mcap_ros_interval_ns = 0;
  int mcap_zstd_level = McapWriter::Options{}.zstd_level;
  /// The 3-D scene's frames and model (scene_channels.hpp), written with the ROS-typed copies.
  SceneOptions scene;
};

class FlightLog {
 public:
  /// Hand buffered rows to the writer at least this often (wall time): with the writer's own
  /// latency, a killed flight loses less than 100 ms of log.
  static constexpr std::int64_t kFlushPeriodNs = 50'000'000;
  /// Called with the log's first write error, once, on the thread that called the FlightLog
  /// method that noticed it (never from the writer thread or under a logger's lock).
  using ErrorHandler = std::function<void(const std::string& line)>;
  using Format = FlightLogFormat;

  /// Creates the run directory (and its parent). Never throws: when it cannot, the error is
  /// reported and nothing is logged.
  explicit FlightLog(fs::path run_dir, ErrorHandler on_error = {}, Format format = {});
  ~FlightLog();  ///< close()

  const fs::path& dir() const { return dir_; }

  /// Declares a topic to log: its column layout, message size and type name ("tern/State": the
  /// MCAP schema's name). Returns its index.
  std::size_t add_topic(const std::string& topic, std::vector<reflect::Column> columns, std::size_t msg_size,
                        std::string_view type_name = {});
  /// Copies one message of topic `index` (msg_size bytes at data), logged at flight time t.
  void capture(std::size_t index, Nanos t, const void* data);
  /// A parameter value at time t (its source: "default", "file:line", "--set ...", "dds" ...).
  void param(Nanos t, const std::string& qualified_name, const std::string& value, const std::string& source);
  /// Hands buffered rows to the writer (call at least every kFlushPeriodNs of wall time), and
  /// reports a write error the writer met since.
  void flush();
  /// Writes a whole small file in the run directory (config.yaml, summary.json ...), atomically.
  void write_file(const std::string& name, const std::string& text);
  /// A spdlog sink writing the text log `name` (e.g. "tern.log") in the run directory, line by
  /// line; it stops with the rest of the log on a write error.
  std::shared_ptr<spdlog::sinks::sink> text_sink(const std::string& name);
  /// Flushes everything and stops the writer thread. Idempotent.
  void close();
  /// The log's first write error, "" if none (some of the log is missing).
  std::string error() const { return health_.error(); }
  /// CPU time the writer thread used, s (complete after close()).
  double writer_cpu_s() const { return writer_cpu_s_.load(); }

 private:
  struct Topic {
    std::string name;
    std::vector<reflect::Column> columns;
    std::size_t msg_size = 0;
    std::unique_ptr<LogFile> file;  // null without CSV
    std::uint16_t channel = 0;      // MCAP channel (0: no MCAP)
    CdrEncoder cdr;                 // its messages on that channel
    struct Copy {                   // a ROS-typed channel this topic feeds (ros_channels.hpp, scene_channels.hpp)
      std::uint16_t channel = 0;
      std::function<void(const void*, std::vector<std::string>&)> encode;
      std::int64_t last = INT64_MIN / 2;  // flight time of its last copy (the writer thread's)
    };
    std::vector<Copy> copies;
    std::vector<char> pending;  // records: int64 t, then msg_size bytes
  };
  static constexpr std::size_t kParams = SIZE_MAX;    // Chunk::topic of params rows
  static constexpr std::size_t kMcap = SIZE_MAX - 1;  // Chunk::topic of MCAP records (all topics)
  static constexpr std::size_t kSync = SIZE_MAX - 2;  // Chunk::topic: the open MCAP chunk to disk
  struct Chunk {
    std::size_t topic;  // a topic's index, kParams, kMcap or kSync
    std::vector<char> bytes;
  };
  void writer_loop();
  void write_chunk(const Chunk& c, std::unique_ptr<char[]>& text, std::size_t& capacity);
  void write_mcap(const std::vector<char>& bytes);
  void add_ros_channels(Topic& t, std::string_view type_name);
  void add_copy(Topic& t, RosChannel ros, const McapWriter::Metadata& metadata);
  void report();
  void hand_over(std::size_t topic, std::vector<char>& buf);

  fs::path dir_;
  ErrorHandler on_error_;
  Format format_;
  LogHealth health_;
  std::unique_ptr<McapWriter> mcap_;
  std::unique_ptr<Scene> scene_;                    // with mcap_ros_channels
  std::map<std::string, std::uint16_t> copy_ids_;   // ROS-typed channels by topic, their schemas by "schema:" type
  std::vector<char> mcap_pending_;                  // records in capture order: uint64 topic, int64 t, msg_size bytes
  std::map<std::string, std::string> attachments_;  // name -> text, attached at the end
  std::string params_text_;                         // params.csv whole, attached at the end
  std::string cdr_;                                 // the writer thread's encoding buffer
  std::vector<std::string> ros_samples_;            // ...and its ROS-typed samples
  std::vector<std::max_align_t> aligned_;           // ...and a message at its alignment
  std::vector<std::unique_ptr<Topic>> topics_;
  std::unique_ptr<LogFile> params_file_;
  std::vector<char> params_pending_;
  std::mutex mu_;
  std::condition_variable cv_, cv_space_;
  std::deque<Chunk> queue_;
  std::size_t queued_bytes_ = 0;
  bool stop_ = false;
  bool closed_ = false;
  std::atomic<double> writer_cpu_s_{0.0};
  std::thread writer_;
};

}  // namespace tern::core
