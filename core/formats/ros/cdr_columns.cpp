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

void encode_cdr(const std::vector<reflect::Column>& columns, const char* msg, std::string& out) {
  out.append(kHeader, sizeof kHeader);
  const std::size_t base = out.size();
  if (columns.empty()) out.push_back('\0');
  for (const auto& c : columns) {
    const std::size_t n = reflect::scalar_size(c.kind);
    out.resize(base + aligned(out.size() - base, n), '\0');
    if (c.kind == reflect::Scalar::boolean)
      out.push_back(msg[c.offset] ? '\1' : '\0');
    else
      out.append(msg + c.offset, n);  // little-endian host
  }
}

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
