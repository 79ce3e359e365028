// core/host/config/external_spec.hpp: what an `external` instance of the mission config declares: a module
// whose code runs in another process (a ROS 2 node, ROSplane's or a lab's own) and whose ports are
// DDS topics (docs/external-modules.md).
//
//   - name: ext
//     plugin: external
//     rate: 100                     # Hz: one lockstep exchange per step
//     role: controller              # ROSplane's topics (below), or inputs:/outputs: by hand
//     timeout_ms: 500               # how long a step waits for the outputs stamped for its tick
//     namespace: ""                 # ROS namespace of the topics ("": rt/<topic>)
//     inputs:  [{port: state, topic: estimated_state, type: rosplane_msgs/msg/State}]
//     outputs: [{port: actuators, topic: command, type: rosflight_msgs/msg/Command}]
//
// A binding joins a tern topic (`port`, the name the port graph binds) to a DDS topic of a ROS 2
// type; only the pairs of kBindings exist, each in one direction (tern -> DDS for inputs, DDS ->
// tern for outputs), so a wrong type is a ConfigError naming the field and the types it may be.
// Role `controller` (ROSplane 2.0, rosplane/src/controller/controller_ros.cpp, ControllerROS():
// subscriptions "estimated_state" and "controller_command", publisher "command", rclcpp default
// QoS: reliable, volatile, depth 10):
//   inputs   state -> estimated_state (rosplane_msgs/msg/State),
//            controller_command -> controller_command (rosplane_msgs/msg/ControllerCommands)
//   outputs  command (rosflight_msgs/msg/Command) -> actuators
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "config/config.hpp"
#include "tern/plugin.hpp"

namespace tern::core {

/// A tern message type and the ROS 2 type an external module exchanges it as.
struct ExternalBinding {
  std::string_view ros_type;   ///< e.g. "rosplane_msgs/msg/State"
  std::string_view tern_type;  ///< e.g. "tern/State"
  bool input;                  ///< true: tern -> DDS (the module reads it); false: DDS -> tern
};
/// The bindings there are (the conversions core/apps/dds implements).
const std::vector<ExternalBinding>& external_bindings();
/// nullptr when `ros_type` has no binding.
const ExternalBinding* find_external_binding(std::string_view ros_type);

struct ExternalTopic {
  std::string port;   ///< tern topic (the port's name)
  std::string topic;  ///< ROS topic name, relative to the namespace (e.g. "estimated_state")
  const ExternalBinding* binding = nullptr;
};

struct ExternalSpec {
  std::string instance;
  std::string role;                    ///< "" or "controller"
  std::string ns;                      ///< ROS namespace without slashes at the ends ("" : none)
  std::vector<ExternalTopic> inputs;   ///< published by tern each step
  std::vector<ExternalTopic> outputs;  ///< taken by tern each step (stamped for the step's tick)
  double timeout_ms = 500.0;           ///< ms a step waits for each output, > 0
  /// true (fast time): each step waits for the outputs stamped for its tick. false (--realtime):
  /// each step takes the newest output that came, whatever its stamp, and holds it up to
  /// timeout_ms of wall time; older than that, the module is silent.
  bool lockstep = true;
  PluginKind kind = PluginKind::generic;  ///< controller for role controller or an `actuators` output
  /// "rt/<ns>/<topic>" (DDS topic name of a ROS 2 topic).
  std::string dds_name(const ExternalTopic& t) const;
};

/// Whether the instance entry is an external one (`plugin: external`).
bool is_external(const InstanceConfig& ic);
/// Reads role/inputs/outputs/timeout_ms/namespace of an external instance. Throws ConfigError
/// (file:line:col: plugins[i].field: what).
ExternalSpec parse_external_spec(const InstanceConfig& ic, const fs::path& file);
/// The keys only an external instance may have.
const std::vector<std::string>& external_keys();

}  // namespace tern::core
