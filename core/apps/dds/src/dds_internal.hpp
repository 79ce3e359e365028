// core/apps/dds/src/dds_internal.hpp: Fast DDS side of the bridge (private to core/apps/dds).
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <fastrtps/rtps/common/WriteParams.h>

#include "answered_requests.hpp"
#include "dds_bridge.hpp"
#include "decoding_type.hpp"
#include "matched_readers.hpp"
#include "tern/time.hpp"

namespace tern::core::ddsi {

namespace fdds = eprosima::fastdds::dds;
using Duration = eprosima::fastrtps::Duration_t;

/// A participant honouring the network options: built-in transports off, one UDPv4 transport
/// restricted to options.interfaces, initial peers options.peers, no multicast unless
/// options.multicast. Throws DdsError.
fdds::DomainParticipant* make_participant(const DdsOptions& options, const std::string& name);
/// Deletes every entity of the participant, then the participant.
void delete_participant(fdds::DomainParticipant* p);

/// `depth` <= 0: default_depth(q).
fdds::DataWriterQos writer_qos(DdsQos q, int depth = 0);
fdds::DataReaderQos reader_qos(DdsQos q);
fdds::DataWriterQos service_writer_qos();
fdds::DataReaderQos service_reader_qos();

/// "rt/<ns>/<name>" ("rt/<name>" for an empty namespace).
std::string topic_name(const std::string& ns, const std::string& name);
/// "rq/<ns>/<service>Request" and "rr/<ns>/<service>Reply".
std::string request_topic(const std::string& ns, const std::string& service);
std::string reply_topic(const std::string& ns, const std::string& service);

/// A tern message type and its DDS counterpart.
struct TypeEntry {
  std::string_view tern_type;  ///< e.g. "tern/State"
  std::uint64_t fingerprint;   ///< of the tern struct
  std::function<fdds::TopicDataType*()> make_type;
  std::function<std::shared_ptr<void>()> make_sample;
  /// tern message -> DDS sample(s): fills `sample` and calls `write` once per sample (a waypoint
  /// list as ROSplane's waypoint_path: a clear, then one sample per waypoint). header.stamp =
  /// the message's stamp (flight time, ns) + `epoch` (ROS time of flight time 0: 0 in sim time).
  std::function<void(const void* tern_msg, void* sample, Nanos epoch, const std::function<void()>& write)> convert;
  /// DDS sample -> "field: value" lines
  std::function<std::string(const void* sample)> render;
  std::string dds_type;  ///< e.g. "rosplane_msgs::msg::dds_::State_"
  std::string ros_type;  ///< e.g. "rosplane_msgs/msg/State"
};
/// nullptr when the tern type has no DDS counterpart; `ros_type` ("sensor_msgs/msg/Imu") picks one
/// of several (empty: the first, tern's own where tern has one).
const TypeEntry* find_type(std::string_view tern_type, std::string_view ros_type = "");
const TypeEntry* find_dds_type(std::string_view dds_type);
const std::vector<TypeEntry>& all_types();

/// Polls `cond` every 2 ms until it holds or `timeout` passes.
bool wait_until(const std::function<bool()>& cond, std::chrono::milliseconds timeout);

/// Registers type T (a fastddsgen PubSubType, as Decoding<T>: bytes Fast CDR refuses are dropped)
/// once on the participant; returns its topic.
template <class PubSub>
fdds::Topic* make_topic(fdds::DomainParticipant* p, const std::string& name) {
  fdds::TypeSupport ts(new Decoding<PubSub>());
  const std::string tname = ts.get_type_name();
  if (p->find_type(tname).empty()) ts.register_type(p);
  if (auto* d = p->find_topic(name, Duration(0, 0))) return d;
  fdds::Topic* t = p->create_topic(name, tname, fdds::TOPIC_QOS_DEFAULT);
  if (t == nullptr) throw DdsError("DDS: cannot create topic '" + name + "' of type " + tname);
  return t;
}

/// A served service's path from a request's bytes to its reply's, without the wire
/// (DdsBridge::answer: tests and tests/fuzz/fuzz_dds_request).
class ServiceEndpoint {
 public:
  virtual ~ServiceEndpoint() = default;
  /// The service's ROS name: "<ns>/<service>" ("tern/add_waypoint", "tern/filter/set_parameters").
  virtual const std::string& service_name() const = 0;
  /// `request`: the serialized request (CDR, its 4-byte encapsulation first). The reply serialized
  /// the same way, or nullopt when the bytes do not decode (the wire drops such a sample).
  virtual std::optional<std::vector<std::uint8_t>> answer(const std::vector<std::uint8_t>& request) = 0;
};

/// Server side of one service: answers each request on a Fast DDS thread with `handler`, the
/// reply carrying the request's sample identity as related_sample_identity. `on_request` (may be
/// empty) is called first, for every request (the host's ground_link_heard()).
template <class ReqPS, class RespPS>
class ServiceServer final : public fdds::DataReaderListener, public ServiceEndpoint {
 public:
  using Req = typename ReqPS::type;
  using Resp = typename RespPS::type;
  ServiceServer(fdds::DomainParticipant* p, fdds::Publisher* pub, fdds::Subscriber* sub, const std::string& ns, const std::string& service,
                std::function<void()> on_request, std::function<Resp(const Req&)> handler)
      : name_(ns.empty() ? service : ns + "/" + service), on_request_(std::move(on_request)), handler_(std::move(handler)) {
    writer_ = pub->create_datawriter(make_topic<RespPS>(p, reply_topic(ns, service)), service_writer_qos(), &matched_,
                                     fdds::StatusMask::publication_matched());
    reader_ = sub->create_datareader(make_topic<ReqPS>(p, request_topic(ns, service)), service_reader_qos(), this);
    if (writer_ == nullptr || reader_ == nullptr) throw DdsError("DDS: cannot create service '" + service + "'");
  }
  void on_data_available(fdds::DataReader* reader) override {
    std::lock_guard lk(mu_);  // a repeated id arriving while its first copy is handled waits for it
    Req req;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&req, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      if (on_request_) on_request_();
      const std::optional<std::uint64_t> id = request_id(info.related_sample_identity);
      const Resp* first = id ? answered_.find(*id) : nullptr;
      const Resp resp = first != nullptr ? *first : handler_(req);
      if (id && first == nullptr) answered_.remember(*id, resp);
      reply(info, resp);
    }
  }
  const std::string& service_name() const override { return name_; }
  std::optional<std::vector<std::uint8_t>> answer(const std::vector<std::uint8_t>& request) override {
    eprosima::fastrtps::rtps::SerializedPayload_t in(static_cast<std::uint32_t>(request.size()));
    std::copy(request.begin(), request.end(), in.data);
    in.length = static_cast<std::uint32_t>(request.size());
    Req req;
    if (!Decoding<ReqPS>().deserialize(&in, &req)) return std::nullopt;
    std::lock_guard lk(mu_);
    if (on_request_) on_request_();
    Resp resp = handler_(req);
    RespPS type;
    eprosima::fastrtps::rtps::SerializedPayload_t out(type.getSerializedSizeProvider(&resp)());
    if (!type.serialize(&resp, &out)) throw DdsError("DDS: service '" + name_ + "': its reply does not serialize");
    return std::vector<std::uint8_t>(out.data, out.data + out.length);
  }
  /// The number of request ids remembered.
  std::size_t remembered() const { return answered_.size(); }
  fdds::DataReader* reader() const { return reader_; }
  fdds::DataWriter* writer() const { return writer_; }

