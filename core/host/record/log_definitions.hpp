// core/host/record/log_definitions.hpp: definitions.json, what a flight log's codes and defaults
// mean, written by the host into every run directory (and attached to flight.mcap) so that the
// log's readers (tern plot, the benches, a researcher's script) take them from the log instead
// of restating C++:
//   "phase"          msg::Phase codes (topics/phase.csv `phase`) -> names (tern/msg/phase.hpp)
//   "item_type"      msg::Waypoint::Type codes (waypoints_items.csv `type`) -> names
//                    (tern/path/item.hpp item_type_name)
//   "land_item"      a land item's defaults where the mission leaves them out (tern/path/item.hpp
//                    LandSpec: glide_slope rad, flare_height m, decision_height m) and
//                    min_entry_heights (kMinEntryHeights: the approach begins at least that many
//                    decision heights above the touchdown point)
// The same bytes for every flight of this build.
#pragma once

#include <string>

namespace tern::core {

/// definitions.json's text.
std::string log_definitions_json();

}  // namespace tern::core
