// core/formats/mcap/mcap_writer.hpp: one MCAP file (https://mcap.dev/spec) written as a flight goes:
// schemas and channels as they are declared, messages into one open chunk, the chunk compressed
// (zstd) and written with its message indexes when it reaches the chunk size, then at finish()
// the data end, the summary (schemas, channels, statistics, chunk, attachment and metadata
// indexes), its offsets and the footer.
//
// Durability without losing determinism: sync() (the flight log calls it at least every
// FlightLog::kFlushPeriodNs of wall time) writes the open chunk as it stands, with its indexes,
// where the chunk will go, uncompressed (compression "", as the spec allows: it is overwritten
// soon; compressing it at every sync cost the default flight 0.06 of its 2.19 s); the next sync()
// or the full chunk, compressed, overwrites it (pwrite, then the file cut to its new end). So the
// file on disk always ends with complete chunks, and the finished file's chunk boundaries depend
// on the messages only (chunk size), never on the wall clock: the same config and seed give the
// same bytes.
//
// Memory is bounded: one open chunk (about the chunk size) and two copies of it; the summary
// keeps a few dozen bytes per chunk. Every byte written reached the kernel with write(2), so a
// killed process leaves a file that `tern export recover` reads up to its last complete chunk.
// A write error is recorded once in the log's LogHealth, the file is cut back to its last
// complete record (the provisional chunk a failed write overwrote is put back) and nothing more
// is written (log_file.hpp). No wall-clock time is written:
// log and publish times are the flight's, attachments' create_time is 0.
// Thread-safe: declarations and attachments come from the flight thread, messages from the
// log's writer thread.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "files/log_file.hpp"

namespace tern::core {

class McapWriter {
 public:
  struct Options {
    std::size_t chunk_bytes = 1024 * 1024;  ///< uncompressed records per chunk (about)
    /// zstd level (log.zstd_level). The default mission's full log (716 s) at levels -5, 1, 3, 6, 9:
    /// 97.9, 92.0, 92.1, 91.0, 91.1 MB, writer CPU 0.37, 0.51, 1.00, 1.57, 2.41 s: doubles hardly
    /// compress further, level 1 halves level 3's CPU. Pinned to one core, without the ROS-typed
    /// copies: levels 1, -2, -5 give 90.8, 94.8, 96.6 MB at writer CPU 0.36, 0.27, 0.25 s.
    int zstd_level = 1;
  };
  using Metadata = std::map<std::string, std::string>;

  /// Creates (truncates) `path` and writes the magic and the header (profile "ros2"); a failure
  /// is recorded in `health`.
  McapWriter(fs::path path, LogHealth& health, Options options);
  ~McapWriter();  ///< finish()
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// A schema record (ids from 1); written at once, before any message that needs it.
  std::uint16_t add_schema(std::string_view name, std::string_view encoding, std::string_view data);
  /// A channel record (ids from 1).
  std::uint16_t add_channel(std::uint16_t schema, std::string_view topic, std::string_view message_encoding, const Metadata& metadata);
  /// A message into the open chunk (sequence: the channel's count, publish_time = log_time, ns).
  void message(std::uint16_t channel, std::uint64_t log_time, std::string_view data);
  /// Many messages under one lock (the flight log's writer thread hands them over by the
  /// thousand): message() without taking the lock each time. Declare nothing while one lives.
  class Batch {
   public:
    explicit Batch(McapWriter& w) : w_(w), lock_(w.mu_) {}
    void message(std::uint16_t channel, std::uint64_t log_time, std::string_view data) { w_.message_locked(channel, log_time, data); }

   private:
    McapWriter& w_;
    std::lock_guard<std::mutex> lock_;
  };
  /// Writes the open chunk as it stands (above), to be overwritten by its next state.
  void sync();
  void metadata(std::string_view name, const Metadata& values);
  void attachment(std::string_view name, std::string_view media_type, std::string_view data, std::uint64_t log_time);
  /// Writes the open chunk, the data end, the summary and the footer; closes the file. Idempotent.
  void finish();
  const fs::path& path() const { return path_; }

 private:
  struct OpenChunk {
    std::string records;
    std::vector<std::vector<std::pair<std::uint64_t, std::uint64_t>>> index;  // by channel id: (log_time, offset)
    std::uint64_t start = UINT64_MAX, end = 0;
  };
  void message_locked(std::uint16_t channel, std::uint64_t log_time, std::string_view data);
  /// Writes `bytes` at size_ (over a provisional chunk) and cuts the file after them.
  void write(const std::string& bytes);
  void restore_provisional();
  /// The open chunk and its message indexes, serialised; `chunk_length` = the chunk record's.
  /// `compress`: zstd (a complete chunk), else stored as it is (a provisional one).
  std::string chunk_records(std::uint64_t& chunk_length, std::map<std::uint16_t, std::uint64_t>& index_offsets, bool compress);
  /// Writes the open chunk for good and starts a new one.
  void write_chunk_locked();
  std::string chunk_index_record(std::uint64_t compressed_size, std::uint64_t chunk_start, std::uint64_t chunk_length,
                                 const std::map<std::uint16_t, std::uint64_t>& index_offsets, std::uint64_t index_length) const;
  void write_summary_locked();

  fs::path path_;
  LogHealth& health_;
  Options options_;
  std::mutex mu_;
  int fd_ = -1;
  std::uint64_t size_ = 0;   // bytes in the file for good (a provisional chunk follows)
  std::string provisional_;  // the provisional chunk at size_, as written (restored if a write fails)
  bool synced_ = true;       // the provisional chunk holds the whole open chunk
  OpenChunk chunk_;
  void* zstd_ = nullptr;    // ZSTD_CCtx, reused
  std::string compressed_;  // the last complete chunk's zstd frame: its first compressed_size_ bytes (the rest spare)
  std::size_t compressed_size_ = 0;
  // the summary's groups, serialised as they are learnt
  std::string schemas_, channels_, chunk_indexes_, attachment_indexes_, metadata_indexes_;
  std::vector<std::uint32_t> sequence_;        // per channel id
  std::vector<std::uint64_t> channel_counts_;  // per channel id
  std::uint64_t messages_ = 0, start_ = UINT64_MAX, end_ = 0;
  std::uint32_t schema_count_ = 0, chunk_count_ = 0, attachment_count_ = 0, metadata_count_ = 0;
  bool finished_ = false;
};

}  // namespace tern::core
