// core/apps/dds/src/mission_item.hpp: a mission item with its type (msg::Waypoint: a land item, a
// loiter) as tern_msgs/MissionItem, the request of the add_mission_item service, field for field:
// to_mission_item() and from_mission_item() are generated from msg::Waypoint's describe()
// (tern_msgs_convert.hpp); here, how an item reads in messages.
#pragma once

#include <string>

#include "tern/msg/path.hpp"
#include "tern_msgs_convert.hpp"

namespace tern::core::ddsi {

/// "waypoint", "loiter item", "return_home item", "land item" (messages).
std::string item_name(const msg::Waypoint& w);
/// What a print of the list adds to an item's position, airspeed and course: "" for a waypoint,
/// " land: glide slope 0.0873 rad, flare 4 m, decision 12 m" (chi_d the runway heading), ...
std::string item_text(const msg::Waypoint& w);

}  // namespace tern::core::ddsi
