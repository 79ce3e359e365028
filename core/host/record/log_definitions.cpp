#include "record/log_definitions.hpp"

#include <nlohmann/json.hpp>

#include "tern/msg/path.hpp"
#include "tern/msg/phase.hpp"
#include "tern/path/item.hpp"

namespace tern::core {

std::string log_definitions_json() {
  nlohmann::ordered_json j;
  j["about"] = "what the log's codes and defaults mean (core/host/record/log_definitions.hpp)";
  for (const msg::Phase p : msg::kAllPhases) j["phase"][std::to_string(static_cast<int>(p))] = msg::phase_name(p);
  for (const auto t : {msg::Waypoint::waypoint, msg::Waypoint::loiter, msg::Waypoint::return_home, msg::Waypoint::land})
    j["item_type"][std::to_string(static_cast<int>(t))] = path::item_type_name(static_cast<path::ItemType>(t));
  const path::LandSpec land;
  j["land_item"] = {{"glide_slope", land.glide_slope},
                    {"flare_height", land.flare_height},
                    {"decision_height", land.decision_height},
                    {"min_entry_heights", path::kMinEntryHeights}};
  return j.dump(2) + "\n";
}

}  // namespace tern::core
