// core/apps/import/dataflash_reader.cpp: the DataFlash message stream (the format's summary and the
// error policy: dataflash_reader.hpp).
#include "import/dataflash_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <fmt/format.h>

#include "tern/input_file.hpp"

namespace tern::core::dataflash {

namespace {

constexpr std::size_t kMaxErrorChars = 200;

template <class T>
T load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));  // DataFlash is little endian, as every host tern builds for
  return v;
}

/// A fixed-size char field up to its first NUL.
std::string fixed_text(const std::uint8_t* p, std::size_t n) {
  const auto* c = reinterpret_cast<const char*>(p);
  return std::string(c, static_cast<std::size_t>(std::find(c, c + n, '\0') - c));
}

}  // namespace

std::size_t field_size(char c) {
  switch (c) {
    case 'b':
    case 'B':
    case 'M': return 1;
    case 'h':
    case 'H':
    case 'c':
    case 'C': return 2;
    case 'i':
    case 'I':
    case 'e':
    case 'E':
    case 'L':
    case 'f':
    case 'n': return 4;
    case 'q':
    case 'Q':
    case 'd': return 8;
    case 'N': return 16;
    case 'Z':
    case 'a': return 64;
    default: return 0;
  }
}

double field_scale(char c) {
  switch (c) {
    case 'c':
    case 'C':
    case 'e':
    case 'E': return 0.01;
    case 'L': return 1e-7;
    default: return 1.0;
  }
}

const Field* Format::field(std::string_view label) const {
  for (const auto& f : fields)
    if (f.name == label) return &f;
  return nullptr;
}

Format parse_fmt(const std::uint8_t* body) {
  Format f;
  f.type = body[0];
  f.length = body[1];
  f.name = fixed_text(body + 2, 4);
  f.format = fixed_text(body + 6, 16);
  const std::string labels = fixed_text(body + 22, 64);
  const std::string what = fmt::format("FMT of type {} '{}'", f.type, printable(f.name, 8));
  std::vector<std::string> names;
  for (std::size_t at = 0; at <= labels.size();) {
    const std::size_t comma = std::min(labels.find(',', at), labels.size());
    names.push_back(labels.substr(at, comma - at));
    at = comma + 1;
  }
  if (labels.empty()) names.clear();
  if (names.size() != f.format.size())
    throw std::invalid_argument(fmt::format("{}: field 'labels': {} labels for the {} fields of format '{}'", what, names.size(),
                                            f.format.size(), printable(f.format, 16)));
  std::size_t offset = 0;
  for (std::size_t i = 0; i < f.format.size(); ++i) {
    const char c = f.format[i];
    const std::size_t n = field_size(c);
    if (n == 0)
      throw std::invalid_argument(fmt::format("{}: field 'format': unknown format character '{}' in '{}'", what,
                                              printable(std::string(1, c), 4), printable(f.format, 16)));
    f.fields.push_back({names[i], c, offset});
    offset += n;
  }
  if (f.length != kHeaderSize + offset)
    throw std::invalid_argument(fmt::format("{}: field 'length': {} bytes, but format '{}' makes {} (3 + {})", what, f.length,
                                            printable(f.format, 16), kHeaderSize + offset, offset));
  return f;
}

namespace {
/// A numeric field's stored value, unscaled (strings and arrays: NaN).
double raw_value(const std::uint8_t* p, char type) {
  switch (type) {
    case 'b': return load<std::int8_t>(p);
    case 'B':
    case 'M': return load<std::uint8_t>(p);
    case 'h':
    case 'c': return load<std::int16_t>(p);
    case 'H':
    case 'C': return load<std::uint16_t>(p);
    case 'i':
    case 'e':
    case 'L': return load<std::int32_t>(p);
    case 'I':
    case 'E': return load<std::uint32_t>(p);
    case 'q': return static_cast<double>(load<std::int64_t>(p));
    case 'Q': return static_cast<double>(load<std::uint64_t>(p));
    case 'f': return load<float>(p);
    case 'd': return load<double>(p);
    default: return std::numeric_limits<double>::quiet_NaN();
  }
}
}  // namespace

