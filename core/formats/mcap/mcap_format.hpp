// core/formats/mcap/mcap_format.hpp: the byte layout of MCAP files (https://mcap.dev/spec, format
// version 0), shared by the writer (mcap_writer.hpp) and the reader (mcap_reader.hpp).
//
// A file is the magic, records, the magic. A record is an opcode (uint8), the content's length
// (uint64) and the content. Every integer is little-endian; a string is a uint32 length and its
// bytes; a map is a uint32 byte length and its key-value pairs; a record's trailing "bytes" field
// is either the rest of the record (Message) or uint32/uint64 length-prefixed (spec, per record).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace tern::core::mcap {

/// 0x89 "MCAP" '0' "\r\n": the first and last 8 bytes of a file.
inline constexpr char kMagic[8] = {'\x89', 'M', 'C', 'A', 'P', '0', '\r', '\n'};
/// Opcode (1 byte) and content length (8 bytes) before each record's content.
inline constexpr std::size_t kRecordPrefix = 9;
/// bytes: the largest uncompressed chunk the reader unpacks (a chunk declaring more is damaged):
/// twice tern's largest log.chunk_size (1 GiB), room for the chunk's last message.
inline constexpr std::uint64_t kMaxChunkBytes = std::uint64_t{2} << 30;

enum class Op : std::uint8_t {
  header = 0x01,
  footer = 0x02,
  schema = 0x03,
  channel = 0x04,
  message = 0x05,
  chunk = 0x06,
  message_index = 0x07,
  chunk_index = 0x08,
  attachment = 0x09,
  attachment_index = 0x0A,
  statistics = 0x0B,
  metadata = 0x0C,
  metadata_index = 0x0D,
  summary_offset = 0x0E,
  data_end = 0x0F,
};

/// Appends little-endian fields to a byte string (the host is little-endian: x86-64, aarch64).
struct Out {
  std::string& b;
  void u8(std::uint8_t v) { b.push_back(static_cast<char>(v)); }
  void u16(std::uint16_t v) { raw(&v, 2); }
  void u32(std::uint32_t v) { raw(&v, 4); }
  void u64(std::uint64_t v) { raw(&v, 8); }
  void str(std::string_view s) {
    u32(static_cast<std::uint32_t>(s.size()));
    b.append(s);
  }
  void raw(const void* p, std::size_t n) { b.append(static_cast<const char*>(p), n); }
};

/// Reads little-endian fields from a byte range; `ok` turns false (and stays) when a field runs
/// past the end, and the reads then return zeros.
struct In {
  const char* p;
  const char* end;
  bool ok = true;
  bool take(void* out, std::size_t n) {
    if (!ok || static_cast<std::size_t>(end - p) < n) {
      ok = false;
      std::memset(out, 0, n);
      return false;
    }
    std::memcpy(out, p, n);
    p += n;
    return true;
  }
  template <class T>
  T num() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  std::uint8_t u8() { return num<std::uint8_t>(); }
  std::uint16_t u16() { return num<std::uint16_t>(); }
  std::uint32_t u32() { return num<std::uint32_t>(); }
  std::uint64_t u64() { return num<std::uint64_t>(); }
  /// `n` bytes as a view (empty and !ok when there are fewer).
  std::string_view bytes(std::uint64_t n) {
    if (!ok || static_cast<std::uint64_t>(end - p) < n) {
      ok = false;
      return {};
    }
    std::string_view v(p, static_cast<std::size_t>(n));
    p += n;
    return v;
  }
  std::string str() { return std::string(bytes(u32())); }
  std::size_t left() const { return static_cast<std::size_t>(end - p); }
};

/// Begins a record: opcode and a zero length that end_record() overwrites with the content's
/// length; returns where the content starts.
inline std::size_t begin_record(std::string& b, Op op) {
  Out{b}.u8(static_cast<std::uint8_t>(op));
  Out{b}.u64(0);
  return b.size();
}
/// Ends the record begun at `content_start`: writes its length.
inline void end_record(std::string& b, std::size_t content_start) {
  const std::uint64_t n = b.size() - content_start;
  std::memcpy(b.data() + content_start - 8, &n, 8);
}

/// CRC-32 (ISO-HDLC, zlib's) of `data`, continuing from `crc` (0 to start).
std::uint32_t crc32(std::string_view data, std::uint32_t crc = 0);

}  // namespace tern::core::mcap
