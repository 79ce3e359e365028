// core/formats/ros/scene_channels.hpp: the 3-D scene in the MCAP flight log, for Foxglove's 3-D
// panel (and RViz-minded tools): transforms and markers, ROS 2 types (scene_msgs.hpp), written
// beside the ROS-typed copies (ros_channels.hpp; log.ros_channels: false leaves both out).
//
// Frames (REP-103: ENU for the world, FLU for the body; REP-105's names), <p> the frame prefix
// ("uav1/" for a fleet's vehicle uav1, "" alone):
//   map                        ENU (x east, y north, z up), m, about the first valid origin of
//                              a State the log captures: in simulation the simulator's origin
//                              (truth's), on a real flight the estimator's first one
//   <p>base_link               the aircraft as simulated (topic truth): x forward, y left, z up
//   <p>map_estimate            ENU about the estimator's origin (its first GNSS fix): the frame
//                              of the estimate, the waypoints and the commanded path; its origin
//                              in map is the estimate's origin as truth's frame places it (a
//                              translation: the planes' tilt, ~1e-6 rad for metres, is left out)
//   <p>base_link_estimate      the aircraft as estimated (topic state), FLU
// NED -> ENU and FRD -> FLU are converted in one place (enu_of_ned, flu_attitude_in_enu below).
//
// Channels (each with metadata tern.scene: its own topic); every marker is frame-locked (drawn
// where its frame is at the time shown, not looked up at its stamp):
//   /tf                          tf2_msgs/msg/TFMessage: map -> <p>base_link at every truth
//                                message copied, map -> <p>map_estimate -> <p>base_link_estimate
//                                at every state message copied; stamps = the State's stamp
//   /tern/markers/aircraft       visualization_msgs/msg/MarkerArray, once per frame: the model,
//                                boxes in <p>base_link (ns "truth", opaque) and a translucent
//                                ghost in <p>base_link_estimate (ns "estimate")
//   /tern/markers/mission        MarkerArray in <p>map_estimate at each new revision of the
//                                waypoint list: waypoints, the route, loiter orbits, home, and a
//                                land item's glide path and runway centre line
//   /tern/markers/current_path   MarkerArray in <p>map_estimate at each change of the commanded
//                                path: its line or orbit
//   /tern/markers/track          MarkerArray: the true track in map (ns truth_track) and the
//                                estimated one in <p>map_estimate (estimate_track), a segment a
//                                second of flight time, each a marker of its own (ids 0, 1 ...)
//   /tern/markers/wind           MarkerArray in map, at most once a second of flight time: the
//                                true wind as an arrow from the aircraft (truth)
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ros/ros_channels.hpp"

namespace tern::core {

/// What the scene draws the aircraft with; from the aircraft file (scene_options()).
struct SceneOptions {
  std::string frame_prefix;  ///< "uav1/" for a fleet's vehicle, "" alone
  /// The model's dimensions, m; span 0: no model. From the aircraft file: the span b, the mean
  /// chord c, and the hard points "nose" and "tail" (body FRD x, tail z) of gear.structure.
  double span = 0.0;
  double chord = 0.0;
  double nose_x = 0.0;  ///< > tail_x
  double tail_x = 0.0;
  double tail_z = 0.0;  ///< FRD: < 0 above the CG
};

/// The options for the aircraft file `aircraft` (empty path: no model) and fleet part
/// `fleet_part` (a vehicle's name, or ""). Throws std::runtime_error "<file>: <field>: <problem>"
/// when the file does not load.
SceneOptions scene_options(const std::string& aircraft, const std::string& fleet_part);

/// A position NED -> ENU (m).
Eigen::Vector3d enu_of_ned(const Eigen::Vector3d& ned);
/// An attitude body FRD -> NED (tern's State::quat) as body FLU -> ENU (ROS's).
Eigen::Quaterniond flu_attitude_in_enu(const Eigen::Quaterniond& frd_to_ned);

/// The scene of one log: the channels each tern topic feeds. Their encoders share the scene's
/// state (the map's origin, the last waypoint list ...): they must run in capture order on one
/// thread (FlightLog's writer).
class Scene {
 public:
  explicit Scene(SceneOptions options);
  ~Scene();
  /// The channels topic `topic` of type `type_name` ("tern/State" ...) feeds; none for most.
  /// RosChannel::encode's samples are this topic's messages on that channel.
  std::vector<RosChannel> channels_of(std::string_view topic, std::string_view type_name);

 private:
  struct State;
  std::shared_ptr<State> state_;
};

}  // namespace tern::core
