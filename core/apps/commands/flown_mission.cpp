// core/apps/commands/flown_mission.cpp: a run's last waypoint list from its log (flown_mission.hpp).
#include "commands/flown_mission.hpp"

#include <cmath>
#include <system_error>
#include <unistd.h>

#include <fmt/format.h>

#include "config/error.hpp"
#include "export/mcap_csv_export.hpp"
#include "graph/message_columns.hpp"
#include "replay/replay_csv.hpp"
#include "tern/reflect.hpp"

namespace tern::core {
namespace {

namespace fs = std::filesystem;

/// A scratch directory removed when it goes out of scope.
struct Scratch {
  fs::path path;
  Scratch() : path(fs::temp_directory_path() / fmt::format("tern-flown-{}", ::getpid())) {}
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

/// Row `row` of `items` as a tern/Waypoint: every field by its log column (w_0, lla, chi_d, ...).
msg::Waypoint waypoint_at(const CsvTable& items, std::size_t row) {
  msg::Waypoint w;
  for (const reflect::Column& c : reflect::layout<msg::Waypoint>()) {
    const double v = items.at(c.name)[row];
    const bool real = c.kind == reflect::Scalar::f64 || c.kind == reflect::Scalar::f32;  // NaN kept (the log's own value)
    if (const std::string problem = real ? "" : column_problem(c, v); !problem.empty())
      throw ConfigError(fmt::format("{}: row {}: {}", items.file.string(), row + 2, problem));
    set_column_value(c, &w, v);
  }
  return w;
}

/// Cell `row` of column `name` of `t`, a whole number in [0, max]; else one line naming the file.
double whole(const CsvTable& t, const std::string& name, std::size_t row, double max) {
  const double v = t.at(name)[row];
  if (!(v >= 0 && v <= max && std::floor(v) == v))
    throw ConfigError(fmt::format("{}: row {}: {} {}: expected a whole number 0 .. {}", t.file.string(), row + 2, name, v, max));
  return v;
}

/// The list of the last row of `lists`, its items from `items` (the rows of its revision).
msg::WaypointList list_of(const CsvTable& lists, const CsvTable& items) {
  const std::size_t last = lists.rows - 1;
  constexpr double kMaxStamp = 9.2e18, kMaxU32 = 4294967295.0;
  msg::WaypointList list;
  list.stamp = static_cast<Nanos>(whole(lists, "stamp", last, kMaxStamp));
  list.revision = static_cast<std::uint32_t>(whole(lists, "revision", last, kMaxU32));
  list.count = static_cast<std::uint32_t>(whole(lists, "count", last, static_cast<double>(msg::WaypointList::kCapacity)));
  list.loop = lists.at("loop")[last] != 0.0;
  list.loops = static_cast<std::uint32_t>(whole(lists, "loops", last, kMaxU32));
  std::vector<bool> seen(list.count, false);
  for (std::size_t r = 0; r < items.rows; ++r) {
    if (items.at("revision")[r] != list.revision) continue;
    const double i = whole(items, "index", r, static_cast<double>(msg::WaypointList::kCapacity));
    if (i >= list.count) continue;  // not in this list
    list.items[static_cast<std::size_t>(i)] = waypoint_at(items, r);
    seen[static_cast<std::size_t>(i)] = true;
  }
  for (std::size_t i = 0; i < list.count; ++i)
    if (!seen[i])
      throw ConfigError(fmt::format("{}: revision {} has no item {} (its list in {} has {})", items.file.string(), list.revision, i,
                                    lists.file.string(), list.count));
  return list;
}

}  // namespace

std::optional<msg::WaypointList> last_waypoint_list(const fs::path& run) {
  fs::path dir = run / "topics";
  Scratch scratch;
  if (!fs::exists(dir / "waypoints.csv") && fs::exists(run / "flight.mcap")) {
    export_csv(run / "flight.mcap", scratch.path, {"waypoints", "waypoints_items"});
    dir = scratch.path;
  }
  if (!fs::exists(dir / "waypoints.csv")) return std::nullopt;
  const CsvTable lists = read_csv_table(dir / "waypoints.csv");
  if (lists.rows == 0) return std::nullopt;
  return list_of(lists, read_csv_table(dir / "waypoints_items.csv"));
}

}  // namespace tern::core
