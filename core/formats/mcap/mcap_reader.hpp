// core/formats/mcap/mcap_reader.hpp: an MCAP file read record by record from its start, as
// `tern export` reads a flight's flight.mcap (whole or cut short by a killed process), one record
// in memory at a time. Checks what a damaged file gets wrong: the magic, a record running past
// the end of the file, a chunk that does not decompress or whose CRC-32 does not match.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>

#include "mcap/mcap_format.hpp"

namespace tern::core {

namespace fs = std::filesystem;

/// A file that is not MCAP, or a damaged record: one line naming the file, offset and field.
struct McapError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct McapRecord {
  mcap::Op op{};
  std::uint64_t offset = 0;  ///< of the opcode in the file
  std::string content;
};

struct McapSchema {
  std::uint16_t id = 0;
  std::string name, encoding, data;
};
struct McapChannel {
  std::uint16_t id = 0, schema = 0;
  std::string topic, message_encoding;
  std::map<std::string, std::string> metadata;
};
struct McapMessage {
  std::uint16_t channel = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0, publish_time = 0;
  std::string_view data;
};
struct McapAttachment {
  std::uint64_t log_time = 0, create_time = 0;
  std::string name, media_type, data;
};
struct McapMetadata {
  std::string name;
  std::map<std::string, std::string> values;
};

class McapReader {
 public:
  /// Opens `path` and checks its magic and header; throws McapError.
  explicit McapReader(fs::path path);
  /// The next record of the data section: false at the data end or footer (a complete file), or
  /// where the file ends in the middle of a record (truncated() then says where).
  bool next(McapRecord& r);
  /// "" for a complete file, else why reading stopped ("truncated at byte N in a chunk record").
  const std::string& truncated() const { return truncated_; }
  const fs::path& path() const { return path_; }

  McapSchema schema(const McapRecord& r) const;
  McapChannel channel(const McapRecord& r) const;
  McapAttachment attachment(const McapRecord& r) const;
  McapMetadata metadata(const McapRecord& r) const;
  /// Every message of a chunk record, decompressed into `buffer`, in the order stored; throws
  /// McapError for a damaged chunk (compression unknown, bad data, CRC-32 mismatch).
  void chunk_messages(const McapRecord& r, std::string& buffer, const std::function<void(const McapMessage&)>& each) const;
  /// A message record (in a chunk or not).
  McapMessage message(std::string_view content, std::uint64_t offset) const;

 private:
  [[noreturn]] void damaged(std::uint64_t offset, const std::string& what) const;
  /// A chunk's zstd frame into `buffer`, exactly `size` bytes (McapError otherwise).
  void unpack_zstd(std::uint64_t offset, std::string_view frame, std::uint64_t size, std::string& buffer) const;
  fs::path path_;
  std::ifstream in_;
  std::uint64_t offset_ = 0;
  std::uint64_t size_ = 0;
  std::string truncated_;
};

}  // namespace tern::core
