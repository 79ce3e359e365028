// core/apps/dds/src/participant.cpp: participants restricted to the configured interfaces, QoS.
#include <arpa/inet.h>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include "dds_internal.hpp"
#include "security.hpp"

namespace tern::core::ddsi {

using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;

namespace {
constexpr std::uint32_t kInitialPeersRange = 32;
}

fdds::DomainParticipant* make_participant(const DdsOptions& o, const std::string& name) {
  fdds::DomainParticipantQos q;  // then: no built-in transports, only the listed interfaces
  q.name(name);
  // as rmw_fastrtps (participant.cpp): "enclave=<enclave>;" in the participant's user data;
  // ROS 2's graph (custom_participant_info.hpp) ignores a participant without it
  const std::string enclave = enclave_user_data(o);
  if (o.security) apply_security(q, *o.security);  // DDS Security (security.hpp)
  q.user_data().setValue(std::vector<eprosima::fastrtps::rtps::octet>(enclave.begin(), enclave.end()));
  // no shared-memory and no any-interface UDP transport: only what the config names
  q.transport().use_builtin_transports = false;
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  for (const auto& i : o.interfaces) udp->interfaceWhiteList.push_back(i);
  // discovery without multicast reaches a peer's participant ids 0..range-1 on each peer
  // address: a process may hold several participants (bridge, command line, tests)
  udp->maxInitialPeersRange = kInitialPeersRange;
  q.transport().user_transports.push_back(udp);
  auto& b = q.wire_protocol().builtin;
  b.initialPeersList.clear();
  for (const auto& peer : o.peers) {
    Locator_t l;
    l.kind = LOCATOR_KIND_UDPv4;
    IPLocator::setIPv4(l, peer);
    b.initialPeersList.push_back(l);
  }
  if (!o.multicast) {
    // discovery by unicast only: metatraffic on each listed interface (port chosen by Fast DDS
    // from the domain and participant id), no multicast locator at all
    b.metatrafficMulticastLocatorList.clear();
    b.metatrafficUnicastLocatorList.clear();
    for (const auto& i : o.interfaces) {
      Locator_t l;
      l.kind = LOCATOR_KIND_UDPv4;
      IPLocator::setIPv4(l, i);
      b.metatrafficUnicastLocatorList.push_back(l);
    }
    q.wire_protocol().default_unicast_locator_list.clear();
    for (const auto& i : o.interfaces) {
      Locator_t l;
      l.kind = LOCATOR_KIND_UDPv4;
      IPLocator::setIPv4(l, i);
      q.wire_protocol().default_unicast_locator_list.push_back(l);
    }
    q.wire_protocol().default_multicast_locator_list.clear();
  }
  auto* f = fdds::DomainParticipantFactory::get_instance();
  fdds::DomainParticipant* p = f->create_participant(static_cast<fdds::DomainId_t>(o.domain), q);
  if (p == nullptr)
    throw DdsError("DDS: cannot create a participant on domain " + std::to_string(o.domain) + " (interfaces " + [&] {
      std::string s;
      for (const auto& i : o.interfaces) s += (s.empty() ? "" : ", ") + i;
      return s;
    }() + ")" + (o.security ? " with the DDS Security files of enclave '" + o.security->enclave + "'" : ""));
  return p;
}

void delete_participant(fdds::DomainParticipant* p) {
  if (p == nullptr) return;
  p->delete_contained_entities();
  fdds::DomainParticipantFactory::get_instance()->delete_participant(p);
}

fdds::DataWriterQos writer_qos(DdsQos k, int depth) {
  fdds::DataWriterQos q = fdds::DATAWRITER_QOS_DEFAULT;
  switch (k) {
    case DdsQos::best_effort:
      q.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
      q.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
      q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
      q.history().depth = 1;
      break;
    case DdsQos::reliable:
      q.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
      q.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
      q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
      q.history().depth = 10;
      break;
    case DdsQos::transient_local:
      q.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
      q.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
      q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
      q.history().depth = 1;
      break;
  }
  if (depth > 0) q.history().depth = depth;
  // the flight thread never blocks on a slow reader
  q.reliability().max_blocking_time = Duration(0, 0);
  q.publish_mode().kind = fdds::SYNCHRONOUS_PUBLISH_MODE;
  return q;
}

fdds::DataReaderQos reader_qos(DdsQos k) {
  fdds::DataReaderQos q = fdds::DATAREADER_QOS_DEFAULT;
  q.reliability().kind = k == DdsQos::best_effort ? fdds::BEST_EFFORT_RELIABILITY_QOS : fdds::RELIABLE_RELIABILITY_QOS;
  q.durability().kind = k == DdsQos::transient_local ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
  q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  q.history().depth = k == DdsQos::reliable ? 10 : (k == DdsQos::best_effort ? 10 : 1);
  return q;
}

// ROS 2's service profile: reliable, volatile, keep-last 10
fdds::DataWriterQos service_writer_qos() {
  fdds::DataWriterQos q = writer_qos(DdsQos::reliable);
  q.reliability().max_blocking_time = Duration(0, 100000000);
  return q;
}
fdds::DataReaderQos service_reader_qos() { return reader_qos(DdsQos::reliable); }

static std::string join(const std::string& prefix, const std::string& ns, const std::string& name) {
  return prefix + (ns.empty() ? "" : ns + "/") + name;
}
std::string topic_name(const std::string& ns, const std::string& name) { return join("rt/", ns, name); }
std::string request_topic(const std::string& ns, const std::string& service) { return join("rq/", ns, service) + "Request"; }
std::string reply_topic(const std::string& ns, const std::string& service) { return join("rr/", ns, service) + "Reply"; }

bool wait_until(const std::function<bool()>& cond, std::chrono::milliseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    if (cond()) return true;
    if (std::chrono::steady_clock::now() >= end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

}  // namespace tern::core::ddsi
