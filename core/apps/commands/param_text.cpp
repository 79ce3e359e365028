// core/apps/commands/param_text.cpp: a parameter's range and description (param_text.hpp).
#include "commands/param_text.hpp"

#include <fmt/format.h>

namespace tern::core {

std::string description_text(const ParamBase& p) { return p.spec().description + (p.spec().live ? "" : " [start-only]"); }

std::string range_text(const ParamBase& p) {
  const auto& s = p.spec();
  if (p.kind() == ParamKind::text) return s.choices.empty() ? (s.is_path ? "path" : "") : fmt::format("{}", fmt::join(s.choices, "|"));
  if (p.kind() == ParamKind::boolean) return "";
  return fmt::format("[{}, {}]{}", s.min, s.max, s.size ? fmt::format(" x{}", s.size) : "");
}

}  // namespace tern::core
