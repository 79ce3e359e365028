// core/apps/dds/src/convert_rosplane.hpp: tern's messages as ROSplane 2.0's (rosplane_msgs): State,
// ControllerCommands, ControllerInternals, CurrentPath, Waypoint, and a waypoint list as the path
// planner's waypoint_path (a clear, then one Waypoint per item). Units as ROSplane's: SI, NED,
// float32 where ROSplane's message has float32. Also the items of tern_msgs/WaypointList
// (generated tern_msgs_convert.cpp), which are ROSplane Waypoints.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "dds_internal.hpp"
#include "rosplane_msgs/msg/Waypoint.h"
#include "std_msgs/msg/Header.h"
#include "tern/msg/path.hpp"

namespace tern::core::ddsi {

/// One item of a tern_msgs/WaypointList: the ROSplane waypoint of `item`, stamped as the list.
void list_waypoint(const msg::Waypoint& item, const std_msgs::msg::Header& list_header, rosplane_msgs::msg::Waypoint& out);
/// "waypoint[<index>]: w [n, e, d] lla .. chi_d .. use_chi .. va_d ..": one line of `tern echo waypoints`.
std::string render_list_waypoint(std::size_t index, const rosplane_msgs::msg::Waypoint& w);

/// Appends the rosplane_msgs conversions.
void add_rosplane_types(std::vector<TypeEntry>& v);

}  // namespace tern::core::ddsi