 private:
  void reply(const fdds::SampleInfo& info, const Resp& resp) {
    // the client's reply reader is discovered at about the time its request writer is: give
    // the reply writer time to match it (a volatile reply to an unmatched reader is lost)
    matched_.wait_for(info.related_sample_identity.writer_guid(), std::chrono::seconds(5));
    // as rmw_fastrtps (rmw_send_response): a client that names its reply reader
    // (related_sample_identity's writer GUID) gets the reply under that GUID, with its request's
    // sequence number
    eprosima::fastrtps::rtps::SampleIdentity sid = info.sample_identity;
    if (info.related_sample_identity.writer_guid() != eprosima::fastrtps::rtps::GUID_t::unknown())
      sid.writer_guid(info.related_sample_identity.writer_guid());
    eprosima::fastrtps::rtps::WriteParams wp;
    wp.related_sample_identity(sid);
    writer_->write(const_cast<Resp*>(&resp), wp);
  }

  std::string name_;
  std::function<void()> on_request_;
  std::function<Resp(const Req&)> handler_;
  fdds::DataWriter* writer_ = nullptr;
  fdds::DataReader* reader_ = nullptr;
  std::mutex mu_;
  AnsweredRequests<Resp> answered_;
  MatchedReaders matched_;
};

/// How a service call ended.
enum class CallResult {
  answered,
  no_server,  ///< no vehicle's service matched within the time-out: nothing was sent
  no_reply,   ///< sent, but no reply within the time-out: the vehicle may have applied it
};

