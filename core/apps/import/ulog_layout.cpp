// core/apps/import/ulog_layout.cpp: ULog formats, their flattened data layouts and value decoding
// (the declarations and the spec's summary: ulog_reader.hpp).
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "import/ulog_reader.hpp"

namespace tern::core::ulog {

namespace {

struct TypeName {
  std::string_view name;
  BaseType type;
};
constexpr TypeName kTypes[] = {{"int8_t", BaseType::int8},     {"uint8_t", BaseType::uint8},   {"int16_t", BaseType::int16},
                               {"uint16_t", BaseType::uint16}, {"int32_t", BaseType::int32},   {"uint32_t", BaseType::uint32},
                               {"int64_t", BaseType::int64},   {"uint64_t", BaseType::uint64}, {"float", BaseType::float32},
                               {"double", BaseType::float64},  {"bool", BaseType::boolean},    {"char", BaseType::character}};

template <class T>
T load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));  // ULog is little endian, as every host tern builds for
  return v;
}

template <class R>
R decode(BaseType type, const std::uint8_t* p) {
  switch (type) {
    case BaseType::int8: return static_cast<R>(load<std::int8_t>(p));
    case BaseType::uint8: return static_cast<R>(load<std::uint8_t>(p));
    case BaseType::int16: return static_cast<R>(load<std::int16_t>(p));
    case BaseType::uint16: return static_cast<R>(load<std::uint16_t>(p));
    case BaseType::int32: return static_cast<R>(load<std::int32_t>(p));
    case BaseType::uint32: return static_cast<R>(load<std::uint32_t>(p));
    case BaseType::int64: return static_cast<R>(load<std::int64_t>(p));
    case BaseType::uint64: return static_cast<R>(load<std::uint64_t>(p));
    case BaseType::float32: return static_cast<R>(load<float>(p));
    case BaseType::float64: return static_cast<R>(load<double>(p));
    case BaseType::boolean: return static_cast<R>(p[0] != 0);
    case BaseType::character: return static_cast<R>(static_cast<std::int8_t>(p[0]));
  }
  return R{};
}

bool is_integer_type(BaseType t) { return t != BaseType::float32 && t != BaseType::float64; }

Format::Member parse_member(std::string_view text) {
  const auto space = text.find(' ');
  if (space == std::string_view::npos || space == 0 || space + 1 == text.size())
    throw std::invalid_argument("field '" + std::string(text) + "' is not '<type> <name>'");
  Format::Member m;
  std::string_view type = text.substr(0, space);
  m.name = std::string(text.substr(space + 1));
  if (const auto open = type.find('['); open != std::string_view::npos) {
    const auto close = type.find(']', open);
    if (close == std::string_view::npos || close != type.size() - 1)
      throw std::invalid_argument("field '" + std::string(text) + "': array type without ']'");
    const auto digits = type.substr(open + 1, close - open - 1);
    auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), m.count);
    if (ec != std::errc() || end != digits.data() + digits.size() || m.count == 0 || m.count > 65535)
      throw std::invalid_argument("field '" + std::string(text) + "': bad array length");
    type = type.substr(0, open);
  }
  m.type = std::string(type);
  return m;
}

}  // namespace

std::optional<BaseType> base_type_from_name(std::string_view name) {
  for (const auto& t : kTypes)
    if (t.name == name) return t.type;
  return std::nullopt;
}

std::size_t base_type_size(BaseType type) {
  switch (type) {
    case BaseType::int16:
    case BaseType::uint16: return 2;
    case BaseType::int32:
    case BaseType::uint32:
    case BaseType::float32: return 4;
    case BaseType::int64:
    case BaseType::uint64:
    case BaseType::float64: return 8;
    default: return 1;
  }
}

Format parse_format(std::string_view text) {
  const auto colon = text.find(':');
  if (colon == std::string_view::npos || colon == 0)
    throw std::invalid_argument("format '" + std::string(text.substr(0, 60)) + "' has no 'name:'");
  Format f;
  f.name = std::string(text.substr(0, colon));
  std::string_view rest = text.substr(colon + 1);
  while (!rest.empty()) {
    const auto semi = rest.find(';');
    const std::string_view item = rest.substr(0, semi);
    if (!item.empty()) f.members.push_back(parse_member(item));
    if (semi == std::string_view::npos) break;
    rest.remove_prefix(semi + 1);
  }
  return f;
}

namespace {
constexpr std::size_t kMaxDataPayload = 65535 - 2;            // a message's uint16 size, less the 'D' message's msg_id
constexpr std::size_t kMaxExpansions = std::size_t{1} << 17;  // a 65533-byte message of 1-byte structs: 2 x 65533
}  // namespace

Subscription::Subscription(std::string topic, std::uint8_t multi, std::uint16_t id, const std::map<std::string, Format>& formats)
    : name(std::move(topic)), multi_id(multi), msg_id(id) {
  flatten("", name, formats, 0);
  for (std::size_t i = 0; i < fields_.size(); ++i) index_.emplace(fields_[i].name, i);
  if (padded_size_ > kMaxDataPayload)
    throw std::invalid_argument("format '" + name + "' is " + std::to_string(padded_size_) + " bytes, more than the " +
                                std::to_string(kMaxDataPayload) + " a data message ('D') carries");
  if (!fields_.empty()) size_ = fields_.back().offset + base_type_size(fields_.back().type);
  if (auto it = index_.find("timestamp"); it != index_.end()) timestamp_ = &fields_[it->second];
}

