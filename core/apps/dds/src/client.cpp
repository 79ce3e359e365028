// core/apps/dds/src/client.cpp: the ground side (command line) of the DDS bridge.
#include <fmt/format.h>

#include "client_impl.hpp"
#include "mission_item.hpp"
#include "rosplane_msgs/srv/AddWaypointPubSubTypes.h"
#include "std_srvs/srv/TriggerPubSubTypes.h"
#include "tern_msgs/srv/ServicesPubSubTypes.h"

namespace tern::core {

using namespace ddsi;
namespace ts = tern_msgs::srv;

DdsClient::DdsClient(const DdsOptions& options, std::chrono::milliseconds timeout) : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  impl_->timeout = timeout;
  impl_->participant = make_participant(options, "tern/client");
  impl_->publisher = impl_->participant->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  impl_->subscriber = impl_->participant->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  if (impl_->publisher == nullptr || impl_->subscriber == nullptr) throw DdsError("DDS: cannot create a publisher/subscriber");
}

DdsClient::~DdsClient() = default;

void DdsClient::set_request_id(std::uint64_t id) { impl_->next_id = id; }

DdsStatus DdsClient::status() {
  ts::Status_Request rq;
  const auto r = impl_->call<ts::Status_RequestPubSubType, ts::Status_ResponsePubSubType>("status", rq);
  DdsStatus s;
  s.mission = r.mission();
  s.config_file = r.config_file();
  s.flying = r.flying();
  s.flight_time = r.flight_time().sec() + r.flight_time().nanosec() * 1e-9;
  s.phase = r.phase_name();
  s.flights = r.flights();
  for (std::size_t i = 0; i < r.topics().size() && i < r.types().size(); ++i) {
    s.topics.emplace_back(r.topics()[i], r.types()[i]);
    s.qos.push_back(i < r.qos().size() && r.qos()[i] <= 2 ? static_cast<DdsQos>(r.qos()[i]) : DdsQos::best_effort);
  }
  return s;
}

std::string DdsClient::param_save(const std::string& filename, bool overwrite) {
  ts::ParamSave_Request rq;
  rq.filename(filename);
  rq.overwrite(overwrite);
  const auto r = impl_->call<ts::ParamSave_RequestPubSubType, ts::ParamSave_ResponsePubSubType>("param_save", rq, "ls on the vehicle");
  if (!r.success()) throw DdsError(r.message());
  return r.message();
}

void DdsClient::mission_add(const msg::Waypoint& wp, bool set_current, bool publish_now) {
  if (wp.type != msg::Waypoint::waypoint) {  // ROSplane's AddWaypoint has no item type: tern's service
    ts::MissionAddItem_Request rq;
    ddsi::to_mission_item(wp, rq.item());
    rq.set_current(set_current);
    rq.publish_now(publish_now);
    const auto r = impl_->call<ts::MissionAddItem_RequestPubSubType, ts::MissionAddItem_ResponsePubSubType>("add_mission_item", rq,
                                                                                                            "tern mission print");
    if (!r.success()) throw DdsError(r.message());
    return;
  }
  rosplane_msgs::srv::AddWaypoint_Request rq;
  for (int i = 0; i < 3; ++i) rq.w()[i] = static_cast<float>(wp.w[i]);
  rq.lla(wp.lla);
  rq.chi_d(static_cast<float>(wp.chi_d));
  rq.use_chi(wp.use_chi);
  rq.va_d(static_cast<float>(wp.Va_d));
  rq.set_current(set_current);
  rq.publish_now(publish_now);
  const auto r = impl_->call<rosplane_msgs::srv::AddWaypoint_RequestPubSubType, rosplane_msgs::srv::AddWaypoint_ResponsePubSubType>(
      "add_waypoint", rq, "tern mission print");
  if (!r.success()) throw DdsError(r.message());
}

void DdsClient::mission_clear() {
  std_srvs::srv::Trigger_Request rq;
  const auto r = impl_->call<std_srvs::srv::Trigger_RequestPubSubType, std_srvs::srv::Trigger_ResponsePubSubType>("clear_waypoints", rq,
                                                                                                                  "tern mission print");
  if (!r.success()) throw DdsError(r.message());
}

