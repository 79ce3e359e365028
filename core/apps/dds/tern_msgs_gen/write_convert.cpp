// C++ of the tern_msgs conversions from the wire model. See write_convert.hpp.
#include "write_convert.hpp"

#include <set>
#include <stdexcept>

#include <fmt/format.h>

namespace tern::msgs_gen {

namespace {

constexpr const char* kBanner =
    "// {}: generated at build time by tern_msgs_gen (core/apps/dds/tern_msgs_gen/) from the SDK\n"
    "// structs' describe() (sdk/include/tern/msg/): edit the struct, or tern_msgs_gen, not this file.\n";

/// "MissionItem" -> "mission_item"
std::string snake(const std::string& name) {
  std::string out;
  for (char c : name) {
    if (c >= 'A' && c <= 'Z') {
      if (!out.empty()) out += '_';
      c = static_cast<char>(c - 'A' + 'a');
    }
    out += c;
  }
  return out;
}

std::string wire_type(const WireStruct& s) { return "tern_msgs::msg::" + s.name; }

bool uses_epoch(const WireStruct& s) {
  for (const auto& f : s.fields)
    if (f.shape == Shape::header || f.shape == Shape::time) return true;
  return false;
}

std::string to_signature(const WireStruct& s) {
  return fmt::format("void to_{}(const {}& m, {}& s{})", snake(s.name), s.cpp_type, wire_type(s), uses_epoch(s) ? ", Nanos epoch" : "");
}

std::string from_signature(const WireStruct& s) { return fmt::format("{} from_{}(const {}& s)", s.cpp_type, snake(s.name), wire_type(s)); }

/// The statement putting one field on the wire sample `s` from the message `m`.
std::string to_statement(const WireStruct& s, const WireField& f) {
  switch (f.shape) {
    case Shape::header: return fmt::format("  stamp(s.header(), m.{} + epoch);\n", f.member);
    case Shape::time: return fmt::format("  to_time(s.{}(), m.{} + epoch);\n", f.name, f.member);
    case Shape::array: return fmt::format("  vec<{}>(s.{}(), m.{});\n", f.length, f.name, f.member);
    case Shape::derived: return fmt::format("  s.{}({});\n", f.name, s.spec.derived.expr);
    case Shape::sequence: {
      const auto& q = s.spec.sequence;
      return fmt::format(
          "  s.{0}().resize(std::min<std::size_t>(m.{1}, m.{2}.size()));\n"
          "  for (std::size_t i = 0; i < s.{0}().size(); ++i) {3}(m.{2}[i], s.header(), s.{0}()[i]);\n",
          f.name, q.length, f.member, q.convert);
    }
    case Shape::scalar: break;
  }
  if (!f.cast.empty()) return fmt::format("  s.{}(static_cast<{}>(m.{}));\n", f.name, f.cast, f.member);
  return fmt::format("  s.{}(m.{});\n", f.name, f.member);
}

/// The statement reading one field of the wire sample `s` into the message `m`.
std::string from_statement(const WireStruct& s, const WireField& f) {
  if (f.shape == Shape::array) return fmt::format("  unvec(m.{}, s.{}());\n", f.member, f.name);
  if (f.shape != Shape::scalar) throw std::runtime_error("tern_msgs_gen: " + s.name + "." + f.name + " cannot be read from the wire");
  if (!f.cast.empty()) return fmt::format("  m.{0} = static_cast<decltype(m.{0})>(s.{1}());\n", f.member, f.name);
  return fmt::format("  m.{} = s.{}();\n", f.member, f.name);
}

/// The Text call rendering one field (`tern echo`).
std::string render_statement(const WireStruct& s, const WireField& f) {
  switch (f.shape) {
    case Shape::header: return "  t.header(s.header());\n";
    case Shape::time: return fmt::format("  t.time(\"{0}\", s.{0}());\n", f.name);
    case Shape::sequence:
      return fmt::format("  t(\"{0}\", s.{1}().size());\n  for (std::size_t i = 0; i < s.{1}().size(); ++i) t.line({2}(i, s.{1}()[i]));\n",
                         s.spec.sequence.length, f.name, s.spec.sequence.render);
    default: return fmt::format("  t(\"{0}\", s.{0}());\n", f.name);
  }
}

std::string functions(const WireStruct& s) {
  std::string out = (s.spec.topic ? "static " : "") + to_signature(s) + " {\n";
  for (const auto& f : s.fields) out += to_statement(s, f);
  out += "}\n\n";
  if (s.spec.read) {
    out += from_signature(s) + " {\n  " + s.cpp_type + " m;\n";
    for (const auto& f : s.fields) out += from_statement(s, f);
    out += "  return m;\n}\n\n";
  }
  if (s.spec.topic) {
    out += fmt::format("static std::string render_{}(const {}& s) {{\n  Text t;\n", snake(s.name), wire_type(s));
    for (const auto& f : s.fields) out += render_statement(s, f);
    out += "  return t.str();\n}\n\n";
  }
  return out;
}

std::string add_types(const std::vector<WireStruct>& all) {
  std::string out = "void add_tern_msgs_types(std::vector<TypeEntry>& v) {\n";
  for (const auto& s : all) {
    if (!s.spec.topic) continue;
    if (!uses_epoch(s)) throw std::runtime_error("tern_msgs_gen: topic message " + s.name + " has no stamp");
    out +=
        fmt::format("  v.push_back(entry<{}, {}PubSubType>(to_{}, render_{}));\n", s.cpp_type, wire_type(s), snake(s.name), snake(s.name));
  }
  return out + "}\n";
}

std::set<std::string> files(const std::vector<WireStruct>& all) {
  std::set<std::string> out;
  for (const auto& s : all) out.insert(std::string(s.spec.file));
  return out;
}

}  // namespace

std::string convert_header(const std::vector<WireStruct>& all) {
  std::string out = fmt::format(kBanner, "tern_msgs_convert.hpp") + "#pragma once\n\n#include <vector>\n\n";
  out += "#include \"dds_internal.hpp\"\n#include \"tern/msg/all.hpp\"\n";
  for (const auto& f : files(all)) out += fmt::format("#include \"tern_msgs/msg/{}.h\"\n", f);
  out += "\nnamespace tern::core::ddsi {\n\n";
  for (const auto& s : all) {
    if (s.spec.topic) continue;
    out += fmt::format("/// {} as tern_msgs/msg/{}, field for field, and back.\n", s.tern_type, s.name);
    out += to_signature(s) + ";\n" + (s.spec.read ? from_signature(s) + ";\n" : "");
  }
  out += "/// Appends the conversion of each of tern's own messages (tern_msgs/msg), in the order of their IDL.\n";
  return out + "void add_tern_msgs_types(std::vector<TypeEntry>& v);\n\n}  // namespace tern::core::ddsi\n";
}

std::string convert_source(const std::vector<WireStruct>& all) {
  std::string out = fmt::format(kBanner, "tern_msgs_convert.cpp") + "#include \"tern_msgs_convert.hpp\"\n\n#include <algorithm>\n\n";
  out += "#include \"convert_util.hpp\"\n";
  std::set<std::string> headers;
  for (const auto& s : all)
    if (!s.spec.sequence.header.empty()) headers.insert(std::string(s.spec.sequence.header));
  for (const auto& h : headers) out += fmt::format("#include \"{}\"\n", h);
  for (const auto& f : files(all)) out += fmt::format("#include \"tern_msgs/msg/{}PubSubTypes.h\"\n", f);
  out += "\nnamespace tern::core::ddsi {\n\n";
  for (const auto& s : all) out += functions(s);
  return out + add_types(all) + "\n}  // namespace tern::core::ddsi\n";
}

}  // namespace tern::msgs_gen
