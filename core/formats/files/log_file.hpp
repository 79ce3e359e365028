// core/formats/files/log_file.hpp: the files of one flight log, and what happens when writing them fails.
//
// A full disk, a read-only directory or a file-size limit must not end a flight: the first write
// error of a log is recorded once in its LogHealth, every file of the log stops writing, and the
// flight goes on. The small files written at the end (summary.json, timing.json) are still
// attempted, so a log that lost its tables may keep its summary.
//
//   LogHealth              the first error of one log (thread-safe), reported once
//   LogFile                an append-only table (CSV, text log) written with write(2): what
//                          append() returns from is in the kernel, so a killed process loses
//                          nothing already appended. A failed or short write cuts the file back
//                          to its last complete line, so that readers see whole rows only.
//   write_file_atomically  a small file replaced at once (temp file + rename): a killed process
//                          leaves the old file or the new one, never half of one. (No fsync: a
//                          power cut may still lose it.)
#pragma once

#include <sys/types.h>

#include <atomic>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

namespace tern::core {

namespace fs = std::filesystem;

class LogHealth {
 public:
  /// Records `what` (one line) if it is the log's first error; later errors are dropped.
  void fail(std::string what);
  bool failed() const { return failed_.load(std::memory_order_acquire); }
  /// The first error ("" if none).
  std::string error() const;
  /// The first error, the first time it is asked for after it happened; nullopt otherwise.
  std::optional<std::string> take_unreported();

 private:
  mutable std::mutex mu_;
  std::string error_;
  bool reported_ = false;
  std::atomic<bool> failed_{false};
};

class LogFile {
 public:
  /// Creates (truncates) `path`; a failure is recorded in `health`. Opens nothing once the log
  /// has failed.
  LogFile(fs::path path, LogHealth& health);
  ~LogFile();
  LogFile(const LogFile&) = delete;
  LogFile& operator=(const LogFile&) = delete;

  /// Writes `text` (whole lines) to the file. Does nothing once the log has failed. On an error
  /// records it, cuts the file back to its last complete line and closes it.
  void append(std::string_view text);
  const fs::path& path() const { return path_; }

 private:
  void fail(int err, std::string_view written);

  fs::path path_;
  LogHealth& health_;
  int fd_ = -1;
  off_t size_ = 0;  ///< bytes known to be in the file
};

/// write(2) until all of `text` is written; returns the bytes written and sets `err` on failure.
std::size_t write_all(int fd, std::string_view text, int& err);
/// "cannot write 'PATH': REASON", one line.
std::string cannot_write(const fs::path& p, int err);

/// Replaces `path` with `text` through `path`.tmp and a rename. On an error records it in
/// `health`, removes the temporary file and returns false. Tried even after the log has failed.
bool write_file_atomically(const fs::path& path, std::string_view text, LogHealth& health);

}  // namespace tern::core
