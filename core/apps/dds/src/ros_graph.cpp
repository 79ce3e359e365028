// core/apps/dds/src/ros_graph.cpp: see ros_graph.hpp.
#include "ros_graph.hpp"

#include <algorithm>

#include "dds_internal.hpp"
#include "rmw_dds_common/msg/ParticipantEntitiesInfoPubSubTypes.h"

namespace tern::core::ddsi {

namespace {
rmw_dds_common::msg::Gid gid(const eprosima::fastrtps::rtps::GUID_t& g) {
  rmw_dds_common::msg::Gid out;
  std::copy(std::begin(g.guidPrefix.value), std::end(g.guidPrefix.value), out.data().begin());
  std::copy(std::begin(g.entityId.value), std::end(g.entityId.value), out.data().begin() + 12);
  return out;
}
}  // namespace

RosGraph::RosGraph(fdds::DomainParticipant* p, fdds::Publisher* pub) : participant_(p) {
  fdds::Topic* t = make_topic<rmw_dds_common::msg::ParticipantEntitiesInfoPubSubType>(p, "ros_discovery_info");
  fdds::DataWriterQos q = pub->get_default_datawriter_qos();
  q.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  q.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
  q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  q.history().depth = 1;
  writer_ = pub->create_datawriter(t, q);
  if (writer_ == nullptr) throw DdsError("DDS: cannot create the ros_discovery_info writer");
}

void RosGraph::announce(const std::vector<RosNode>& nodes) {
  rmw_dds_common::msg::ParticipantEntitiesInfo info;
  info.gid(gid(participant_->guid()));
  for (const auto& n : nodes) {
    rmw_dds_common::msg::NodeEntitiesInfo e;
    e.node_namespace(n.ns);
    e.node_name(n.name);
    for (const auto& r : n.readers) e.reader_gid_seq().push_back(gid(r));
    for (const auto& w : n.writers) e.writer_gid_seq().push_back(gid(w));
    info.node_entities_info_seq().push_back(std::move(e));
  }
  writer_->write(&info);
}

}  // namespace tern::core::ddsi
