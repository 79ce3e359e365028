// core/src/record/flight_log.hpp: the flight log directory.
//
//   <run>/config.yaml       the resolved config (every parameter's effective value)
//   <run>/topics/<t>.csv    one table per logged topic: a header row "name [unit]", then one row
//                           per published message (t [s] = flight time of the tick)
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
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "record/log_file.hpp"
#include "tern/port.hpp"
#include "tern/reflect.hpp"
#include "tern/time.hpp"

namespace spdlog::sinks {
class sink;
}

namespace tern::core {

namespace fs = std::filesystem;

class FlightLog {
 public:
  /// Hand buffered rows to the writer at least this often (wall time): with the writer's own
  /// latency, a killed flight loses less than 100 ms of log.
  static constexpr std::int64_t kFlushPeriodNs = 50'000'000;
  /// Called with the log's first write error, once, on the thread that called the FlightLog
  /// method that noticed it (never from the writer thread or under a logger's lock).
  using ErrorHandler = std::function<void(const std::string& line)>;

  /// Creates the run directory (and its parent). Never throws: when it cannot, the error is
  /// reported and nothing is logged.
  explicit FlightLog(fs::path run_dir, ErrorHandler on_error = {});
  ~FlightLog();  ///< close()

  const fs::path& dir() const { return dir_; }

  /// Declares a topic to log: its column layout and message size. Returns its index.
  std::size_t add_topic(const std::string& topic, std::vector<reflect::Column> columns, std::size_t msg_size);
  /// Copies one message of topic `index` (msg_size bytes at data), logged at flight time t.
  void capture(std::size_t index, Nanos t, const void* data);
  /// A parameter value at time t ("default", "config", "cli", "dds" ... as source).
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
    std::unique_ptr<LogFile> file;
    std::vector<char> pending;  // records: int64 t, then msg_size bytes
  };
  struct Chunk {
    std::size_t topic;  // SIZE_MAX: params file
    std::vector<char> bytes;
  };
  void writer_loop();
  void write_chunk(const Chunk& c, std::unique_ptr<char[]>& text, std::size_t& capacity);
  void report();
  void hand_over(std::size_t topic, std::vector<char>& buf);
  /// Formats the records in `bytes` as CSV rows into `out` (grown to `capacity` when needed);
  /// returns the number of characters written.
  std::size_t format(const Topic& t, const std::vector<char>& bytes, std::unique_ptr<char[]>& out, std::size_t& capacity) const;

  fs::path dir_;
  ErrorHandler on_error_;
  LogHealth health_;
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
