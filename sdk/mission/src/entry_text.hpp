// Where a mission entry is, for the mission reader's and checker's messages.
#pragma once

#include <string>

#include "tern/path/mission.hpp"

namespace tern::path {

/// "source:line: field: " of an entry of `m` (its own source when it has one: a config's items
/// after a file's; the line and field left out when unknown).
inline std::string entry_prefix(const Mission& m, const MissionWaypoint& wp) {
  std::string s = wp.source.empty() ? m.source : wp.source;
  if (wp.line > 0) s.append(":").append(std::to_string(wp.line));
  s.append(": ");
  if (!wp.field.empty()) s.append(wp.field).append(": ");
  return s;
}

}  // namespace tern::path
