// core/host/record/status_line.hpp: the live line `tern fly` keeps on a terminal: flight time (s),
// phase, altitude h = -p_d (m), airspeed Va (m/s), current waypoint index.
//
// It reads the topics `state`, `flight_phase` and `current_path` (those that carry tern's
// message types; a part is left out when its topic is missing) and redraws at most four times a
// second of wall time, on stdout, only when stdout is a terminal.
#pragma once

#include <cstdint>

#include "graph/port_graph.hpp"
#include "tern/msg/all.hpp"

namespace tern::core {

class StatusLine {
 public:
  /// The topics' writers as bound now; `enabled` false (or stdout not a terminal): draws nothing.
  StatusLine(const PortGraph& graph, bool enabled);
  /// Redraws the line for flight time `now`, unless it was drawn less than 250 ms ago.
  void draw(Nanos now);
  /// Ends the line (after the last tick).
  void finish();

 private:
  bool enabled_;
  const msg::State* state_ = nullptr;
  const msg::FlightPhase* phase_ = nullptr;
  const msg::CurrentPath* path_ = nullptr;
  std::int64_t last_draw_;  // wall_ns()
};

}  // namespace tern::core
