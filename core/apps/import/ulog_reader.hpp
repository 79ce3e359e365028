// core/apps/import/ulog_reader.hpp: a streaming reader of PX4 ULog files (.ulg), for `tern import ulog`.
//
// Source: the "ULog File Format" spec of the PX4 user guide (docs.px4.io, dev_log/ulog_file_format);
// pyulog (github.com/PX4/pyulog) was read as a second description only. Little endian throughout.
//
//   header (16 bytes)   magic "ULog" 0x01 0x12 0x35, version (1 byte), start timestamp (uint64, us)
//   definitions         'B' flag bits (first message, if present), 'F' formats, 'I' info, 'M' multi info,
//                       'P' initial parameters, 'Q' default parameters
//   data                'A' subscription (multi_id, msg_id, name), 'R' unsubscription, 'D' data,
//                       'L' logged string, 'C' tagged logged string, 'S' sync, 'O' dropout, and
//                       'I'/'M'/'P'/'Q' again (a 'P' here is a parameter change)
//
// Every message is `uint16 msg_size, uint8 msg_type, msg_size bytes`. The constructor reads the header
// and the definitions; read_data() then streams the data section one message at a time into a
// DataHandler, holding one message (at most 65535 bytes) and the subscriptions' layouts in memory:
// the reader's memory does not grow with the file.
//
// Data messages are decoded on demand: Subscription::field("gyro_rad[1]") looks a flattened field up
// (nested types as "parent.child", arrays as "name[i]", `_padding*` fields skipped), and
// DataMessage::value(field) converts the stored value to double.
//
// Errors (UlogError, one line "<file>: byte <offset>: <what>"): no ULog magic, a file cut short in the
// header or the definitions, unknown incompatible flag bits (the spec: a parser must refuse such a
// log), a format that does not parse, a subscription to an undefined format. Tolerated and counted
// (UlogDataStats): the data section's last message cut short (a log whose writer stopped), data
// messages of an unknown subscription or of the wrong size, unknown message types (the spec: skip
// them), corrupt regions skipped up to the next sync marker; a corrupt message header with no sync
// marker after it ends the data there, what came before it kept (as pyulog keeps it: a log whose
// storage failed mid-flight still gives the flight up to the failure).
// Appended data ('B' incompat bit 0, DATA_APPENDED): the data section is read up to each appended
// offset in turn (a message crossing an offset was cut by the original writer: counted as truncated)
// and continues at that offset.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tern::core::ulog {

/// A ULog file that cannot be read: "<file>: byte <offset>: <what>", one line (what the file says
/// in it is printable(), tern/input_file.hpp).
struct UlogError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// characters: the most of an error's text after the file and offset (it may quote the file).
inline constexpr std::size_t kMaxErrorChars = 1000;

/// The spec's basic types (sizes in bytes: int8/uint8/bool/char 1, int16 2, int32/float 4, int64/double 8).
enum class BaseType : std::uint8_t { int8, uint8, int16, uint16, int32, uint32, int64, uint64, float32, float64, boolean, character };

/// The type named in a format ("float", "uint64_t", ...), or nullopt for a nested (user) type.
std::optional<BaseType> base_type_from_name(std::string_view name);
std::size_t base_type_size(BaseType type);

/// One 'F' message: "name:type0 field0;type1[n] field1;...".
struct Format {
  struct Member {
    std::string type;       ///< a basic type name or another format's name
    std::size_t count = 1;  ///< array length (1: not an array)
    std::string name;
  };
  std::string name;
  std::vector<Member> members;
};

/// One leaf of a flattened data layout.
struct Field {
  std::string name;  ///< "timestamp", "gyro_rad[0]", "parent.child", "items[2].value"
  BaseType type = BaseType::uint8;
  std::size_t offset = 0;  ///< bytes from the start of the message's payload (after msg_id)
};

/// An 'A' message: the data layout of one logged topic instance.
class Subscription {
 public:
  std::string name;           ///< the format (topic) name, e.g. "sensor_combined"
  std::uint8_t multi_id = 0;  ///< instance of the topic
  std::uint16_t msg_id = 0;   ///< the id its 'D' messages carry
  /// The flattened fields, in order, without `_padding*` fields.
  const std::vector<Field>& fields() const { return fields_; }
  /// The field of that flattened name, or nullptr if the format has none.
  const Field* field(std::string_view flat_name) const;
  /// Payload bytes without the trailing padding (the least a data message may carry; pyulog's "message size").
  std::size_t size() const { return size_; }
  /// Payload bytes with the trailing padding (the most a data message may carry).
  std::size_t padded_size() const { return padded_size_; }
  /// The top-level "timestamp" field (uint64 us since boot), or nullptr.
  const Field* timestamp() const { return timestamp_; }

