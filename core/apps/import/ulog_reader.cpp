// core/apps/import/ulog_reader.cpp: the ULog message stream: header, definitions, data section
// (the spec's summary and the error policy: ulog_reader.hpp).
#include "import/ulog_reader.hpp"

#include <algorithm>
#include <cstring>

#include "tern/input_file.hpp"

namespace tern::core::ulog {

namespace {

constexpr std::uint8_t kMagic[7] = {0x55, 0x4c, 0x6f, 0x67, 0x01, 0x12, 0x35};
constexpr std::uint8_t kSync[8] = {0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12};
constexpr std::size_t kFlagBitsSize = 8 + 8 + 3 * 8;

template <class T>
T load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

bool is_definition_type(char t) { return t == 'B' || t == 'F' || t == 'I' || t == 'M' || t == 'P' || t == 'Q'; }
bool is_data_type(char t) { return t == 'A' || t == 'R' || t == 'D' || t == 'L' || t == 'C' || t == 'S' || t == 'O'; }
/// pyulog's test of a header that cannot be a message of a newer spec version.
bool looks_corrupt(char t, std::uint16_t size) { return t == 0 || size == 0 || size > 10000; }

std::string type_text(char t) {
  char buf[16];
  if (t >= 0x20 && t < 0x7f) return std::string("'") + t + "'";
  std::snprintf(buf, sizeof buf, "0x%02x", static_cast<unsigned>(static_cast<std::uint8_t>(t)));
  return buf;
}

}  // namespace

struct Reader::Message {
  char type = 0;
  std::uint16_t size = 0;
  std::uint64_t offset = 0;  ///< of its 3-byte header
  const std::uint8_t* payload = nullptr;
  enum class Status { ok, end, truncated } status = Status::end;
};

Reader::Reader(const std::filesystem::path& file) : path_(file), stream_buffer_(1 << 16), buffer_(65536) {
  std::error_code ec;
  size_ = std::filesystem::file_size(file, ec);
  if (ec) throw UlogError(file.string() + ": cannot read: " + ec.message());
  in_.rdbuf()->pubsetbuf(stream_buffer_.data(), static_cast<std::streamsize>(stream_buffer_.size()));
  in_.open(file, std::ios::binary);
  if (!in_) throw UlogError(file.string() + ": cannot open");
  std::uint8_t header[16];
  if (size_ < 16 || !in_.read(reinterpret_cast<char*>(header), 16))
    fail(0, "file of " + std::to_string(size_) + " bytes is shorter than the 16-byte ULog header");
  if (std::memcmp(header, kMagic, 7) != 0) fail(0, "no ULog magic (\"ULog\" 01 12 35): not a ULog file, or its header is corrupt");
  version_ = header[7];
  start_timestamp_ = load<std::uint64_t>(header + 8);
  pos_ = 16;
  read_definitions();
}

Reader::~Reader() = default;

void Reader::fail(std::uint64_t offset, const std::string& what) const {
  // `what` may quote the file (a key, a format, a type name): one line, control characters escaped
  // (fuzz_ulog_conversion: a parameter key holding a newline), at most kMaxErrorChars
  throw UlogError(path_.string() + ": byte " + std::to_string(offset) + ": " + printable(what, kMaxErrorChars));
}

bool Reader::read_message(Message& m, std::uint64_t limit) {
  m.offset = pos_;
  m.payload = buffer_.data();
  if (pos_ >= limit) {
    m.status = Message::Status::end;
    return false;
  }
  std::uint8_t h[3];
  if (pos_ != stream_pos_) in_.seekg(static_cast<std::streamoff>(pos_));  // seeking drops the stream's buffer: only when needed
  stream_pos_ = ~0ull;                                                    // unknown until this message was read whole
  if (limit - pos_ < 3 || !in_.read(reinterpret_cast<char*>(h), 3)) {
    in_.clear();
    m.status = Message::Status::truncated;
    return false;
  }
  m.size = load<std::uint16_t>(h);
  m.type = static_cast<char>(h[2]);
  if (limit - pos_ - 3 < m.size || !in_.read(reinterpret_cast<char*>(buffer_.data()), m.size)) {
    in_.clear();
    m.status = Message::Status::truncated;
    return false;
  }
  pos_ += 3 + m.size;
  stream_pos_ = pos_;
  m.status = Message::Status::ok;
  return true;
}

void Reader::read_definitions() {
  Message m;
  bool first = true;
  while (read_message(m, size_)) {
    if (is_data_type(m.type)) {
      pos_ = m.offset;  // the data section starts here
      break;
    }
    if (m.type == 'B') {
      if (!first) fail(m.offset, "flag bits message ('B') is not the first message (the spec requires it first)");
      read_flag_bits(m);
    } else if (m.type == 'F') {
      try {
        const Format f = parse_format(std::string_view(reinterpret_cast<const char*>(m.payload), m.size));
        formats_[f.name] = f;
      } catch (const std::invalid_argument& e) {
        fail(m.offset, std::string("format message ('F'): ") + e.what());
      }
    } else if (is_definition_type(m.type)) {
      read_info_like(m, false);
    } else if (looks_corrupt(m.type, m.size)) {
      fail(m.offset, "corrupt message header in the definitions (type " + type_text(m.type) + ", size " + std::to_string(m.size) + ")");
    } else {
      ++unknown_in_definitions_;
    }
    first = false;
  }
  if (m.status == Message::Status::truncated)
    fail(m.offset, "file cut short in the definitions section (" + std::to_string(size_ - m.offset) +
                       " bytes left for a message header and payload)");
  data_start_ = pos_;
}

void Reader::read_flag_bits(const Message& m) {
  if (m.size < kFlagBitsSize) fail(m.offset, "flag bits message ('B') of " + std::to_string(m.size) + " bytes (40 expected)");
  std::copy_n(m.payload, 8, compat_.begin());
  std::copy_n(m.payload + 8, 8, incompat_.begin());
  for (int i = 0; i < 8; ++i) {
    const std::uint8_t unknown = i == 0 ? static_cast<std::uint8_t>(incompat_[0] & ~1u) : incompat_[i];
    if (unknown)
      fail(m.offset, "unknown incompatible flag bits set (incompat_flags[" + std::to_string(i) + "] = " + std::to_string(incompat_[i]) +
                         "): the ULog spec forbids parsing this log");
  }
  for (int i = 0; i < 3; ++i) {
    const auto off = load<std::uint64_t>(m.payload + 16 + 8 * i);
    if (off == 0) continue;
    if ((incompat_[0] & 1u) == 0) continue;  // offsets without the DATA_APPENDED bit: not appended data
    if (off > size_)
      fail(m.offset, "appended-data offset " + std::to_string(off) + " lies beyond the file's " + std::to_string(size_) + " bytes");
    appended_.push_back(off);
  }
}

std::pair<std::string, Value> Reader::read_info_like(const Message& m, bool in_data) {
  std::size_t at = 0;
  bool continued = false;
  int default_types = 0;
  if (m.type == 'M') continued = m.size > 0 && m.payload[at++] != 0;
  if (m.type == 'Q' && m.size > 0) default_types = m.payload[at++];
  if (at >= m.size) fail(m.offset, "message " + type_text(m.type) + " of " + std::to_string(m.size) + " bytes has no key");
  const std::size_t key_len = m.payload[at++];
  if (at + key_len > m.size)
    fail(m.offset, "message " + type_text(m.type) + ": key length " + std::to_string(key_len) + " exceeds the message");
  const std::string key(reinterpret_cast<const char*>(m.payload + at), key_len);
  const auto space = key.find(' ');
  if (space == std::string::npos || space == 0)
    fail(m.offset, "message " + type_text(m.type) + ": key '" + key + "' is not '<type> <name>'");
  Value v{key.substr(0, space), std::string(reinterpret_cast<const char*>(m.payload + at + key_len), m.size - at - key_len)};
  const std::string name = key.substr(space + 1);
  if (m.type == 'I') {
    info_[name] = std::move(v);
  } else if (m.type == 'M') {
    auto& list = info_multiple_[name];
    if (continued && !list.empty())
      list.back().push_back(std::move(v));
    else
      list.push_back({std::move(v)});
  } else if (m.type == 'P') {
    if (!in_data) parameters_[name] = v;
  } else {
    for (int bit = 0; bit < 8; ++bit)
      if (default_types & (1 << bit)) defaults_[bit][name] = v;
  }
  return {name, std::move(v)};
}

UlogDataStats Reader::read_data(const DataHandler& handler) {
  if (data_read_) throw std::logic_error("ulog::Reader::read_data called twice");
  data_read_ = true;
  UlogDataStats stats;
  stats.unknown_types = unknown_in_definitions_;
  pos_ = data_start_;
  for (const std::uint64_t off : appended_) {
    if (off < data_start_) fail(data_start_, "appended-data offset " + std::to_string(off) + " lies inside the definitions section");
    read_data_span(handler, off, stats);
    if (stats.unread_bytes) break;
    pos_ = off;
  }
  if (!stats.unread_bytes) read_data_span(handler, size_, stats);
  stats.last_timestamp = last_timestamp_;
  return stats;
}

void Reader::read_data_span(const DataHandler& h, std::uint64_t limit, UlogDataStats& stats) {
  Message m;
  auto note = [&](std::uint64_t& counter) {
    if (!stats.first_problem_offset) stats.first_problem_offset = m.offset;
    ++counter;
  };
  while (read_message(m, limit)) {
    ++stats.messages;
    const std::string problem = dispatch(h, m);
    if (problem.empty()) continue;
    if (problem == "unknown type") {
      note(stats.unknown_types);
    } else if (problem == "unknown msg_id") {
      note(stats.unknown_msg_id);
    } else if (problem == "wrong size") {
      note(stats.wrong_size);
    } else {
      if (!resync(m.offset + 1, limit)) {  // the data before it kept, as pyulog keeps it
        if (!stats.first_problem_offset) stats.first_problem_offset = m.offset;
        stats.unread_from = m.offset;
        stats.unread_reason = printable(problem, kMaxErrorChars);
        stats.unread_bytes = size_ - m.offset;
        return;
      }
      note(stats.corrupt_regions);
    }
  }
  if (m.status == Message::Status::truncated) note(stats.truncated);
}

std::string Reader::dispatch(const DataHandler& h, const Message& m) {
  switch (m.type) {
    case 'D': return read_data_message(h, m);
    case 'A': return read_subscription(h, m);
    case 'R':
      if (m.size < 2) return "unsubscription ('R') of " + std::to_string(m.size) + " bytes";
      subscriptions_.erase(load<std::uint16_t>(m.payload));
      return "";
    case 'L':
    case 'C': return read_logged_string(h, m);
    case 'O':
      if (m.size < 2) return "dropout ('O') of " + std::to_string(m.size) + " bytes";
      if (h.on_dropout) h.on_dropout(load<std::uint16_t>(m.payload), last_timestamp_);
      return "";
    case 'S':
      if (m.size < 8 || std::memcmp(m.payload, kSync, 8) != 0) return "sync message ('S') without the sync magic";
      return "";
    case 'F': return "format message ('F') in the data section";
    case 'I':
    case 'M':
    case 'Q': read_info_like(m, true); return "";
    case 'P': {
      const auto [name, value] = read_info_like(m, true);
      if (h.on_parameter) h.on_parameter(name, value, last_timestamp_);
      return "";
    }
    case 'B': return "flag bits message ('B') in the data section";
    default:
      if (looks_corrupt(m.type, m.size))
        return "corrupt message header (type " + type_text(m.type) + ", size " + std::to_string(m.size) + ")";
      return "unknown type";
  }
}

std::string Reader::read_subscription(const DataHandler& h, const Message& m) {
  if (m.size < 4) return "subscription ('A') of " + std::to_string(m.size) + " bytes";
  const std::uint8_t multi_id = m.payload[0];
  const auto msg_id = load<std::uint16_t>(m.payload + 1);
  std::string name(reinterpret_cast<const char*>(m.payload + 3), m.size - 3);
  if (!formats_.count(name)) return "subscription ('A') to '" + name.substr(0, 64) + "', which no format message defines";
  try {
    auto sub = std::make_unique<Subscription>(std::move(name), multi_id, msg_id, formats_);
    const Subscription& ref = *sub;
    subscriptions_[msg_id] = std::move(sub);
    if (h.on_subscription) h.on_subscription(ref);
  } catch (const std::invalid_argument& e) {
    fail(m.offset, std::string("subscription ('A'): ") + e.what());
  }
  return "";
}

std::string Reader::read_data_message(const DataHandler& h, const Message& m) {
  if (m.size < 2) return "data message ('D') of " + std::to_string(m.size) + " bytes";
  const auto it = subscriptions_.find(load<std::uint16_t>(m.payload));
  if (it == subscriptions_.end()) return "unknown msg_id";
  const Subscription& sub = *it->second;
  const std::size_t n = m.size - 2u;
  if (n < sub.size() || n > sub.padded_size()) return "wrong size";
  const DataMessage data(sub, m.payload + 2, n);
  last_timestamp_ = std::max(last_timestamp_, data.timestamp());
  if (h.on_data) h.on_data(data);
  return "";
}

std::string Reader::read_logged_string(const DataHandler& h, const Message& m) {
  const std::size_t head = m.type == 'C' ? 11 : 9;
  if (m.size < head) return "logged string (" + type_text(m.type) + ") of " + std::to_string(m.size) + " bytes";
  LoggedString s;
  s.level = m.payload[0];
  if (m.type == 'C') s.tag = load<std::uint16_t>(m.payload + 1);
  s.timestamp = load<std::uint64_t>(m.payload + head - 8);
  s.message.assign(reinterpret_cast<const char*>(m.payload + head), m.size - head);
  if (h.on_logged_string) h.on_logged_string(s);
  return "";
}

bool Reader::resync(std::uint64_t from, std::uint64_t limit) {
  // Scan forward in chunks for the 8 sync bytes (the payload of an 'S' message); resume after them.
  std::vector<char> chunk(1 << 16);
  std::uint64_t at = from;
  while (at + sizeof kSync <= limit) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(chunk.size(), limit - at));
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(at));
    if (!in_.read(chunk.data(), static_cast<std::streamsize>(n))) break;
    const auto hit = std::search(chunk.begin(), chunk.begin() + static_cast<std::ptrdiff_t>(n), std::begin(kSync), std::end(kSync),
                                 [](char a, std::uint8_t b) { return static_cast<std::uint8_t>(a) == b; });
    if (hit != chunk.begin() + static_cast<std::ptrdiff_t>(n)) {
      pos_ = at + static_cast<std::uint64_t>(hit - chunk.begin()) + sizeof kSync;
      stream_pos_ = ~0ull;
      return true;
    }
    if (n < sizeof kSync) break;
    at += n - (sizeof kSync - 1);
  }
  in_.clear();
  stream_pos_ = ~0ull;
  return false;
}

}  // namespace tern::core::ulog