/// A fresh request id (1 .. 2^62-1), random so that ids from different client processes differ.
inline std::uint64_t new_request_id() {
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  return (rng() >> 2) | 1;
}

/// Client side of one service (not thread-safe: one call at a time).
template <class ReqPS, class RespPS>
class ServiceClient {
 public:
  using Req = typename ReqPS::type;
  using Resp = typename RespPS::type;
  ServiceClient(fdds::DomainParticipant* p, fdds::Publisher* pub, fdds::Subscriber* sub, const std::string& ns, const std::string& service)
      : service_(service) {
    writer_ = pub->create_datawriter(make_topic<ReqPS>(p, request_topic(ns, service)), service_writer_qos());
    reader_ = sub->create_datareader(make_topic<RespPS>(p, reply_topic(ns, service)), service_reader_qos());
    if (writer_ == nullptr || reader_ == nullptr) throw DdsError("DDS: cannot create client of '" + service + "'");
  }
  /// Waits for the server, sends with request id `id` (answered_requests.hpp), waits for the
  /// matching reply; without one after kResendInterval sends the request again under the same id
  /// (the server applies an id once and answers a repeat with the first answer): a reply written
  /// before the server's reply writer had matched this client's reader is lost, and discovery
  /// on a loaded machine can take longer than the server waits for that match.
  CallResult call(const Req& req, Resp& resp, std::chrono::milliseconds timeout, std::uint64_t id) {
    const auto t0 = std::chrono::steady_clock::now();
    const bool matched = wait_until(
        [&] {
          fdds::PublicationMatchedStatus ps;
          fdds::SubscriptionMatchedStatus ss;
          writer_->get_publication_matched_status(ps);
          reader_->get_subscription_matched_status(ss);
          return ps.current_count > 0 && ss.current_count > 0;
        },
        timeout);
    if (!matched) return CallResult::no_server;
    // the request names this client's reply reader (rmw_fastrtps convention) and carries the
    // request id; the reply comes back with related_sample_identity = (reader GUID, request
    // sequence number)
    std::vector<eprosima::fastrtps::rtps::SequenceNumber_t> sent;  // each copy's sequence number: a reply names one
    auto send = [&] {
      eprosima::fastrtps::rtps::WriteParams wp;
      wp.related_sample_identity().writer_guid(reader_->guid());
      wp.related_sample_identity().sequence_number(eprosima::fastrtps::rtps::SequenceNumber_t(id));
      if (!writer_->write(const_cast<Req*>(&req), wp)) return false;
      sent.push_back(wp.sample_identity().sequence_number());
      return true;
    };
    if (!send()) return CallResult::no_server;
    auto last_send = std::chrono::steady_clock::now();
    for (;;) {
      const auto now = std::chrono::steady_clock::now();
      const auto left = timeout - std::chrono::duration_cast<std::chrono::milliseconds>(now - t0);
      if (left.count() <= 0) return CallResult::no_reply;
      fdds::SampleInfo info;
      if (reader_->take_next_sample(&resp, &info) == ReturnCode_t::RETCODE_OK) {
        const auto seq = info.related_sample_identity.sequence_number();
        if (info.valid_data && info.related_sample_identity.writer_guid() == reader_->guid() &&
            std::find(sent.begin(), sent.end(), seq) != sent.end())
          return CallResult::answered;
        continue;
      }
      if (now - last_send >= kResendInterval && send()) last_send = now;
      reader_->wait_for_unread_message(Duration(0, static_cast<std::uint32_t>(std::min<long>(left.count(), 100) * 1000000)));
    }
  }
  static constexpr std::chrono::seconds kResendInterval{3};

 private:
  std::string service_;
  fdds::DataWriter* writer_ = nullptr;
  fdds::DataReader* reader_ = nullptr;
};

}  // namespace tern::core::ddsi
