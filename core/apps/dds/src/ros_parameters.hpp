// core/apps/dds/src/ros_parameters.hpp: each plugin instance as a ROS 2 node serving rclcpp's
// parameter services (rclcpp/src/rclcpp/parameter_service.cpp), so that `ros2 param` and
// rqt_reconfigure drive tern as they drive ROSplane:
//   node            /<namespace>/<instance> (parameters by their plain names: roll_kp)
//   services        <node>/{list_parameters, get_parameters, set_parameters,
//                   set_parameters_atomically, describe_parameters, get_parameter_types} on
//                   rq/<namespace>/<instance>/<service>Request, rr/.../<service>Reply, types
//                   rcl_interfaces::srv::dds_::<Srv>_Request_/_Response_ (rmw_fastrtps naming)
//   events          every accepted change on rt/parameter_events (rcl_interfaces/msg/ParameterEvent,
//                   reliable, volatile, keep-last 1000: rmw_qos_profile_parameter_events), stamped
//                   with the wall clock, when the vehicle accepts it (applied at the next tick)
// Values are validated by the parameter's spec; start-only parameters are read_only in their
// descriptors and refused in flight. Changes are recorded in params.csv with source "dds".
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ros_graph.hpp"

namespace tern::core {
class Host;
struct DdsOptions;
}  // namespace tern::core

namespace tern::core::ddsi {

class ServiceEndpoint;

class RosParameters {
 public:
  /// `on_flight_thread` runs a read where parameter values are stable (the bridge's). `options` is
  /// kept by reference: it must outlive this object (the bridge passes its own copy).
  RosParameters(Host& host, const DdsOptions& options, eprosima::fastdds::dds::DomainParticipant* p, eprosima::fastdds::dds::Publisher* pub,
                eprosima::fastdds::dds::Subscriber* sub, std::function<void(const std::function<void()>&)> on_flight_thread);
  ~RosParameters();
  /// One node per instance, with its services' readers and writers.
  std::vector<RosNode> nodes() const;
  /// The parameter-event writer (it belongs to the bridge's node).
  eprosima::fastrtps::rtps::GUID_t events_writer() const;
  /// The parameter services (DdsBridge::answer).
  std::vector<ServiceEndpoint*> endpoints() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tern::core::ddsi
