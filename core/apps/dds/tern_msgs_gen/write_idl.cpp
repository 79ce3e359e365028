// IDL text from the wire model. See write_idl.hpp.
#include "write_idl.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace tern::msgs_gen {

namespace {

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
  return out;
}

std::string member(const WireStruct& s, const WireField& f) {
  std::string type = f.shape == Shape::sequence ? "sequence<" + f.idl_type + ">" : f.idl_type;
  std::string line = fmt::format("      {} {}{};", type, f.name, f.length ? fmt::format("[{}]", f.length) : "");
  if (!f.unit.empty() && f.unit != "ns" && f.unit != "bool" && f.unit != "enum") line += "  // " + f.unit;
  if (f.shape == Shape::time) line += "  // flight time + the bridge's epoch";
  if (f.shape == Shape::derived) line += "  // " + std::string(s.spec.derived.expr);
  return line + "\n";
}

std::string idl_struct(const WireStruct& s) {
  std::string out;
  if (!s.spec.constants.empty()) {
    out += fmt::format("    module {}_Constants {{\n", s.name);
    for (const auto& [name, value] : s.spec.constants) out += fmt::format("      const {} {} = {};\n", s.spec.constants_type, name, value);
    out += "    };\n";
  }
  out += fmt::format("    // {}\n    struct {} {{\n", s.tern_type, s.name);
  for (const auto& f : s.fields) out += member(s, f);
  return out + "    };\n";
}

/// The IDL files the structs' field types come from, in the order of first use.
std::vector<std::string> includes(std::string_view file, const std::vector<WireStruct>& all) {
  std::vector<std::string> out;
  auto add = [&](std::string_view inc) {
    if (std::find(out.begin(), out.end(), inc) == out.end()) out.emplace_back(inc);
  };
  for (const auto& s : all) {
    if (s.spec.file != file) continue;
    for (const auto& f : s.fields) {
      if (f.shape == Shape::header || f.shape == Shape::time) add("std_msgs/msg/Header.idl");  // and Time.idl
      if (f.shape == Shape::sequence) add(s.spec.sequence.include);
    }
  }
  return out;
}

}  // namespace

std::string idl_file(std::string_view file, const std::vector<WireStruct>& all) {
  const std::string guard = "TERN_MSGS_MSG_" + upper(file) + "_IDL_";
  std::string out = fmt::format(
      "// tern_msgs/msg/{}.idl: generated at build time by tern_msgs_gen (core/apps/dds/tern_msgs_gen/) from the\n"
      "// SDK structs' describe() (sdk/include/tern/msg/): edit the struct, not this file. SI units; body FRD, NED.\n"
      "#ifndef {}\n#define {}\n",
      file, guard, guard);
  for (const auto& inc : includes(file, all)) out += fmt::format("#include \"{}\"\n", inc);
  out += "\nmodule tern_msgs {\n  module msg {\n";
  for (const auto& s : all)
    if (s.spec.file == file) out += idl_struct(s);
  return out + fmt::format("  }};\n}};\n\n#endif  // {}\n", guard);
}

}  // namespace tern::msgs_gen
