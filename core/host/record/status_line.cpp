#include "record/status_line.hpp"

#include <unistd.h>

#include <cstdio>
#include <string>

#include <fmt/format.h>

#include "graph/scheduler.hpp"

namespace tern::core {

namespace {

// The latest message on `topic` if its writer publishes a T, else nullptr.
template <class T>
const T* source(const PortGraph& graph, const char* topic) {
  const OutputBase* w = graph.writer_of<T>(topic);
  return w != nullptr ? static_cast<const T*>(w->data()) : nullptr;
}

}  // namespace

StatusLine::StatusLine(const PortGraph& graph, bool enabled)
    : enabled_(enabled && isatty(STDOUT_FILENO)),
      state_(source<msg::State>(graph, "state")),
      phase_(source<msg::FlightPhase>(graph, "flight_phase")),
      path_(source<msg::CurrentPath>(graph, "current_path")),
      last_draw_(wall_ns()) {}

void StatusLine::draw(Nanos now) {
  if (!enabled_) return;
  const std::int64_t w = wall_ns();
  if (w - last_draw_ <= 250'000'000) return;
  last_draw_ = w;
  std::string line = fmt::format("\r t {:8.2f} s", to_seconds(now));
  if (phase_) line += fmt::format("  {:<8}", msg::phase_name(phase_->phase));
  if (state_) line += fmt::format("  h {:7.1f} m  Va {:5.1f} m/s", -state_->p_d, state_->Va);
  if (path_) line += fmt::format("  wp {:>3}", path_->waypoint_index);
  line += "   ";
  std::fwrite(line.data(), 1, line.size(), stdout);
  std::fflush(stdout);
}

void StatusLine::finish() {
  if (enabled_) std::fputs("\n", stdout);
}

}  // namespace tern::core
