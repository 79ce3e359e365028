// tern.Host's mission edits: ROSplane's mission services (add_waypoint, clear_waypoints,
// load_mission_from_file, as the DDS bridge offers them) queued on the host, which publishes each
// on `mission_edit` at the start of the next tick for the path planner (Host::edit_mission).
#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "config/error.hpp"
#include "python/python_host.hpp"

namespace tern::core::python {

namespace {
msg::MissionEdit edit_of(std::uint8_t op, std::uint32_t id) {
  msg::MissionEdit e;
  e.op = op;
  e.id = id;
  return e;
}
}  // namespace

std::uint32_t PythonHost::add_waypoint(const std::array<double, 3>& w, double Va_d, double chi_d, bool use_chi, bool lla,
                                       bool set_current) {
  if (!std::all_of(w.begin(), w.end(), [](double x) { return std::isfinite(x); }) || !std::isfinite(chi_d) || !std::isfinite(Va_d) ||
      Va_d <= 0.0)
    throw ConfigError(
        fmt::format("Host.add_waypoint: w [{}, {}, {}], chi_d {} must be finite and Va_d {} > 0", w[0], w[1], w[2], chi_d, Va_d));
  msg::MissionEdit e = edit_of(msg::MissionEdit::add, edits_ + 1);
  for (int i = 0; i < 3; ++i) e.waypoint.w[i] = w[static_cast<std::size_t>(i)];
  e.waypoint.lla = lla;
  e.waypoint.chi_d = chi_d;
  e.waypoint.use_chi = use_chi;
  e.waypoint.Va_d = Va_d;
  e.set_current_wp = set_current;
  host_->edit_mission(e);
  return ++edits_;
}

std::uint32_t PythonHost::clear_waypoints() {
  host_->edit_mission(edit_of(msg::MissionEdit::clear, edits_ + 1));
  return ++edits_;
}

std::uint32_t PythonHost::load_mission(const std::string& file) {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::absolute(file, ec);
  if (ec || !std::filesystem::is_regular_file(p)) throw ConfigError(fmt::format("Host.load_mission: no such file: {}", file));
  msg::MissionEdit e = edit_of(msg::MissionEdit::load_file, edits_ + 1);
  const std::string path = p.string();  // (string() makes a new string at each call)
  if (path.size() >= e.file.size())
    throw ConfigError(fmt::format("Host.load_mission: the path is longer than {} characters: {}", e.file.size() - 1, path));
  std::copy(path.begin(), path.end(), e.file.begin());
  host_->edit_mission(e);
  return ++edits_;
}

}  // namespace tern::core::python
