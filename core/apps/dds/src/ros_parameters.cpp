// core/apps/dds/src/ros_parameters.cpp: see ros_parameters.hpp.
#include "ros_parameters.hpp"

#include <algorithm>
#include <chrono>
#include <map>

#include "dds_internal.hpp"
#include "flight/host.hpp"
#include "rcl_convert.hpp"
#include "rcl_interfaces/msg/ParameterEventPubSubTypes.h"
#include "rcl_interfaces/srv/ParametersPubSubTypes.h"

namespace tern::core::ddsi {

namespace rs = rcl_interfaces::srv;
namespace rm = rcl_interfaces::msg;

struct RosParameters::Impl {
  Host& host;
  const DdsOptions& options;
  fdds::DomainParticipant* participant;
  fdds::Publisher* publisher;
  fdds::Subscriber* subscriber;
  std::function<void(const std::function<void()>&)> on_flight_thread;
  fdds::DataWriter* events = nullptr;
  std::vector<std::shared_ptr<void>> servers{};
  std::vector<ServiceEndpoint*> endpoints{};  // the servers' (answer(): without the wire)
  std::vector<RosNode> nodes{};

  /// The instance's parameters by plain name (read where values are stable).
  std::map<std::string, const ParamBase*> params_of(const std::string& instance) const {
    std::map<std::string, const ParamBase*> out;
    for (const auto& [name, p] : host.parameters())
      if (name.size() > instance.size() && name.compare(0, instance.size() + 1, instance + ".") == 0) out[p->name()] = p;
    return out;
  }

  template <class Srv>
  void serve(RosNode& node, const std::string& service, std::function<typename Srv::Resp(const typename Srv::Req&)> fn) {
    const std::string ns = (options.ns.empty() ? "" : options.ns + "/") + node.name;
    auto s = std::make_shared<ServiceServer<typename Srv::ReqPS, typename Srv::RespPS>>(
        participant, publisher, subscriber, ns, service, [this] { host.ground_link_heard(); }, std::move(fn));
    node.readers.push_back(s->reader()->guid());
    node.writers.push_back(s->writer()->guid());
    endpoints.push_back(s.get());
    servers.push_back(std::move(s));
  }

  void publish_event(const std::string& instance, const std::vector<rm::Parameter>& changed) {
    rm::ParameterEvent e;
    const auto ns = std::chrono::system_clock::now().time_since_epoch() / std::chrono::nanoseconds(1);
    e.stamp().sec(static_cast<std::int32_t>(ns / 1000000000));
    e.stamp().nanosec(static_cast<std::uint32_t>(ns % 1000000000));
    e.node("/" + (options.ns.empty() ? "" : options.ns + "/") + instance);
    e.changed_parameters(changed);
    events->write(&e);
  }

  /// Asks the host for `instance.name` = value; "" on success, else the reason.
  std::string set_one(const std::string& instance, const rm::Parameter& p) {
    try {
      host.request_param(instance + "." + p.name(), from_rcl(p.value()), "dds");
      return "";
    } catch (const std::exception& e) {
      return e.what();
    }
  }

