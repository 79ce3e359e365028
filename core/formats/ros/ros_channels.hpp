// core/formats/ros/ros_channels.hpp: the ROS 2 types of the MCAP flight log (issue 44).
//
// Beside each topic's own channel (tern_msgs, every column, what `tern export csv` reads), a
// topic that tern also speaks on the wire in a ROS type gets a second channel in that type, named
// and typed as ROSplane 2.0 and rosflight_io publish it (the DDS bridge's default profile,
// core/apps/dds/src/rosplane_profile.cpp): estimated_state as rosplane_msgs/msg/State, imu/data as
// sensor_msgs/msg/Imu, ..., under the bridge's default namespace as on the wire
// (/tern/estimated_state, /tern/imu/data: beside tern's own /state, /imu). Foxglove, PlotJuggler
// and `ros2 bag` then open those with the messages they know. The types and their CDR encoding come from the DDS bridge (tern_dds), which
// registers a lookup at start-up; a tern built without Fast DDS writes tern's own channels only.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tern::core {

/// One ROS-typed channel of a tern topic.
struct RosChannel {
  std::string topic;   ///< ROS topic, e.g. "/tern/estimated_state"
  std::string type;    ///< e.g. "rosplane_msgs/msg/State"
  std::string schema;  ///< ros2msg text: the type's .msg, then each dependency after a "====" line and "MSG: pkg/Type"
  /// Encodes one tern message (the topic's struct, at its alignment) as CDR with its encapsulation
  /// header, one string per ROS sample (a waypoint list is several); header stamps in flight time.
  std::function<void(const void* msg, std::vector<std::string>& samples)> encode;
};

/// tern topic and type name (e.g. "state", "tern/State") -> its ROS channel, if it has one.
using RosChannelLookup = std::function<std::optional<RosChannel>(std::string_view topic, std::string_view type_name)>;

/// Set once at start-up (tern's main, by tern_dds); unset: no ROS channels.
void set_ros_channel_lookup(RosChannelLookup lookup);
const RosChannelLookup& ros_channel_lookup();

}  // namespace tern::core