double Message::value(const Field& f) const { return raw_value(body_ + f.offset, f.type) * field_scale(f.type); }

std::int64_t Message::integer(const Field& f) const {
  const std::uint8_t* p = body_ + f.offset;
  if (f.type == 'q') return load<std::int64_t>(p);
  if (f.type == 'Q')
    return static_cast<std::int64_t>(std::min<std::uint64_t>(load<std::uint64_t>(p), std::numeric_limits<std::int64_t>::max()));
  const double v = raw_value(p, f.type);  // every other integer is exact in a double
  if (std::isnan(v)) return 0;
  if (v >= 9.2e18) return std::numeric_limits<std::int64_t>::max();
  if (v <= -9.2e18) return std::numeric_limits<std::int64_t>::min();
  return static_cast<std::int64_t>(v);
}

std::string Message::text(const Field& f) const {
  const std::size_t n = field_size(f.type);
  if (f.type != 'n' && f.type != 'N' && f.type != 'Z') return {};
  return fixed_text(body_ + f.offset, n);
}

std::optional<std::uint64_t> Message::time_us() const {
  const Field* t = format_->field("TimeUS");
  if (!t || (t->type != 'Q' && t->type != 'q')) return std::nullopt;
  const std::int64_t v = t->type == 'q' ? load<std::int64_t>(body_ + t->offset) : 0;
  if (t->type == 'q' && v < 0) return std::nullopt;  // no time since boot
  return t->type == 'q' ? static_cast<std::uint64_t>(v) : load<std::uint64_t>(body_ + t->offset);
}

std::vector<std::string> DataflashStats::warnings(const std::string& file) const {
  std::vector<std::string> out;
  if (skipped_regions)
    out.push_back(
        fmt::format("{}: {} byte(s) in {} place(s) that are no message (first at byte {}): skipped to the next 0xA3 0x95 header, "
                    "as ArduPilot's readers do",
                    file, skipped_bytes, skipped_regions, first_problem_offset));
  if (unknown_types)
    out.push_back(
        fmt::format("{}: {} message header(s) of a type no FMT defines: skipped to the next 0xA3 0x95 header", file, unknown_types));
  if (truncated) out.push_back(fmt::format("{}: the last message is cut short (a log whose writer stopped): dropped", file));
  return out;
}

Reader::Reader(const std::filesystem::path& file) : path_(file), stream_buffer_(1 << 16) {
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(status)) throw DataflashError(file.string() + ": no such file");
  if (!std::filesystem::is_regular_file(status)) throw DataflashError(file.string() + ": not a regular file: nothing is read from it");
  size_ = std::filesystem::file_size(file, ec);
  if (ec) throw DataflashError(file.string() + ": cannot read: " + ec.message());
  in_.rdbuf()->pubsetbuf(stream_buffer_.data(), static_cast<std::streamsize>(stream_buffer_.size()));
  in_.open(file, std::ios::binary);
  if (!in_) throw DataflashError(file.string() + ": cannot open");
}

void Reader::fail(std::uint64_t offset, const std::string& what) const {
  throw DataflashError(path_.string() + ": byte " + std::to_string(offset) + ": " + printable(what, kMaxErrorChars));
}