  void add_node(const std::string& instance);
  void add_reads(RosNode& node, const std::string& instance);
  void add_writes(RosNode& node, const std::string& instance);
  std::string check_all(const std::string& instance, const std::vector<rm::Parameter>& ps);
};

template <class Rq, class Rs, class RqPS, class RsPS>
struct Srv {
  using Req = Rq;
  using Resp = Rs;
  using ReqPS = RqPS;
  using RespPS = RsPS;
};
using ListSrv = Srv<rs::ListParameters_Request, rs::ListParameters_Response, rs::ListParameters_RequestPubSubType,
                    rs::ListParameters_ResponsePubSubType>;
using GetSrv =
    Srv<rs::GetParameters_Request, rs::GetParameters_Response, rs::GetParameters_RequestPubSubType, rs::GetParameters_ResponsePubSubType>;
using SetSrv =
    Srv<rs::SetParameters_Request, rs::SetParameters_Response, rs::SetParameters_RequestPubSubType, rs::SetParameters_ResponsePubSubType>;
using AtomicSrv = Srv<rs::SetParametersAtomically_Request, rs::SetParametersAtomically_Response,
                      rs::SetParametersAtomically_RequestPubSubType, rs::SetParametersAtomically_ResponsePubSubType>;
using DescribeSrv = Srv<rs::DescribeParameters_Request, rs::DescribeParameters_Response, rs::DescribeParameters_RequestPubSubType,
                        rs::DescribeParameters_ResponsePubSubType>;
using TypesSrv = Srv<rs::GetParameterTypes_Request, rs::GetParameterTypes_Response, rs::GetParameterTypes_RequestPubSubType,
                     rs::GetParameterTypes_ResponsePubSubType>;

void RosParameters::Impl::add_reads(RosNode& node, const std::string& instance) {
  serve<ListSrv>(node, "list_parameters", [this, instance](const rs::ListParameters_Request& rq) {
    rs::ListParameters_Response r;  // tern names have no '.': depth does not matter
    on_flight_thread([&] {
      for (const auto& [name, p] : params_of(instance)) {
        bool match = rq.prefixes().empty();
        for (const auto& pre : rq.prefixes()) match = match || name == pre || name.rfind(pre + ".", 0) == 0;
        if (match) r.result().names().push_back(name);
      }
    });
    return r;
  });
  serve<GetSrv>(node, "get_parameters", [this, instance](const rs::GetParameters_Request& rq) {
    rs::GetParameters_Response r;  // an unknown name: PARAMETER_NOT_SET, as rclcpp answers
    on_flight_thread([&] {
      const auto ps = params_of(instance);
      for (const auto& n : rq.names()) r.values().push_back(ps.count(n) ? to_rcl(ps.at(n)->value()) : rm::ParameterValue());
    });
    return r;
  });
  serve<DescribeSrv>(node, "describe_parameters", [this, instance](const rs::DescribeParameters_Request& rq) {
    rs::DescribeParameters_Response r;
    const auto ps = params_of(instance);  // descriptors do not change in flight
    for (const auto& n : rq.names()) {
      rm::ParameterDescriptor d = ps.count(n) ? describe(*ps.at(n)) : rm::ParameterDescriptor();
      d.name(n);
      r.descriptors().push_back(d);
    }
    return r;
  });
  serve<TypesSrv>(node, "get_parameter_types", [this, instance](const rs::GetParameterTypes_Request& rq) {
    rs::GetParameterTypes_Response r;
    const auto ps = params_of(instance);
    for (const auto& n : rq.names()) r.types().push_back(ps.count(n) ? rcl_type(ps.at(n)->default_value()) : kNotSet);
    return r;
  });
}

std::string RosParameters::Impl::check_all(const std::string& instance, const std::vector<rm::Parameter>& ps) {
  const auto known = params_of(instance);
  for (const auto& p : ps) {
    const auto it = known.find(p.name());
    if (it == known.end()) return "unknown parameter '" + instance + "." + p.name() + "'";
    try {
      it->second->validate(from_rcl(p.value()));
    } catch (const std::exception& e) {
      return e.what();
    }
    if (!it->second->spec().live && host.flying())
      return "parameter '" + instance + "." + p.name() + "' is read-only in flight (start-only: set it between flights)";
  }
  return "";
}

void RosParameters::Impl::add_writes(RosNode& node, const std::string& instance) {
  serve<SetSrv>(node, "set_parameters", [this, instance](const rs::SetParameters_Request& rq) {
    rs::SetParameters_Response r;  // each on its own, as rclcpp's set_parameters
    std::vector<rm::Parameter> changed;
    for (const auto& p : rq.parameters()) {
      rm::SetParametersResult res;
      res.reason(set_one(instance, p));
      res.successful(res.reason().empty());
      if (res.successful()) changed.push_back(p);
      r.results().push_back(res);
    }
    if (!changed.empty()) publish_event(instance, changed);
    return r;
  });
  serve<AtomicSrv>(node, "set_parameters_atomically", [this, instance](const rs::SetParametersAtomically_Request& rq) {
    rs::SetParametersAtomically_Response r;  // all or none: every value is checked before any is asked for
    r.result().reason(check_all(instance, rq.parameters()));
    if (r.result().reason().empty())
      for (const auto& p : rq.parameters()) r.result().reason(r.result().reason() + set_one(instance, p));
    r.result().successful(r.result().reason().empty());
    if (r.result().successful() && !rq.parameters().empty()) publish_event(instance, rq.parameters());
    return r;
  });
}

void RosParameters::Impl::add_node(const std::string& instance) {
  RosNode node;
  node.ns = "/" + options.ns;
  node.name = instance;
  add_reads(node, instance);
  if (!options.read_only) add_writes(node, instance);
  nodes.push_back(std::move(node));
}

RosParameters::RosParameters(Host& host, const DdsOptions& options, fdds::DomainParticipant* p, fdds::Publisher* pub, fdds::Subscriber* sub,
                             std::function<void(const std::function<void()>&)> on_flight_thread)
    : impl_(new Impl{host, options, p, pub, sub, std::move(on_flight_thread)}) {
  fdds::DataWriterQos q = pub->get_default_datawriter_qos();
  q.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  q.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
  q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  q.history().depth = 1000;
  impl_->events = pub->create_datawriter(make_topic<rm::ParameterEventPubSubType>(p, "rt/parameter_events"), q);
  if (impl_->events == nullptr) throw DdsError("DDS: cannot create the rt/parameter_events writer");
  // every instance (schedule order), then the host's own parameter owners (phase_machine, metrics)
  std::vector<std::string> names = host.schedule();
  for (const auto& [name, param] : host.parameters()) {
    const std::string inst = name.substr(0, name.find('.'));
    if (std::find(names.begin(), names.end(), inst) == names.end()) names.push_back(inst);
  }
  for (const auto& n : names) impl_->add_node(n);
}

RosParameters::~RosParameters() = default;

std::vector<RosNode> RosParameters::nodes() const { return impl_->nodes; }

eprosima::fastrtps::rtps::GUID_t RosParameters::events_writer() const { return impl_->events->guid(); }

std::vector<ServiceEndpoint*> RosParameters::endpoints() const { return impl_->endpoints; }

}  // namespace tern::core::ddsi
