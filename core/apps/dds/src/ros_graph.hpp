// core/apps/dds/src/ros_graph.hpp: how ROS 2 tools see tern's nodes. rmw implementations announce
// which DDS readers and writers belong to which node on the topic `ros_discovery_info` (no rt/
// prefix), type rmw_dds_common/msg/ParticipantEntitiesInfo, QoS reliable, transient-local,
// keep-last 1 (rmw_fastrtps_cpp init_rmw_context_impl.cpp); `ros2 node list` reads it. A GID is
// the 16-byte DDS GUID (prefix, entity id) as rmw_dds_common/msg/Gid.msg has it since Iron (Humble
// used 24 bytes: Humble's tools cannot read these announcements).
#pragma once

#include <string>
#include <vector>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/rtps/common/Guid.h>

namespace tern::core::ddsi {

struct RosNode {
  std::string ns;    ///< "/tern"
  std::string name;  ///< "slc"
  std::vector<eprosima::fastrtps::rtps::GUID_t> readers, writers;
};

class RosGraph {
 public:
  RosGraph(eprosima::fastdds::dds::DomainParticipant* p, eprosima::fastdds::dds::Publisher* pub);
  /// Publishes the participant's nodes (all of them, each time: the last sample is kept for late
  /// joiners).
  void announce(const std::vector<RosNode>& nodes);

 private:
  eprosima::fastdds::dds::DomainParticipant* participant_;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

}  // namespace tern::core::ddsi
