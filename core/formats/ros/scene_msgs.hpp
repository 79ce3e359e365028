// core/formats/ros/scene_msgs.hpp: the ROS 2 messages of the MCAP log's 3-D scene
// (scene_channels.hpp), their ros2msg schemas and their CDR encoding (cdr_writer.hpp):
//   tf2_msgs/msg/TFMessage            transforms (/tf), a list of geometry_msgs/TransformStamped
//   visualization_msgs/msg/MarkerArray markers (the aircraft model, the mission, the path)
// The schemas are the types' .msg fields as ROS 2 Humble and Jazzy define them (ros2/geometry2
// tf2_msgs, ros2/common_interfaces geometry_msgs, std_msgs, sensor_msgs, visualization_msgs,
// ros2/rcl_interfaces builtin_interfaces; Apache-2.0, Open Source Robotics Foundation), each type
// followed by the types it uses after a line of 80 '=' and "MSG: pkg/Type", as rosbag2 writes
// them (the MCAP ros2 profile). Frames and units are ROS's (REP-103): m, rad, ENU/FLU; stamps are
// flight time (ns since the flight's start, as every other channel of the log).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "tern/time.hpp"

namespace tern::core {

/// geometry_msgs/TransformStamped: the pose of `child` in `parent` at `stamp`.
struct RosTransform {
  Nanos stamp = 0;
  std::string parent;                                            ///< header.frame_id
  std::string child;                                             ///< child_frame_id
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();         ///< child's origin in parent, m
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  ///< child -> parent
};

/// visualization_msgs/Marker (action ADD, lifetime 0: until replaced; no texture, no mesh).
struct RosMarker {
  /// Marker.type values used here (the .msg's constants).
  enum Type : std::int32_t { arrow = 0, cube = 1, sphere = 2, cylinder = 3, line_strip = 4, line_list = 5, sphere_list = 7 };
  Nanos stamp = 0;
  std::string frame_id;
  std::string ns;
  std::int32_t id = 0;
  Type type = cube;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               ///< pose.position, m in frame_id
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< pose.orientation
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();     ///< m: a box's size; lines: x = width; arrow: length, shaft and head diameters
  std::array<float, 4> color{1.0F, 1.0F, 1.0F, 1.0F};  ///< r, g, b, a in [0, 1]
  bool frame_locked = false;                           ///< follows its frame as the frame moves
  std::vector<Eigen::Vector3d> points;                 ///< lines and lists, m in frame_id
};

inline constexpr const char* kTfMessageType = "tf2_msgs/msg/TFMessage";
inline constexpr const char* kMarkerArrayType = "visualization_msgs/msg/MarkerArray";

/// The ros2msg schema of TFMessage, of MarkerArray (with their dependencies, as above).
std::string tf_message_schema();
std::string marker_array_schema();

/// Appends the CDR encoding (header included) of a TFMessage / MarkerArray to `out`.
void encode_tf_message(const std::vector<RosTransform>& transforms, std::string& out);
void encode_marker_array(const std::vector<RosMarker>& markers, std::string& out);

}  // namespace tern::core