  /// Flattens `name`'s format. Throws std::invalid_argument naming a missing nested format, or a
  /// layout larger than a data message can carry (65533 bytes) or of more than 2^17 members.
  Subscription(std::string name, std::uint8_t multi_id, std::uint16_t msg_id, const std::map<std::string, Format>& formats);

 private:
  void flatten(const std::string& prefix, const std::string& type, const std::map<std::string, Format>& formats, int depth);
  std::vector<Field> fields_;
  std::map<std::string, std::size_t, std::less<>> index_;
  std::size_t size_ = 0;
  std::size_t padded_size_ = 0;
  std::size_t expansions_ = 0;  ///< members flattened so far (bounded: nested arrays multiply)
  const Field* timestamp_ = nullptr;
};

/// A 'D' message, valid during the handler's call only.
class DataMessage {
 public:
  DataMessage(const Subscription& sub, const std::uint8_t* payload, std::size_t size) : sub_(&sub), payload_(payload), size_(size) {}
  const Subscription& subscription() const { return *sub_; }
  /// The field's value converted to double (integers above 2^53 lose precision: use integer()).
  double value(const Field& field) const;
  /// The field's value as a 64-bit integer (floats truncated toward zero, NaN as 0, saturated beyond int64).
  std::int64_t integer(const Field& field) const;
  /// The value of the named field; throws std::out_of_range naming the topic and field if absent.
  double value(std::string_view flat_name) const;
  /// The top-level timestamp, us since boot (0 if the format has none).
  std::uint64_t timestamp() const;

 private:
  const Subscription* sub_;
  const std::uint8_t* payload_;
  std::size_t size_;
};

/// An 'I', 'M', 'P' or 'Q' value: its declared type ("char[5]", "int32_t", "float", ...) and raw bytes.
struct Value {
  std::string type;
  std::string bytes;
  bool is_string() const { return type.rfind("char[", 0) == 0; }
  /// A string value as text; a number as its decimal text.
  std::string text() const;
  /// A scalar number (throws std::invalid_argument for strings and arrays).
  double number() const;
};

/// An 'L' or 'C' message.
struct LoggedString {
  std::uint8_t level = 0;            ///< syslog level as an ASCII digit: '0' emergency .. '3' error, '4' warning, '6' info, '7' debug
  std::optional<std::uint16_t> tag;  ///< 'C' messages only
  std::uint64_t timestamp = 0;       ///< us since boot
  std::string message;
  /// "EMERGENCY", "ALERT", "CRITICAL", "ERROR", "WARNING", "NOTICE", "INFO", "DEBUG" or "UNKNOWN" (pyulog's words).
  std::string_view level_name() const;
};

/// Callbacks of the data section; any may be empty.
struct DataHandler {
  std::function<void(const Subscription&)> on_subscription;
  std::function<void(const DataMessage&)> on_data;
  std::function<void(const LoggedString&)> on_logged_string;
  /// A parameter change, at the last data timestamp seen.
  std::function<void(const std::string& name, const Value&, std::uint64_t timestamp)> on_parameter;
  /// A dropout ('O'): duration in ms, at the last data timestamp seen.
  std::function<void(std::uint16_t duration_ms, std::uint64_t timestamp)> on_dropout;
};

/// What read_data() tolerated, and the log's time span.
struct UlogDataStats {
  std::uint64_t messages = 0;         ///< messages of the data section read
  std::uint64_t truncated = 0;        ///< a message cut short (the end of the file, or an appended offset)
  std::uint64_t unknown_msg_id = 0;   ///< 'D' messages of no current subscription
  std::uint64_t wrong_size = 0;       ///< 'D' messages shorter than their format or longer than its padded size
  std::uint64_t unknown_types = 0;    ///< messages of a type the spec does not define (skipped)
  std::uint64_t corrupt_regions = 0;  ///< corrupt message headers skipped up to the next sync marker
  /// A corrupt message header with no sync marker after it: the data from there to the file's end
  /// is not read (unread_bytes of it, from byte unread_from; unread_reason: the header's problem).
  std::uint64_t unread_from = 0, unread_bytes = 0;
  std::string unread_reason;
  std::uint64_t first_problem_offset = 0;  ///< byte offset of the first of the above (0: none)
  std::uint64_t last_timestamp = 0;        ///< the largest data timestamp, us since boot
  /// One line per kind of problem counted (empty if none).
  std::vector<std::string> warnings(const std::string& file) const;
};