DataflashStats Reader::read(const std::function<void(const Message&)>& handler) {
  if (read_) throw std::logic_error("dataflash::Reader::read called twice");
  read_ = true;
  DataflashStats stats;
  // a sliding window over the file: buf_[begin, end) holds the bytes from file offset `pos`
  std::vector<std::uint8_t> buf(1 << 16);
  std::size_t begin = 0, end = 0;
  std::uint64_t pos = 0;
  bool eof = false;
  auto ensure = [&](std::size_t n) {  // at least n bytes in the window, unless the file ends first
    if (end - begin >= n) return true;
    if (eof) return false;
    std::memmove(buf.data(), buf.data() + begin, end - begin);
    end -= begin, begin = 0;
    while (end < n && !eof) {
      in_.read(reinterpret_cast<char*>(buf.data() + end), static_cast<std::streamsize>(buf.size() - end));
      const auto got = static_cast<std::size_t>(in_.gcount());
      end += got;
      if (got == 0 || !in_) eof = true;
    }
    return end - begin >= n;
  };
  auto advance = [&](std::size_t n) { begin += n, pos += n; };
  bool in_garbage = false;
  auto note = [&](std::uint64_t& counter) {
    if (!stats.first_problem_offset) stats.first_problem_offset = pos;
    ++counter;
  };
  // skips to the next 0xA3 0x95 (or the end), counting the bytes skipped
  auto skip_to_header = [&] {
    while (ensure(2)) {
      const std::uint8_t* p = buf.data() + begin;
      const std::size_t n = end - begin;
      std::size_t i = 0;
      while (i + 1 < n && !(p[i] == kHead1 && p[i + 1] == kHead2)) ++i;
      stats.skipped_bytes += i;
      advance(i);
      if (i + 1 < n) return;  // found
    }
    if (end - begin > 0 && !(buf[begin] == kHead1)) {  // one last byte that is no header
      stats.skipped_bytes += end - begin;
      advance(end - begin);
    }
  };
  while (ensure(kHeaderSize)) {
    const std::uint8_t* h = buf.data() + begin;
    if (h[0] != kHead1 || h[1] != kHead2) {
      if (!in_garbage) note(stats.skipped_regions);
      in_garbage = true;
      skip_to_header();
      continue;
    }
    const std::uint8_t type = h[2];
    const std::size_t length = type == kFmtType ? kFmtLength : formats_[type] ? formats_[type]->length : 0;
    if (length == 0) {  // no FMT defines it: skip its header, then to the next header
      note(stats.unknown_types);
      advance(kHeaderSize);
      in_garbage = true;  // the bytes up to the next header belong to it: not a region of their own
      skip_to_header();
      continue;
    }
    in_garbage = false;
    if (!ensure(length)) {
      note(stats.truncated);
      advance(end - begin);
      break;
    }
    const std::uint8_t* body = buf.data() + begin + kHeaderSize;
    if (type == kFmtType) {
      Format f;
      try {
        f = parse_fmt(body);
      } catch (const std::invalid_argument& e) {
        fail(pos, e.what());
      }
      if (f.type == kFmtType && (f.length != kFmtLength || f.format != "BBnNZ"))
        fail(pos, fmt::format("FMT of type 128 (FMT itself): field 'format': '{}' of {} bytes, not 'BBnNZ' of 89", printable(f.format, 16),
                              f.length));
      auto& slot = formats_[f.type];
      if (slot && (slot->length != f.length || slot->format != f.format || slot->name != f.name))
        fail(pos, fmt::format("FMT of type {} '{}': field 'format': redefines type {} ('{}', '{}' of {} bytes) as '{}' of {} bytes", f.type,
                              printable(f.name, 8), f.type, printable(slot->name, 8), printable(slot->format, 16), slot->length,
                              printable(f.format, 16), f.length));
      if (!slot) slot = std::move(f);  // the same FMT again: the first stays (its fields are referred to)
    }
    ++stats.messages;
    // a log that never defines FMT itself: the built-in layout stands for it (every other type has one)
    static const Format kFmtOfFmt = [] {
      Format ff;
      ff.type = kFmtType, ff.length = kFmtLength, ff.name = "FMT", ff.format = "BBnNZ";
      ff.fields = {{"Type", 'B', 0}, {"Length", 'B', 1}, {"Name", 'n', 2}, {"Format", 'N', 6}, {"Columns", 'Z', 22}};
      return ff;
    }();
    handler(Message(formats_[type] ? *formats_[type] : kFmtOfFmt, body, pos));
    advance(length);
  }
  if (end - begin > 0) {  // fewer than 3 bytes left
    if (buf[begin] == kHead1) {
      note(stats.truncated);
    } else {
      if (!in_garbage) note(stats.skipped_regions);
      stats.skipped_bytes += end - begin;
    }
  }
  if (stats.messages == 0)
    fail(0, fmt::format("no DataFlash message (a 0xA3 0x95 header and a FMT) in its {} bytes: not an ArduPilot .bin log", size_));
  return stats;
}

}  // namespace tern::core::dataflash
