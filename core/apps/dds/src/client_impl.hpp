// core/apps/dds/src/client_impl.hpp: the state of a DdsClient (private to core/apps/dds): its participant
// and one ServiceClient per service it has called.
#pragma once

#include <map>
#include <optional>

#include <fmt/format.h>

#include "dds_internal.hpp"

namespace tern::core {

using namespace ddsi;

struct DdsClient::Impl {
  DdsOptions options;
  std::chrono::milliseconds timeout;
  fdds::DomainParticipant* participant = nullptr;
  fdds::Publisher* publisher = nullptr;
  fdds::Subscriber* subscriber = nullptr;
  std::map<std::string, std::shared_ptr<void>> clients;  // ns/service -> ServiceClient<...>
  std::optional<std::uint64_t> next_id;                  // set_request_id()

  ~Impl() { delete_participant(participant); }

  /// `check`: how to see whether a change was applied, for the time-out message ("" for a read).
  template <class ReqPS, class RespPS>
  typename RespPS::type call(const std::string& service, const typename ReqPS::type& req, const std::string& check = "") {
    return call_in<ReqPS, RespPS>(options.ns, service, req, check);
  }
  /// The service `service` of the node (or vehicle namespace) `ns` ("tern/slc").
  template <class ReqPS, class RespPS>
  typename RespPS::type call_in(const std::string& ns, const std::string& service, const typename ReqPS::type& req,
                                const std::string& check = "") {
    auto& slot = clients[ns + "/" + service];
    if (!slot) slot = std::make_shared<ServiceClient<ReqPS, RespPS>>(participant, publisher, subscriber, ns, service);
    auto* c = static_cast<ServiceClient<ReqPS, RespPS>*>(slot.get());
    typename RespPS::type resp;
    const std::uint64_t id = next_id.value_or(new_request_id());
    next_id.reset();
    const CallResult r = c->call(req, resp, timeout, id);
    if (r == CallResult::answered) return resp;
    std::string msg = fmt::format("no vehicle answered '{}' on DDS domain {}, namespace '{}' within {:.1f} s", service, options.domain,
                                  options.ns, static_cast<double>(timeout.count()) / 1000.0);
    if (r == CallResult::no_reply && !check.empty())
      msg += fmt::format(
          ": the request was sent and may have been applied; check with `{}`, or repeat it with --request-id {} "
          "(the vehicle applies one id once)",
          check, id);
    throw DdsError(msg);
  }
};

}  // namespace tern::core