class Reader {
 public:
  /// Opens the file and reads the header and definitions. Throws UlogError.
  explicit Reader(const std::filesystem::path& file);
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::uint8_t version() const { return version_; }
  /// Start of logging, us since boot (the header's timestamp).
  std::uint64_t start_timestamp() const { return start_timestamp_; }
  std::array<std::uint8_t, 8> compat_flags() const { return compat_; }
  std::array<std::uint8_t, 8> incompat_flags() const { return incompat_; }
  /// Non-zero appended-data offsets of the 'B' message.
  const std::vector<std::uint64_t>& appended_offsets() const { return appended_; }

  const std::map<std::string, Format>& formats() const { return formats_; }
  /// 'I' messages by key (definitions, and any read so far in the data section).
  const std::map<std::string, Value>& info() const { return info_; }
  /// 'M' messages by key: a list of values, each a list of continued parts.
  const std::map<std::string, std::vector<std::vector<Value>>>& info_multiple() const { return info_multiple_; }
  /// The parameters' values at the start of the log ('P' in the definitions).
  const std::map<std::string, Value>& initial_parameters() const { return parameters_; }
  /// 'Q' default parameters by default type bit (0: system defaults, 1: current setup's defaults).
  const std::map<int, std::map<std::string, Value>>& default_parameters() const { return defaults_; }

  /// Streams the data section into `handler`, once; throws UlogError on corruption it cannot resync from.
  UlogDataStats read_data(const DataHandler& handler);

 private:
  struct Message;
  bool read_message(Message& m, std::uint64_t limit);
  void read_definitions();
  void read_flag_bits(const Message& m);
  /// 'I', 'M', 'P', 'Q': stores it ('P' only from the definitions), returns (name, value).
  std::pair<std::string, Value> read_info_like(const Message& m, bool in_data);
  void read_data_span(const DataHandler& h, std::uint64_t limit, UlogDataStats& stats);
  /// One data-section message; returns "" or what was wrong ("unknown type", "unknown msg_id",
  /// "wrong size", or a corrupt message's description).
  std::string dispatch(const DataHandler& h, const Message& m);
  std::string read_data_message(const DataHandler& h, const Message& m);
  std::string read_subscription(const DataHandler& h, const Message& m);
  std::string read_logged_string(const DataHandler& h, const Message& m);
  bool resync(std::uint64_t from, std::uint64_t limit);
  [[noreturn]] void fail(std::uint64_t offset, const std::string& what) const;

  std::filesystem::path path_;
  std::vector<char> stream_buffer_;  ///< in_'s read buffer (declared first: it outlives in_)
  std::ifstream in_;
  std::uint64_t size_ = 0;
  std::uint64_t pos_ = 0;         ///< current file offset
  std::uint64_t stream_pos_ = 0;  ///< where in_ stands (~0: unknown)
  std::uint64_t data_start_ = 0;
  std::uint8_t version_ = 0;
  std::uint64_t start_timestamp_ = 0;
  std::array<std::uint8_t, 8> compat_{};
  std::array<std::uint8_t, 8> incompat_{};
  std::vector<std::uint64_t> appended_;
  std::map<std::string, Format> formats_;
  std::map<std::string, Value> info_;
  std::map<std::string, std::vector<std::vector<Value>>> info_multiple_;
  std::map<std::string, Value> parameters_;
  std::map<int, std::map<std::string, Value>> defaults_;
  std::map<std::uint16_t, std::unique_ptr<Subscription>> subscriptions_;
  std::vector<std::uint8_t> buffer_;  ///< one message's payload
  std::uint64_t last_timestamp_ = 0;
  std::uint64_t unknown_in_definitions_ = 0;
  bool data_read_ = false;
};

/// Parses one 'F' payload; throws std::invalid_argument saying what is wrong.
Format parse_format(std::string_view text);

}  // namespace tern::core::ulog
