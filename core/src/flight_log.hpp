// core/src/flight_log.hpp: the flight log directory.
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
// thread; a writer thread formats rows and writes them, at least once a second and on close.
// Records are never dropped: when the writer falls behind, capture waits for it.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "tern/port.hpp"
#include "tern/reflect.hpp"
#include "tern/time.hpp"

namespace tern::core {

namespace fs = std::filesystem;

class FlightLog {
 public:
  /// Creates the run directory (and its parent). Throws ConfigError if it cannot.
  explicit FlightLog(fs::path run_dir);
  ~FlightLog();  ///< close()

  const fs::path& dir() const { return dir_; }

  /// Declares a topic to log: its column layout and message size. Returns its index.
  std::size_t add_topic(const std::string& topic, std::vector<reflect::Column> columns, std::size_t msg_size);
  /// Copies one message of topic `index` (msg_size bytes at data), logged at flight time t.
  void capture(std::size_t index, Nanos t, const void* data);
  /// A parameter value at time t ("default", "config", "cli", "dds" ... as source).
  void param(Nanos t, const std::string& qualified_name, const std::string& value, const std::string& source);
  /// Hands buffered rows to the writer (call about once a second of wall time).
  void flush();
  /// Writes a whole small file in the run directory (config.yaml, summary.json ...).
  void write_file(const std::string& name, const std::string& text);
  /// Flushes everything and stops the writer thread. Idempotent.
  void close();
  /// CPU time the writer thread used, s (complete after close()).
  double writer_cpu_s() const { return writer_cpu_s_.load(); }

 private:
  struct Topic {
    std::string name;
    std::vector<reflect::Column> columns;
    std::size_t msg_size = 0;
    std::FILE* file = nullptr;
    std::vector<char> pending;  // records: int64 t, then msg_size bytes
  };
  struct Chunk {
    std::size_t topic;  // SIZE_MAX: params file
    std::vector<char> bytes;
  };
  void writer_loop();
  void hand_over(std::size_t topic, std::vector<char>& buf);
  /// Formats the records in `bytes` as CSV rows into `out` (grown to `capacity` when needed);
  /// returns the number of characters written.
  std::size_t format(const Topic& t, const std::vector<char>& bytes, std::unique_ptr<char[]>& out,
                     std::size_t& capacity) const;

  fs::path dir_;
  std::vector<std::unique_ptr<Topic>> topics_;
  std::FILE* params_file_ = nullptr;
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
