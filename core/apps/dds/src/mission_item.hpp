// core/apps/dds/src/mission_item.hpp: a mission item with its type (msg::Waypoint: a land item, a
// loiter) as tern_msgs/MissionItem, the request of the add_mission_item service; field for
// field (ctest dds_messages checks the IDL against msg::Waypoint's describe()).
#pragma once

#include <string>

#include "tern/msg/path.hpp"
#include "tern_msgs/msg/Vehicle.h"

namespace tern::core::ddsi {

void to_mission_item(const msg::Waypoint& w, tern_msgs::msg::MissionItem& out);
msg::Waypoint from_mission_item(const tern_msgs::msg::MissionItem& in);

/// "waypoint", "loiter item", "return_home item", "land item" (messages).
std::string item_name(const msg::Waypoint& w);
/// What a print of the list adds to an item's position, airspeed and course: "" for a waypoint,
/// " land: glide slope 0.0873 rad, flare 4 m, decision 12 m" (chi_d the runway heading), ...
std::string item_text(const msg::Waypoint& w);

}  // namespace tern::core::ddsi
