// core/apps/import/dataflash_reader.hpp: a streaming reader of ArduPilot DataFlash logs (.bin), for
// `tern import dataflash`.
//
// Source: ArduPilot's libraries/AP_Logger/LogStructure.h (the format characters, the FMT, FMTU and
// PARM messages) and AP_Logger's README; pymavlink's DFReader.py was read as a second description
// only. Little endian throughout. The log is a sequence of messages, each
//
//   0xA3 0x95 type (uint8)   then length - 3 bytes of fields, as the FMT of `type` describes them
//
// and self-describing: FMT (type 128, 89 bytes: type uint8, length uint8, name char[4], format
// char[16], labels char[64]) defines every other type before its first message (ArduPilot writes
// the FMT of FMT first, and the FMT of a streamed message just before its first message). Format
// characters and their sizes and scales (LogStructure.h; pymavlink divides c C e E by 100 and L by
// 1e7, as here):
//   b int8  B uint8  h int16  H uint16  i int32  I uint32  q int64  Q uint64  f float  d double
//   n char[4]  N char[16]  Z char[64]  a int16[32]  M uint8 (flight mode)
//   c int16 * 100   C uint16 * 100   e int32 * 100   E uint32 * 100   L int32 deg * 1e7
// Message::value() returns the scaled value (a c field of 1234 is 12.34).
//
// Errors (DataflashError, one line "<file>: byte <offset>: <what>"): a file that is not regular or
// cannot be opened, one with no message at all, a FMT whose length does not match its format, whose
// format has an unknown character, whose labels do not match its format, or that redefines a type
// another way. Tolerated and counted (DataflashStats), as ArduPilot's own readers do: bytes that are
// no message header (skipped up to the next 0xA3 0x95), messages of a type no FMT defined (skipped
// the same way), the last message cut short. The reader holds one message (at most 255 bytes) and
// the 256 formats: its memory does not grow with the file.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace tern::core::dataflash {

/// A DataFlash file that cannot be read: "<file>: byte <offset>: <what>", one line.
struct DataflashError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

inline constexpr std::uint8_t kHead1 = 0xA3, kHead2 = 0x95;
inline constexpr std::uint8_t kFmtType = 128;   ///< FMT's own type id
inline constexpr std::uint8_t kFmtLength = 89;  ///< FMT's length: 3 + 1 + 1 + 4 + 16 + 64
inline constexpr std::size_t kHeaderSize = 3;

/// Bytes of one format character's field (0: not a format character).
std::size_t field_size(char format_char);
/// The factor a format character's raw value is multiplied by (c C e E: 0.01, L: 1e-7, else 1).
double field_scale(char format_char);

struct Field {
  std::string name;        ///< the label ("TimeUS", "GyrX")
  char type = 0;           ///< the format character
  std::size_t offset = 0;  ///< bytes from the start of the message (after the 3-byte header)
};

/// One FMT: a message type's layout.
struct Format {
  std::uint8_t type = 0;
  std::uint8_t length = 0;  ///< bytes with the 3-byte header
  std::string name;         ///< "IMU", "GPS", ...
  std::string format;       ///< "QBffffffIIfBBHH"
  std::vector<Field> fields;
  /// The field labelled `label`, or nullptr.
  const Field* field(std::string_view label) const;
};

/// Parses a FMT message's 86 bytes after the header. Throws std::invalid_argument saying what is
/// wrong (a length that is not 3 + the format's bytes, an unknown format character, labels that
/// are not one per format character).
Format parse_fmt(const std::uint8_t* body);

/// One message, valid during the handler's call only.
class Message {
 public:
  Message(const Format& f, const std::uint8_t* body, std::uint64_t offset) : format_(&f), body_(body), offset_(offset) {}
  const Format& format() const { return *format_; }
  /// Byte offset of its header in the file.
  std::uint64_t offset() const { return offset_; }
  /// The field's value, scaled by its format character (strings and arrays: NaN).
  double value(const Field& f) const;
  /// An integer field's raw value (a float truncated toward zero, NaN as 0, saturated beyond int64).
  std::int64_t integer(const Field& f) const;
  /// A string field (n N Z), without its trailing NULs.
  std::string text(const Field& f) const;
  /// The TimeUS field (us since boot), if the format has one.
  std::optional<std::uint64_t> time_us() const;

 private:
  const Format* format_;
  const std::uint8_t* body_;
  std::uint64_t offset_;
};

/// What read() tolerated.
struct DataflashStats {
  std::uint64_t messages = 0;              ///< messages read (FMT included)
  std::uint64_t skipped_bytes = 0;         ///< bytes that were no message header, skipped to the next 0xA3 0x95
  std::uint64_t skipped_regions = 0;       ///< runs of such bytes
  std::uint64_t unknown_types = 0;         ///< headers of a type no FMT defined (skipped the same way)
  std::uint64_t truncated = 0;             ///< the last message cut short by the end of the file
  std::uint64_t first_problem_offset = 0;  ///< of the first of the above (0: none)
  /// One line per kind of problem counted (empty if none).
  std::vector<std::string> warnings(const std::string& file) const;
};

class Reader {
 public:
  /// Opens the file. Throws DataflashError (not a regular file, cannot be opened).
  explicit Reader(const std::filesystem::path& file);
  const std::filesystem::path& path() const { return path_; }
  std::uint64_t size() const { return size_; }
  /// Streams every message (FMT included, after it was parsed) into `handler`. Callable once per
  /// Reader. Throws DataflashError for a bad FMT, or a file without one message.
  DataflashStats read(const std::function<void(const Message&)>& handler);
  /// The formats defined so far, by type (nullopt: none).
  const std::array<std::optional<Format>, 256>& formats() const { return formats_; }

 private:
  [[noreturn]] void fail(std::uint64_t offset, const std::string& what) const;
  std::filesystem::path path_;
  std::vector<char> stream_buffer_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
  std::array<std::optional<Format>, 256> formats_;
  bool read_ = false;
};

}  // namespace tern::core::dataflash
