// tern/msg/mission.hpp: runtime mission edits, topic `mission_edit`.
// The host's mission API (command line, DDS bridge) publishes these; the path planner applies
// them in order and republishes `waypoints` with a higher revision. Fields follow ROSplane's
// AddWaypoint service.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "tern/msg/path.hpp"
#include "tern/time.hpp"

namespace tern::msg {

struct MissionEdit {
  static constexpr std::string_view type_name = "tern/MissionEdit";
  enum Op : std::uint8_t {
    add = 0,          ///< append `waypoint` (set_current: start a new list with it, fly it now)
    clear = 1,        ///< remove every waypoint (the manager then orbits the origin)
    set_current = 2,  ///< fly to waypoint number `index` next
    load_file = 3,    ///< replace the mission with the waypoint file `file` (tern or ROSplane format)
  };
  /// Edits a reader takes between two of its steps: the host publishes one edit per tick and
  /// keeps this many (its output's history), the path planner reads them all (its input's queue).
  static constexpr std::uint32_t kQueue = 64;
  Nanos stamp = 0;
  std::uint32_t id = 0;  ///< increasing edit number, echoed in logs
  std::uint8_t op = add;
  Waypoint waypoint{};
  bool set_current_wp = false;   ///< ROSplane's set_current: this waypoint starts a new list, now
  bool publish_now = true;       ///< ROSplane's publish_now: republish the list immediately
  std::uint32_t index = 0;       ///< for set_current
  std::array<char, 256> file{};  ///< for load_file: NUL-terminated absolute path
  template <class V>
  static constexpr void describe(V& v) {
    v(&MissionEdit::stamp, "stamp", "ns");
    v(&MissionEdit::id, "id", "");
    v(&MissionEdit::op, "op", "enum");
    v(&MissionEdit::waypoint, "waypoint", "");
    v(&MissionEdit::set_current_wp, "set_current", "bool");
    v(&MissionEdit::publish_now, "publish_now", "bool");
    v(&MissionEdit::index, "index", "");
    v(&MissionEdit::file, "file", "");
  }
};

}  // namespace tern::msg
