// core/apps/dds/src/client_params.cpp: `tern param` over ROS 2's parameter services (rcl_interfaces),
// the ones `ros2 param` uses: the vehicle's nodes come from ros_discovery_info (ros_graph.hpp),
// a parameter "slc.roll_kp" is parameter roll_kp of node /<namespace>/slc.
#include <algorithm>

#include "client_impl.hpp"
#include "config/error.hpp"
#include "rcl_convert.hpp"
#include "rcl_interfaces/srv/ParametersPubSubTypes.h"
#include "rmw_dds_common/msg/ParticipantEntitiesInfoPubSubTypes.h"

namespace tern::core {

namespace rs = rcl_interfaces::srv;
namespace rm = rcl_interfaces::msg;

namespace {

/// "ctl.kp" -> {"ctl", "kp"}; DdsError without a '.'.
std::pair<std::string, std::string> split(const std::string& qualified) {
  const auto dot = qualified.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == qualified.size())
    throw DdsError("'" + qualified + "' is not a parameter name (instance.param, e.g. slc.roll_kp)");
  return {qualified.substr(0, dot), qualified.substr(dot + 1)};
}

}  // namespace

std::pair<std::string, std::string> DdsClient::known_node(const std::string& qualified) {
  auto parts = split(qualified);
  const auto all = nodes();
  if (std::find(all.begin(), all.end(), parts.first) == all.end())
    throw DdsError("unknown parameter '" + qualified + "': the vehicle has no instance '" + parts.first + "'" +
                   did_you_mean(parts.first, all));
  return parts;
}

std::vector<std::string> DdsClient::nodes() {
  auto* p = impl_->participant;
  fdds::Topic* t = make_topic<rmw_dds_common::msg::ParticipantEntitiesInfoPubSubType>(p, "ros_discovery_info");
  fdds::DataReaderQos q = impl_->subscriber->get_default_datareader_qos();
  q.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  q.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
  q.history().kind = fdds::KEEP_ALL_HISTORY_QOS;
  fdds::DataReader* r = impl_->subscriber->create_datareader(t, q);
  if (r == nullptr) throw DdsError("DDS: cannot create a ros_discovery_info reader");
  const std::string ns = "/" + impl_->options.ns;
  std::vector<std::string> out;
  const auto deadline = std::chrono::steady_clock::now() + impl_->timeout;
  while (out.empty() && std::chrono::steady_clock::now() < deadline) {
    rmw_dds_common::msg::ParticipantEntitiesInfo info;
    fdds::SampleInfo si;
    if (r->take_next_sample(&info, &si) != ReturnCode_t::RETCODE_OK) {
      r->wait_for_unread_message(Duration(0, 100000000));
      continue;
    }
    for (const auto& n : info.node_entities_info_seq())
      if (si.valid_data && n.node_namespace().to_string() == ns && n.node_name().to_string() != "bridge")
        out.push_back(n.node_name().to_string());
  }
  impl_->subscriber->delete_datareader(r);
  if (out.empty())
    throw DdsError(fmt::format("no vehicle announced its nodes (ros_discovery_info) on DDS domain {}, namespace '{}' within {:.1f} s",
                               impl_->options.domain, impl_->options.ns, static_cast<double>(impl_->timeout.count()) / 1000.0));
  return out;
}

std::vector<DdsParam> DdsClient::param_list(const std::string& prefix) {
  std::vector<DdsParam> out;
  for (const auto& node : nodes()) {
    if (!prefix.empty() && prefix.compare(0, std::min(prefix.size(), node.size() + 1), (node + ".").substr(0, prefix.size())) != 0)
      continue;  // the prefix names another instance
    rs::ListParameters_Request lq;
    const auto names =
        impl_->call_in<rs::ListParameters_RequestPubSubType, rs::ListParameters_ResponsePubSubType>(param_ns(node), "list_parameters", lq)
            .result()
            .names();
    for (const auto& d : describe(node, names))
      if (d.name.compare(0, prefix.size(), prefix) == 0) out.push_back(d);
  }
  return out;
}

std::string DdsClient::param_ns(const std::string& node) const { return impl_->options.ns.empty() ? node : impl_->options.ns + "/" + node; }

std::vector<DdsParam> DdsClient::describe(const std::string& node, const std::vector<std::string>& names) {
  rs::GetParameters_Request gq;
  gq.names(names);
  const auto values =
      impl_->call_in<rs::GetParameters_RequestPubSubType, rs::GetParameters_ResponsePubSubType>(param_ns(node), "get_parameters", gq);
  rs::DescribeParameters_Request dq;
  dq.names(names);
  const auto descs = impl_->call_in<rs::DescribeParameters_RequestPubSubType, rs::DescribeParameters_ResponsePubSubType>(
      param_ns(node), "describe_parameters", dq);
  std::vector<DdsParam> out;
  for (std::size_t i = 0; i < names.size() && i < values.values().size() && i < descs.descriptors().size(); ++i) {
    if (values.values()[i].type() == ddsi::kNotSet) continue;  // unknown
    out.push_back(ddsi::from_rcl(node + "." + names[i], values.values()[i], descs.descriptors()[i]));
  }
  return out;
}

DdsParam DdsClient::param_get(const std::string& name) {
  const auto [node, param] = known_node(name);
  auto found = describe(node, {param});
  if (!found.empty()) return found.front();
  std::vector<std::string> known;
  for (const auto& p : param_list(node + ".")) known.push_back(p.name);
  throw DdsError("unknown parameter '" + name + "'" + did_you_mean(name, known));
}

void DdsClient::param_set(const std::string& name, const ParamValue& value) {
  const auto [node, param] = known_node(name);
  rs::SetParameters_Request rq;
  rm::Parameter p;
  p.name(param);
  p.value(ddsi::to_rcl(value));
  rq.parameters({p});
  const auto r = impl_->call_in<rs::SetParameters_RequestPubSubType, rs::SetParameters_ResponsePubSubType>(param_ns(node), "set_parameters",
                                                                                                           rq, "tern param get " + name);
  if (r.results().empty()) throw DdsError("set_parameters: the vehicle answered without a result");
  if (!r.results()[0].successful()) throw DdsError(r.results()[0].reason());
}

}  // namespace tern::core
