#include "ros/cdr_columns.hpp"

#include <array>
#include <cstring>
#include <set>

namespace tern::core {

namespace {
constexpr char kHeader[4] = {0x00, 0x01, 0x00, 0x00};  // CDR_LE, options 0
// rosidl gives a message without members this one field (and CDR one byte for it)
constexpr std::string_view kEmptyMessageField = "uint8 structure_needs_at_least_one_member\n";

struct Kind {
  reflect::Scalar scalar;
  std::string_view ros;
};
constexpr std::array<Kind, 11> kKinds = {{{reflect::Scalar::f64, "float64"},
                                          {reflect::Scalar::f32, "float32"},
                                          {reflect::Scalar::i64, "int64"},
                                          {reflect::Scalar::i32, "int32"},
                                          {reflect::Scalar::i16, "int16"},
                                          {reflect::Scalar::i8, "int8"},
                                          {reflect::Scalar::u64, "uint64"},
                                          {reflect::Scalar::u32, "uint32"},
                                          {reflect::Scalar::u16, "uint16"},
                                          {reflect::Scalar::u8, "uint8"},
                                          {reflect::Scalar::boolean, "bool"}}};

std::size_t aligned(std::size_t pos, std::size_t size) { return (pos + size - 1) / size * size; }
}  // namespace

std::string tern_schema_name(std::string_view type_name, std::string_view fallback) {
  std::string_view n = type_name.empty() ? fallback : type_name;
  if (const auto slash = n.rfind('/'); slash != std::string_view::npos) n = n.substr(slash + 1);
  return "tern_msgs/msg/" + std::string(n);
}

std::string_view ros2msg_type(reflect::Scalar kind) {
  for (const auto& k : kKinds)
    if (k.scalar == kind) return k.ros;
  return "uint8";
}

std::optional<reflect::Scalar> scalar_of_ros2msg(std::string_view type) {
  for (const auto& k : kKinds)
    if (k.ros == type) return k.scalar;
  return std::nullopt;
}

std::string ros2msg_field_name(std::string_view column) {
  std::string n;
  for (char ch : column) {
    const bool alnum = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9');
    const char c = alnum ? static_cast<char>(ch >= 'A' && ch <= 'Z' ? ch - 'A' + 'a' : ch) : '_';
    if (c == '_' && (n.empty() || n.back() == '_')) continue;  // no leading or double underscore
    n.push_back(c);
  }
  while (!n.empty() && n.back() == '_') n.pop_back();
  if (n.empty() || (n[0] >= '0' && n[0] <= '9')) n = "f_" + n;
  return n;
}

std::string tern_schema_text(const std::vector<reflect::Column>& columns) {
  if (columns.empty()) return std::string(kEmptyMessageField);
  std::string s;
  std::set<std::string> taken;
  for (const auto& c : columns) {
    std::string name = ros2msg_field_name(c.name);
    for (int k = 2; !taken.insert(name).second; ++k) name = ros2msg_field_name(c.name) + "_" + std::to_string(k);
    s += ros2msg_type(c.kind);
    s += ' ' + name;
    if (!c.unit.empty()) s += "  # " + c.unit;
    s += '\n';
  }
  return s;
}

CdrEncoder::CdrEncoder(const std::vector<reflect::Column>& columns) {
  std::size_t pos = 0;           // in the body, after the header
  if (columns.empty()) pos = 1;  // the one zero byte of a message without members
  for (const auto& c : columns) {
    const std::size_t n = reflect::scalar_size(c.kind);
    pos = aligned(pos, n);
    if (c.kind == reflect::Scalar::boolean)
      bools_.emplace_back(c.offset, sizeof kHeader + pos);
    else if (!runs_.empty() && runs_.back().from + runs_.back().n == c.offset && runs_.back().to + runs_.back().n == sizeof kHeader + pos)
      runs_.back().n += n;  // adjacent in the message and in the encoding: one copy
    else
      runs_.push_back({c.offset, sizeof kHeader + pos, n});
    pos += n;
  }
  size_ = sizeof kHeader + pos;
}

void CdrEncoder::append(const char* msg, std::string& out) const {
  const std::size_t base = out.size();
  out.resize(base + size_, '\0');  // padding and the empty message's byte: zeros
  char* o = out.data() + base;
  std::memcpy(o, kHeader, sizeof kHeader);
  for (const Run& r : runs_) std::memcpy(o + r.to, msg + r.from, r.n);  // little-endian host
  for (const auto& [from, to] : bools_) o[to] = msg[from] ? '\1' : '\0';
}

void encode_cdr(const std::vector<reflect::Column>& columns, const char* msg, std::string& out) { CdrEncoder(columns).append(msg, out); }

bool decode_cdr(const std::vector<reflect::Column>& columns, std::string_view data, char* msg) {
  if (data.size() < sizeof kHeader || data[0] != 0x00 || data[1] != 0x01) return false;
  const std::string_view body = data.substr(sizeof kHeader);
  std::size_t pos = 0;
  for (const auto& c : columns) {
    const std::size_t n = reflect::scalar_size(c.kind);
    pos = aligned(pos, n);
    if (pos + n > body.size()) return false;
    std::memcpy(msg + c.offset, body.data() + pos, n);
    pos += n;
  }
  return true;
}

}  // namespace tern::core
