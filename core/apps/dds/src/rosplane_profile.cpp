// core/apps/dds/src/rosplane_profile.cpp: the bridge's default topics, ROSplane 2.0's wire profile.
// Names, types and QoS as ROSplane's nodes and rosflight_io create them (rclcpp: a depth alone
// means reliable, volatile, keep-last depth). Read from rosflight/rosplane (commit ba7e114a) and
// rosflight/rosflight_ros_pkgs (commit 68729f2b); core/apps/dds/README.md has the table with the file
// and function of each.
#include "dds_bridge.hpp"

namespace tern::core {

std::vector<DdsTopicOptions> DdsOptions::rosplane_profile(bool aliases) {
  const auto rel = DdsQos::reliable;
  std::vector<DdsTopicOptions> t = {
      // ROSplane's nodes (rosplane/src/...)
      {"state", "estimated_state", -1, rel, 10, "rosplane_msgs/msg/State"},                                    // ekf/estimator_ros.cpp
      {"waypoints", "waypoint_path", -1, DdsQos::transient_local, 10, "rosplane_msgs/msg/Waypoint"},           // path_planner_waypoints.cpp
      {"current_path", "current_path", -1, rel, 10, "rosplane_msgs/msg/CurrentPath"},                          // path_manager_ros.cpp
      {"controller_command", "controller_command", -1, rel, 1, "rosplane_msgs/msg/ControllerCommands"},        // path_follower_ros.cpp
      {"controller_internals", "controller_internals", -1, rel, 10, "rosplane_msgs/msg/ControllerInternals"},  // controller_ros.cpp
      {"actuators", "command", -1, rel, 10, "rosflight_msgs/msg/Command"},                                     // controller_ros.cpp
      // rosflight_io (rosflight_io/src/rosflight_io.cpp): the FCU's sensors and status
      {"imu", "imu/data", -1, rel, 1, "sensor_msgs/msg/Imu"},                    // handle_small_imu_msg
      {"gnss", "gnss", -1, rel, 1, "rosflight_msgs/msg/GNSS"},                   // handle_rosflight_gnss_msg
      {"baro", "baro", -1, rel, 1, "rosflight_msgs/msg/Barometer"},              // handle_small_baro_msg
      {"diff_pressure", "airspeed", -1, rel, 1, "rosflight_msgs/msg/Airspeed"},  // handle_diff_pressure_msg
      {"mag", "magnetometer", -1, rel, 1, "sensor_msgs/msg/MagneticField"},      // handle_small_mag_msg
      {"fcu_status", "status", -1, rel, 1, "rosflight_msgs/msg/Status"},         // handle_status_msg
      // tern's own (no ROSplane counterpart)
      {"flight_phase", "flight_phase", -1, DdsQos::transient_local, std::nullopt, ""},
  };
  if (aliases) {
    // tern's names from before the profile, in tern's types and QoS (`tern echo state` ...)
    t.push_back({"state", "state", -1, DdsQos::best_effort, std::nullopt, ""});
    t.push_back({"waypoints", "waypoints", -1, DdsQos::transient_local, std::nullopt, ""});
    t.push_back({"actuators", "actuators", -1, DdsQos::best_effort, std::nullopt, ""});
  }
  return t;
}

}  // namespace tern::core