void DdsClient::mission_load(const std::string& filename) {
  ts::MissionLoad_Request rq;
  rq.filename(filename);
  const auto r = impl_->call<ts::MissionLoad_RequestPubSubType, ts::MissionLoad_ResponsePubSubType>("load_mission_from_file", rq,
                                                                                                    "tern mission print");
  if (!r.success()) throw DdsError(r.message());
}

std::string DdsClient::mission_print() {
  std_srvs::srv::Trigger_Request rq;
  const auto r = impl_->call<std_srvs::srv::Trigger_RequestPubSubType, std_srvs::srv::Trigger_ResponsePubSubType>("print_waypoints", rq);
  if (!r.success()) throw DdsError(r.message());
  return r.message();
}

std::string DdsClient::go_around() {
  std_srvs::srv::Trigger_Request rq;
  const auto r = impl_->call<std_srvs::srv::Trigger_RequestPubSubType, std_srvs::srv::Trigger_ResponsePubSubType>("go_around", rq);
  if (!r.success()) throw DdsError(r.message());
  return r.message();
}

std::string DdsClient::bridge_topic(const std::string& topic, double rate) {
  ts::BridgeTopic_Request rq;
  rq.topic(topic);
  rq.rate(rate);
  const auto r = impl_->call<ts::BridgeTopic_RequestPubSubType, ts::BridgeTopic_ResponsePubSubType>("bridge_topic", rq);
  if (!r.success()) throw DdsError(r.message());
  return r.message();
}

namespace {
/// The DDS type and QoS of `name` in the vehicle's status, or nullptr.
const TypeEntry* published_type(const DdsStatus& st, const std::string& name, DdsQos& qos) {
  for (std::size_t i = 0; i < st.topics.size(); ++i)
    if (st.topics[i].first == name) {
      qos = st.qos[i];
      return find_dds_type(st.topics[i].second);
    }
  return nullptr;
}
}  // namespace

void DdsClient::echo(const std::string& topic, const std::function<bool(const std::string&)>& on_sample) {
  // the vehicle says which DDS type the topic has; a tern topic it does not bridge yet (truth,
  // imu) is asked for
  const std::string name = topic.rfind("rt/", 0) == 0 ? topic : topic_name(impl_->options.ns, topic);
  DdsQos qos = DdsQos::best_effort;
  const TypeEntry* type = published_type(status(), name, qos);
  if (type == nullptr && topic.rfind("rt/", 0) != 0) {
    bridge_topic(topic, 0);
    type = published_type(status(), name, qos);
  }
  if (type == nullptr) throw DdsError("the vehicle does not publish " + name + " (see `tern topics`)");
  fdds::TypeSupport tsup(type->make_type());
  auto* p = impl_->participant;
  if (p->find_type(tsup.get_type_name()).empty()) tsup.register_type(p);
  fdds::Topic* t = p->create_topic(name, tsup.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
  if (t == nullptr) throw DdsError("DDS: cannot create topic " + name);
  // the writer's QoS: a transient-local topic (waypoints, flight_phase) gives its last sample at once
  fdds::DataReader* r = impl_->subscriber->create_datareader(t, reader_qos(qos));
  if (r == nullptr) throw DdsError("DDS: cannot create a reader for " + name);
  struct Cleanup {
    fdds::Subscriber* s;
    fdds::DomainParticipant* p;
    fdds::DataReader* r;
    fdds::Topic* t;
    ~Cleanup() {
      s->delete_datareader(r);
      p->delete_topic(t);
    }
  } cleanup{impl_->subscriber, p, r, t};
  auto sample = type->make_sample();
  for (;;) {
    if (!r->wait_for_unread_message(Duration(static_cast<std::int32_t>(impl_->timeout.count() / 1000),
                                             static_cast<std::uint32_t>((impl_->timeout.count() % 1000) * 1000000))))
      throw DdsError(fmt::format("no sample on {} within {:.1f} s", name, static_cast<double>(impl_->timeout.count()) / 1000.0));
    fdds::SampleInfo info;
    while (r->take_next_sample(sample.get(), &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      if (!on_sample(type->render(sample.get()))) return;
    }
  }
}

}  // namespace tern::core