void Subscription::flatten(const std::string& prefix, const std::string& type, const std::map<std::string, Format>& formats, int depth) {
  const auto it = formats.find(type);
  if (it == formats.end()) throw std::invalid_argument("no format definition of type '" + type + "'");
  if (depth > 16) throw std::invalid_argument("format '" + type + "' nests deeper than 16 levels (recursive?)");
  for (const auto& m : it->second.members) {
    const auto base = base_type_from_name(m.type);
    const bool padding = m.name.rfind("_padding", 0) == 0;
    for (std::size_t i = 0; i < m.count; ++i) {
      // arrays of nested arrays multiply: stop at what one data message can carry (a format of
      // 65535 x 65535 bytes, or of 65535^16 empty structs, would otherwise never finish)
      if (padded_size_ > kMaxDataPayload)
        throw std::invalid_argument("format '" + name + "' is more than " + std::to_string(kMaxDataPayload) +
                                    " bytes, more than a data message ('D') carries (at '" + prefix + m.name + "')");
      if (++expansions_ > kMaxExpansions)
        throw std::invalid_argument("format '" + name + "' expands to more than " + std::to_string(kMaxExpansions) +
                                    " members (nested arrays of empty formats?)");
      std::string leaf = prefix + m.name;
      if (m.count > 1) leaf += "[" + std::to_string(i) + "]";
      if (!base) {
        flatten(leaf + ".", m.type, formats, depth + 1);
      } else {
        if (!padding) fields_.push_back({leaf, *base, padded_size_});
        padded_size_ += base_type_size(*base);
      }
    }
  }
}

const Field* Subscription::field(std::string_view flat_name) const {
  const auto it = index_.find(flat_name);
  return it == index_.end() ? nullptr : &fields_[it->second];
}

double DataMessage::value(const Field& f) const { return decode<double>(f.type, payload_ + f.offset); }

std::int64_t DataMessage::integer(const Field& f) const {
  if (f.type == BaseType::uint64) return static_cast<std::int64_t>(load<std::uint64_t>(payload_ + f.offset));
  if (!is_integer_type(f.type)) {
    // a float where a log's format puts one (any field may be declared float): truncated toward
    // zero, NaN as 0 and beyond int64's range saturated (converting those is undefined behaviour)
    const double v = decode<double>(f.type, payload_ + f.offset);
    if (std::isnan(v)) return 0;
    if (v >= 9223372036854775807.0) return std::numeric_limits<std::int64_t>::max();
    if (v <= -9223372036854775808.0) return std::numeric_limits<std::int64_t>::min();
    return static_cast<std::int64_t>(v);
  }
  return decode<std::int64_t>(f.type, payload_ + f.offset);
}

double DataMessage::value(std::string_view flat_name) const {
  const Field* f = sub_->field(flat_name);
  if (!f) throw std::out_of_range("ulog topic '" + sub_->name + "' has no field '" + std::string(flat_name) + "'");
  return value(*f);
}

std::uint64_t DataMessage::timestamp() const {
  const Field* f = sub_->timestamp();
  if (!f) return 0;
  return f->type == BaseType::uint64 ? load<std::uint64_t>(payload_ + f->offset) : static_cast<std::uint64_t>(integer(*f));
}

double Value::number() const {
  const auto base = base_type_from_name(type);
  if (!base || bytes.size() != base_type_size(*base)) throw std::invalid_argument("ulog value of type '" + type + "' is not a number");
  return decode<double>(*base, reinterpret_cast<const std::uint8_t*>(bytes.data()));
}

std::string Value::text() const {
  if (is_string()) return bytes;
  const auto base = base_type_from_name(type);
  if (!base || bytes.size() != base_type_size(*base)) return "<" + type + ", " + std::to_string(bytes.size()) + " bytes>";
  const auto* p = reinterpret_cast<const std::uint8_t*>(bytes.data());
  if (*base == BaseType::uint64) return std::to_string(load<std::uint64_t>(p));
  if (is_integer_type(*base)) return std::to_string(decode<std::int64_t>(*base, p));
  char buf[32];
  const auto r = *base == BaseType::float32 ? std::to_chars(buf, buf + sizeof buf, load<float>(p))
                                            : std::to_chars(buf, buf + sizeof buf, load<double>(p));
  return std::string(buf, r.ptr);
}

std::string_view LoggedString::level_name() const {
  static constexpr std::string_view kNames[] = {"EMERGENCY", "ALERT", "CRITICAL", "ERROR", "WARNING", "NOTICE", "INFO", "DEBUG"};
  if (level >= '0' && level <= '7') return kNames[level - '0'];
  return "UNKNOWN";
}

std::vector<std::string> UlogDataStats::warnings(const std::string& file) const {
  std::vector<std::string> out;
  const std::string at =
      first_problem_offset ? " (the first problem in the data at byte " + std::to_string(first_problem_offset) + ")" : "";
  auto add = [&](std::uint64_t n, const std::string& what) {
    if (n) out.push_back(file + ": " + std::to_string(n) + " " + what + at);
  };
  add(truncated, "message(s) cut short at the end of the data (a log whose writer stopped): dropped");
  add(unknown_msg_id, "data message(s) of no subscription: skipped");
  add(wrong_size, "data message(s) of the wrong size for their format: skipped");
  add(unknown_types, "message(s) of a type the ULog spec does not define: skipped");
  add(corrupt_regions, "corrupt region(s) skipped to the next sync marker");
  if (unread_bytes)
    out.push_back(file + ": byte " + std::to_string(unread_from) + ": " + unread_reason +
                  ", and no sync marker after it to resume from: the data ends there (the last " + std::to_string(unread_bytes) +
                  " bytes not read)");
  return out;
}

}  // namespace tern::core::ulog
