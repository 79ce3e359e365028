// core/apps/export/flown_mission.cpp: a run's last waypoint list from its log (flown_mission.hpp).
#include "export/flown_mission.hpp"

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
    if (const std::string problem = column_problem(c, v); !problem.empty())
      throw ConfigError(fmt::format("{}: row {}: {}", items.file.string(), row + 2, problem));
    set_column_value(c, &w, v);
  }
  return w;
}

/// The list of the last row of `lists`, its items from `items` (the rows of its revision).
msg::WaypointList list_of(const CsvTable& lists, const CsvTable& items) {
  const std::size_t last = lists.rows - 1;
  msg::WaypointList list;
  list.stamp = static_cast<Nanos>(lists.at("stamp")[last]);
  list.revision = static_cast<std::uint32_t>(lists.at("revision")[last]);
  const double count = lists.at("count")[last];
  if (!(count >= 0 && count <= static_cast<double>(msg::WaypointList::kCapacity)))
    throw ConfigError(fmt::format("{}: last row: count {} (0..{})", lists.file.string(), count, msg::WaypointList::kCapacity));
  list.count = static_cast<std::uint32_t>(count);
  list.loop = lists.at("loop")[last] != 0.0;
  list.loops = static_cast<std::uint32_t>(std::fmax(0.0, lists.at("loops")[last]));
  std::vector<bool> seen(list.count, false);
  for (std::size_t r = 0; r < items.rows; ++r) {
    if (items.at("revision")[r] != list.revision) continue;
    const double i = items.at("index")[r];
    if (!(i >= 0 && i < count)) continue;  // a list of the same revision logged again
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
