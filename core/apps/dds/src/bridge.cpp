// core/apps/dds/src/bridge.cpp: the vehicle side of the DDS bridge.
#include <cmath>
#include <condition_variable>
#include <deque>
#include <future>
#include <map>
#include <mutex>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include "dds_internal.hpp"
#include "config/error.hpp"
#include "file_access.hpp"
#include "flight/host.hpp"
#include "mission_item.hpp"
#include "ros_parameters.hpp"
#include "stamp_clock.hpp"
#include "rosplane_msgs/srv/AddWaypointPubSubTypes.h"
#include "std_srvs/srv/TriggerPubSubTypes.h"
#include "tern/input_file.hpp"
#include "tern/msg/all.hpp"
#include "tern/reflect.hpp"
#include "tern_msgs/srv/ServicesPubSubTypes.h"

namespace tern::core {

using namespace ddsi;

namespace {

struct Writer {
  std::string topic, dds_name;
  const TypeEntry* type = nullptr;
  fdds::DataWriter* writer = nullptr;
  std::shared_ptr<void> sample;
  Nanos interval = 0;
  DdsQos qos = DdsQos::best_effort;
  int depth = 1;
  const OutputBase* last_src = nullptr;
  std::uint64_t last_seq = 0;
  Nanos last_t = 0;
  std::atomic<std::uint64_t> written{0};
};

/// One-line error text of a service failure.
template <class Resp>
Resp failure(const std::string& message) {
  Resp r;
  r.success(false);
  r.message(message);
  return r;
}
template <class Resp>
Resp success(const std::string& message = "") {
  Resp r;
  r.success(true);
  r.message(message);
  return r;
}

}  // namespace

struct DdsBridge::Impl {
  Host& host;
  int observer_id = 0;  // the host's tick observer: tick()
  /// every request is the ground station speaking: the link-loss failsafe's "heard"
  const std::function<void()> heard = [this] { host.ground_link_heard(); };
  DdsOptions options;
  fdds::DomainParticipant* participant = nullptr;
  fdds::Publisher* publisher = nullptr;
  fdds::Subscriber* subscriber = nullptr;
  std::vector<std::unique_ptr<Writer>> writers;  // grows at run time (bridge_topic): under writers_mu
  mutable std::mutex writers_mu;
  std::vector<std::shared_ptr<fdds::DataReaderListener>> servers;
  std::vector<ServiceEndpoint*> endpoints;    // the servers' (answer(): without the wire)
  RosNode bridge_node;                        // "/<ns>/bridge": entities of the bridge itself
  std::unique_ptr<RosParameters> ros_params;  // a ROS 2 node per instance (rcl_interfaces)
  std::unique_ptr<RosGraph> graph;            // ros_discovery_info

  // ROS time (stamp_clock.hpp): the flight's epoch and rt/clock in sim time
  StampClock stamps;
  // what the flight thread last saw (for status and mission print)
  std::atomic<Nanos> flight_time{0};
  std::atomic<int> phase{0};
  std::mutex mu;
  std::optional<msg::WaypointList> waypoints;
  const OutputBase* waypoints_src = nullptr;
  std::uint64_t waypoints_seq = 0;
  // reads of parameter values, run on the flight thread while flying (values change there)
  std::deque<std::shared_ptr<std::packaged_task<void()>>> tasks;
  std::atomic<bool> tasks_pending{false};
  std::atomic<std::uint32_t> edit_id{0};
  // where network requests may read missions and write parameter files
  FileAccess mission_files, param_files;

  Impl(Host& h, const DdsOptions& o)
      : host(h),
        options(o),
        stamps(resolve_time(h.config(), o.time), o.clock_rate),
        mission_files(with_first(h.config().dir, o.mission_dirs)),
        param_files(with_first(h.options().log_dir.value_or(h.config().log.dir), o.param_dirs)) {}
  static std::vector<fs::path> with_first(const fs::path& first, std::vector<fs::path> more) {
    more.insert(more.begin(), first);
    return more;
  }
  ~Impl() {
    delete_participant(participant);  // stops the listener threads before the servers go
  }

  /// Runs fn where parameter values are stable: on the flight thread when flying, here otherwise.
  void on_flight_thread(const std::function<void()>& fn) {
    if (host.flying()) {
      auto task = std::make_shared<std::packaged_task<void()>>(fn);
      auto fut = task->get_future();
      {
        std::lock_guard lk(mu);
        tasks.push_back(task);
        tasks_pending.store(true, std::memory_order_release);
      }
      if (fut.wait_for(std::chrono::seconds(2)) == std::future_status::ready) return fut.get();
      bool removed = false;
      {
        std::lock_guard lk(mu);
        for (auto it = tasks.begin(); it != tasks.end(); ++it)
          if (*it == task) {
            tasks.erase(it);
            removed = true;
            break;
          }
      }
      if (!removed) return fut.get();  // it is running now
    }
    fn();
  }

  void tick(Nanos now) {
    flight_time.store(now, std::memory_order_relaxed);
    stamps.tick(now);
    publish(now);
    remember_phase_and_waypoints();
    run_tasks();
  }

  void publish(Nanos now) {
    std::lock_guard lk(writers_mu);
    for (auto& w : writers) {
      const OutputBase* src = host.topic_source(w->topic);
      if (src == nullptr) continue;
      const std::uint64_t seq = src->sequence();
      if (seq == 0 || (src == w->last_src && seq == w->last_seq)) continue;
      // (a new flight restarts the clock: now < last_t publishes at once)
      if (w->last_src != nullptr && w->interval > 0 && now >= w->last_t && now - w->last_t < w->interval) continue;
      w->last_src = src;
      w->last_seq = seq;
      w->last_t = now;
      Writer& wr = *w;
      w->type->convert(src->data(), w->sample.get(), stamps.epoch(), [&wr] {
        wr.writer->write(wr.sample.get());
        wr.written.fetch_add(1, std::memory_order_relaxed);
      });
    }
  }

  void remember_phase_and_waypoints() {
    if (const OutputBase* ph = host.topic_source("flight_phase");
        ph != nullptr && ph->sequence() > 0 && ph->type().fingerprint == reflect::fingerprint<msg::FlightPhase>())
      phase.store(static_cast<int>(static_cast<const msg::FlightPhase*>(ph->data())->phase), std::memory_order_relaxed);
    if (const OutputBase* wp = host.topic_source("waypoints"); wp != nullptr && wp->sequence() > 0 &&
                                                               wp->type().fingerprint == reflect::fingerprint<msg::WaypointList>() &&
                                                               (wp != waypoints_src || wp->sequence() != waypoints_seq)) {
      waypoints_src = wp;
      waypoints_seq = wp->sequence();
      std::lock_guard lk(mu);
      waypoints = *static_cast<const msg::WaypointList*>(wp->data());
    }
  }

  void run_tasks() {
    if (tasks_pending.load(std::memory_order_acquire)) {
      std::deque<std::shared_ptr<std::packaged_task<void()>>> run;
      {
        std::lock_guard lk(mu);
        run.swap(tasks);
        tasks_pending.store(false, std::memory_order_relaxed);
      }
      for (auto& t : run) (*t)();
    }
  }

  std::string save_params(const std::string& filename, bool overwrite) {
    const fs::path path = param_files.for_writing("param_save", filename, overwrite);
    std::string text;
    on_flight_thread([&] {
      YAML::Emitter y;
      y << YAML::Comment(fmt::format("tern parameters of mission '{}' (saved over DDS)", host.config().name));
      y << YAML::BeginMap;
      std::string current;
      for (const auto& [name, p] : host.parameters()) {
        const std::string inst = name.substr(0, name.find('.'));
        if (inst != current) {
          if (!current.empty()) y << YAML::EndMap << YAML::EndMap;
          current = inst;
          y << YAML::Key << inst << YAML::Value << YAML::BeginMap << YAML::Key << "ros__parameters" << YAML::Value << YAML::BeginMap;
        }
        y << YAML::Key << p->name() << YAML::Value;
        emit_value(y, p->value());
      }
      if (!current.empty()) y << YAML::EndMap << YAML::EndMap;
      y << YAML::EndMap;
      text = std::string(y.c_str()) + "\n";
    });
    FileAccess::write_file("param_save", path, text, overwrite);
    return path.string();
  }

  static void emit_value(YAML::Emitter& y, const ParamValue& v) {
    std::visit(
        [&](const auto& x) {
          using T = std::decay_t<decltype(x)>;
          if constexpr (std::is_same_v<T, std::vector<double>>) {
            y << YAML::Flow << YAML::BeginSeq;
            for (double d : x) y << d;
            y << YAML::EndSeq;
          } else if constexpr (std::is_same_v<T, std::string>) {
            y << YAML::DoubleQuoted << x;
          } else if constexpr (std::is_same_v<T, double>) {
            // a whole number keeps a decimal point so that it reads back as a real
            y << (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 1e15 ? fmt::format("{:.1f}", x) : fmt::format("{}", x));
          } else {
            y << x;
          }
        },
        v);
  }

  msg::MissionEdit new_edit(std::uint8_t op) {
    msg::MissionEdit e;
    e.op = op;
    e.id = edit_id.fetch_add(1) + 1;
    return e;
  }

  /// A DDS writer for tern topic `to.topic` of type `type` (checked by the caller).
  void add_writer(const DdsTopicOptions& to, const TypeEntry* type) {
    auto w = std::make_unique<Writer>();
    w->topic = to.topic;
    w->dds_name = to.name;
    w->type = type;
    fdds::TypeSupport ts(type->make_type());
    if (participant->find_type(ts.get_type_name()).empty()) ts.register_type(participant);
    fdds::Topic* t = participant->create_topic(topic_name(options.ns, to.name), ts.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    const DdsQos q = to.qos.value_or(to.topic == "waypoints" || to.topic == "flight_phase" ? DdsQos::transient_local : DdsQos::best_effort);
    w->qos = q;
    w->depth = to.depth.value_or(default_depth(q));
    if (t != nullptr) w->writer = publisher->create_datawriter(t, writer_qos(q, w->depth));
    if (t == nullptr || w->writer == nullptr) throw DdsError("DDS: cannot create a writer for " + topic_name(options.ns, to.name));
    w->sample = type->make_sample();
    const double rate = to.rate >= 0 ? to.rate : options.rate;
    w->interval = rate > 0 ? static_cast<Nanos>(std::llround(1e9 / rate)) : 0;
    std::lock_guard lk(writers_mu);
    writers.push_back(std::move(w));
  }

  /// bridge_topic: one more topic at run time (telemetry the defaults leave out: truth, imu).
  std::string bridge_topic(const std::string& topic, double rate) {
    if (!std::isfinite(rate) || rate < 0 || rate > 1e6) throw DdsError(fmt::format("bridge_topic: rate {} is outside [0, 1e6] Hz", rate));
    std::vector<std::string> names;
    const Host::TopicInfo* info = nullptr;
    const auto topics = host.topics();
    for (const auto& t : topics) {
      names.push_back(t.name);
      if (t.name == topic) info = &t;
    }
    if (info == nullptr)
      throw DdsError("bridge_topic: no instance publishes topic '" + printable(topic) + "'" +
                     (topic.size() <= kMaxEchoChars ? did_you_mean(topic, names) : ""));
    const TypeEntry* type = find_type(info->type_name);
    if (type == nullptr || type->fingerprint != info->fingerprint)
      throw DdsError("bridge_topic: topic '" + topic + "' carries " + info->type_name + ", which has no DDS type");
    {
      std::lock_guard lk(writers_mu);
      for (const auto& w : writers)
        if (w->dds_name == topic) return topic_name(options.ns, w->dds_name) + " is already published";
    }
    add_writer({topic, topic, rate, std::nullopt, std::nullopt, ""}, type);
    announce();
    host.logger()->info("DDS bridge: now publishing {} ({}) on request", topic_name(options.ns, topic), type->dds_type);
    return topic_name(options.ns, topic) + " " + type->dds_type;
  }

  /// Every service, or only status when the config says read_only (telemetry only).
  void start_services() {
    start_status_service();
    start_bridge_topic_service();
    if (options.read_only) return;
    start_param_services();
    start_mission_services();
    start_mission_item_service();
  }

  /// A tern service (its entities belong to the bridge's ROS node).
  template <class Server>
  void add_server(std::shared_ptr<Server> server) {
    bridge_node.readers.push_back(server->reader()->guid());
    bridge_node.writers.push_back(server->writer()->guid());
    endpoints.push_back(server.get());
    servers.push_back(std::move(server));
  }

  /// ros_discovery_info: the bridge's node (topics, tern's services, parameter events) and one
  /// node per instance (its parameter services).
  void announce() {
    std::vector<RosNode> nodes = ros_params->nodes();
    RosNode b = bridge_node;
    b.writers.push_back(ros_params->events_writer());
    {
      std::lock_guard lk(writers_mu);
      for (const auto& w : writers) b.writers.push_back(w->writer->guid());
    }
    if (const auto* c = stamps.writer()) b.writers.push_back(c->guid());
    nodes.push_back(std::move(b));
    graph->announce(nodes);
  }

  void start_param_services() {
    using namespace tern_msgs::srv;
    const std::string& ns = options.ns;
    auto add = [&](auto server) { add_server(std::move(server)); };
    add(std::make_shared<ServiceServer<ParamSave_RequestPubSubType, ParamSave_ResponsePubSubType>>(
        participant, publisher, subscriber, ns, "param_save", heard, [this](const ParamSave_Request& rq) {
          try {
            return success<ParamSave_Response>(save_params(rq.filename(), rq.overwrite()));
          } catch (const std::exception& e) {
            host.logger()->warn("DDS: {}", e.what());
            return failure<ParamSave_Response>(e.what());
          }
        }));
  }

  void start_mission_services() {
    using namespace tern_msgs::srv;
    const std::string& ns = options.ns;
    auto add = [&](auto server) { add_server(std::move(server)); };
    add(std::make_shared<
        ServiceServer<rosplane_msgs::srv::AddWaypoint_RequestPubSubType, rosplane_msgs::srv::AddWaypoint_ResponsePubSubType>>(
        participant, publisher, subscriber, ns, "add_waypoint", heard, [this](const rosplane_msgs::srv::AddWaypoint_Request& rq) {
          using Resp = rosplane_msgs::srv::AddWaypoint_Response;
          try {
            msg::MissionEdit e = new_edit(msg::MissionEdit::add);
            for (int i = 0; i < 3; ++i) e.waypoint.w[i] = rq.w()[i];
            e.waypoint.lla = rq.lla();
            e.waypoint.chi_d = rq.chi_d();
            e.waypoint.use_chi = rq.use_chi();
            e.waypoint.Va_d = rq.va_d();
            e.set_current_wp = rq.set_current();
            e.publish_now = rq.publish_now();
            if (!e.waypoint.w.allFinite() || !std::isfinite(e.waypoint.chi_d) || !std::isfinite(e.waypoint.Va_d) || e.waypoint.Va_d <= 0)
              return failure<Resp>("add_waypoint: w, chi_d must be finite and va_d > 0");
            host.edit_mission(e);
            return success<Resp>(fmt::format("waypoint added (edit #{})", e.id));
          } catch (const std::exception& e) {
            return failure<Resp>(e.what());
          }
        }));
    using std_srvs::srv::Trigger_Request, std_srvs::srv::Trigger_Response;
    using TriggerServer = ServiceServer<std_srvs::srv::Trigger_RequestPubSubType, std_srvs::srv::Trigger_ResponsePubSubType>;
    add(std::make_shared<TriggerServer>(participant, publisher, subscriber, ns, "clear_waypoints", heard, [this](const Trigger_Request&) {
      try {
        msg::MissionEdit e = new_edit(msg::MissionEdit::clear);
        host.edit_mission(e);
        return success<Trigger_Response>(fmt::format("waypoints cleared (edit #{})", e.id));
      } catch (const std::exception& e) {
        return failure<Trigger_Response>(e.what());
      }
    }));
    add(std::make_shared<TriggerServer>(participant, publisher, subscriber, ns, "print_waypoints", heard, [this](const Trigger_Request&) {
      std::lock_guard lk(mu);
      if (!waypoints) return failure<Trigger_Response>("no waypoint list published yet (topic 'waypoints')");
      std::string s = fmt::format("{} waypoints (revision {}{}{})\n", waypoints->count, waypoints->revision,
                                  waypoints->loop ? ", loop" : "", waypoints->loops > 0 ? fmt::format(" {} times", waypoints->loops) : "");
      for (std::uint32_t i = 0; i < waypoints->count && i < msg::WaypointList::kCapacity; ++i) {
        const auto& w = waypoints->items[i];
        s += fmt::format("{:3d}: w [{:.3f}, {:.3f}, {:.3f}]{} Va_d {:.2f} m/s chi_d {:.4f} rad{}{}\n", i, w.w.x(), w.w.y(), w.w.z(),
                         w.lla ? " (lla)" : "", w.Va_d, w.chi_d, w.use_chi ? " (dubins)" : "", item_text(w));
      }
      return success<Trigger_Response>(s);
    }));
    add(std::make_shared<TriggerServer>(participant, publisher, subscriber, ns, "go_around", heard, [this](const Trigger_Request&) {
      const auto ph = static_cast<msg::Phase>(phase.load(std::memory_order_relaxed));
      if (!host.flying() || !msg::on_final(ph))
        return failure<Trigger_Response>(
            fmt::format("go_around: no landing to go around from ({}phase {}): taken on the final approach "
                        "and in the flare",
                        host.flying() ? "" : "not flying, ", msg::phase_name(ph)));
      try {
        host.go_around("DDS go_around");
        return success<Trigger_Response>(
            fmt::format("go-around commanded in the {} (the vehicle's log says when it is taken)", msg::phase_name(ph)));
      } catch (const std::exception& e) {
        return failure<Trigger_Response>(e.what());
      }
    }));
    add(std::make_shared<ServiceServer<MissionLoad_RequestPubSubType, MissionLoad_ResponsePubSubType>>(
        participant, publisher, subscriber, ns, "load_mission_from_file", heard, [this](const MissionLoad_Request& rq) {
          using Resp = MissionLoad_Response;
          try {
            const fs::path p = mission_files.for_reading("load_mission_from_file", rq.filename());
            msg::MissionEdit e = new_edit(msg::MissionEdit::load_file);
            const std::string path = p.string();  // (string() makes a new string at each call)
            if (path.size() >= e.file.size()) return failure<Resp>("load_mission_from_file: path too long: " + path);
            std::copy(path.begin(), path.end(), e.file.begin());
            host.edit_mission(e);
            return success<Resp>(fmt::format("loading {} (edit #{})", p.string(), e.id));
          } catch (const std::exception& e) {
            host.logger()->warn("DDS: {}", e.what());
            return failure<Resp>(e.what());
          }
        }));
  }

  /// add_mission_item: a mission item with its type (a land item, a loiter), as add_waypoint.
  void start_mission_item_service() {
    using namespace tern_msgs::srv;
    add_server(std::make_shared<ServiceServer<MissionAddItem_RequestPubSubType, MissionAddItem_ResponsePubSubType>>(
        participant, publisher, subscriber, options.ns, "add_mission_item", heard, [this](const MissionAddItem_Request& rq) {
          using Resp = MissionAddItem_Response;
          try {
            msg::MissionEdit e = new_edit(msg::MissionEdit::add);
            e.waypoint = from_mission_item(rq.item());
            e.set_current_wp = rq.set_current();
            e.publish_now = rq.publish_now();
            if (e.waypoint.type > msg::Waypoint::land)
              return failure<Resp>(
                  fmt::format("add_mission_item: type {} is not a mission item type (0 waypoint, 1 loiter, "
                              "2 return_home, 3 land)",
                              static_cast<int>(e.waypoint.type)));
            host.edit_mission(e);
            return success<Resp>(
                fmt::format("{} added (edit #{}): the vehicle's log says if the planner refused it", item_name(e.waypoint), e.id));
          } catch (const std::exception& e) {
            return failure<Resp>(e.what());
          }
        }));
  }

  void start_bridge_topic_service() {
    using namespace tern_msgs::srv;
    add_server(std::make_shared<ServiceServer<BridgeTopic_RequestPubSubType, BridgeTopic_ResponsePubSubType>>(
        participant, publisher, subscriber, options.ns, "bridge_topic", heard, [this](const BridgeTopic_Request& rq) {
          try {
            return success<BridgeTopic_Response>(bridge_topic(rq.topic(), rq.rate()));
          } catch (const std::exception& e) {
            return failure<BridgeTopic_Response>(e.what());
          }
        }));
  }

  void start_status_service() {
    using namespace tern_msgs::srv;
    const std::string& ns = options.ns;
    auto add = [&](auto server) { add_server(std::move(server)); };
    add(std::make_shared<ServiceServer<Status_RequestPubSubType, Status_ResponsePubSubType>>(
        participant, publisher, subscriber, ns, "status", heard, [this](const Status_Request&) {
          Status_Response r;
          r.mission(host.config().name);
          r.config_file(host.config().file.string());
          r.flying(host.flying());
          const Nanos t = flight_time.load();
          r.flight_time().sec(static_cast<std::int32_t>(t / 1000000000));
          r.flight_time().nanosec(static_cast<std::uint32_t>(t % 1000000000));
          r.phase(static_cast<std::uint8_t>(phase.load()));
          r.phase_name(std::string(msg::phase_name(static_cast<msg::Phase>(phase.load()))));
          r.flights(static_cast<std::uint32_t>(host.flights()));
          std::lock_guard lk(writers_mu);
          for (const auto& w : writers) {
            r.topics().push_back(topic_name(options.ns, w->dds_name));
            r.types().push_back(w->type->dds_type);
            r.qos().push_back(static_cast<std::uint8_t>(w->qos));
          }
          return r;
        }));
  }
};

DdsBridge::DdsBridge(Host& host, const DdsOptions& options) : impl_(std::make_unique<Impl>(host, options)) {
  Impl& m = *impl_;
  const auto topics = host.topics();
  std::vector<std::string> names;
  for (const auto& t : topics) names.push_back(t.name);
  const fs::path& file = host.config().file;
  // check every bridged topic before opening any socket
  std::vector<std::pair<const DdsTopicOptions*, const TypeEntry*>> plan;
  for (const auto& to : options.topics) {
    const Host::TopicInfo* info = nullptr;
    for (const auto& t : topics)
      if (t.name == to.topic) info = &t;
    if (info == nullptr) {
      // the default set bridges what exists; a topic the config names must exist
      if (!options.topics_from_config) continue;
      throw ConfigError(file.string() + ": dds.topics: no instance publishes topic '" + to.topic + "'" + did_you_mean(to.topic, names));
    }
    const TypeEntry* type = find_type(info->type_name, to.type);
    if (type == nullptr || type->fingerprint != info->fingerprint)
      throw ConfigError(file.string() + ": dds.topics: topic '" + to.topic + "' carries " + info->type_name + ", which has no DDS type" +
                        (to.type.empty() ? std::string() : " " + to.type));
    plan.emplace_back(&to, type);
  }
  m.participant = make_participant(options, "tern/" + (options.ns.empty() ? host.config().name : options.ns));
  m.publisher = m.participant->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  m.subscriber = m.participant->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  if (m.publisher == nullptr || m.subscriber == nullptr) throw DdsError("DDS: cannot create a publisher/subscriber");
  for (const auto& [to, type] : plan) m.add_writer(*to, type);
  m.stamps.start(m.participant, m.publisher);
  m.bridge_node.ns = "/" + options.ns;
  m.bridge_node.name = "bridge";
  // the bridge's own copy of the options: RosParameters keeps a reference (the caller's may be a temporary)
  m.ros_params = std::make_unique<RosParameters>(host, m.options, m.participant, m.publisher, m.subscriber,
                                                 [impl = &m](const std::function<void()>& fn) { impl->on_flight_thread(fn); });
  m.graph = std::make_unique<RosGraph>(m.participant, m.publisher);
  // after ros_params and graph: a bridge_topic request may arrive at once, and announce() uses both
  m.start_services();
  m.announce();
  m.observer_id = host.add_tick_observer([impl = impl_.get()](Nanos now) { impl->tick(now); });
  std::string ifs;
  for (const auto& i : options.interfaces) ifs += (ifs.empty() ? "" : ", ") + i;
  host.logger()->info("DDS bridge: domain {}, namespace '{}', interfaces {}{}, {} topics, services under rq/{}", options.domain, options.ns,
                      ifs, options.multicast ? " (multicast)" : "", m.writers.size(), options.ns);
  host.logger()->info("DDS bridge: header stamps in {}", m.stamps.describe());
  if (options.read_only) host.logger()->info("DDS bridge: read_only: telemetry and status only");
  if (options.security)
    host.logger()->info("DDS bridge: DDS Security on: enclave '{}' of keystore {} (authenticated, access-controlled, encrypted)",
                        options.security->enclave, options.security->keystore.string());
}

DdsBridge::~DdsBridge() { impl_->host.remove_tick_observer(impl_->observer_id); }

std::vector<DdsBridge::Published> DdsBridge::published() const {
  std::lock_guard lk(impl_->writers_mu);
  std::vector<Published> out;
  for (const auto& w : impl_->writers)
    out.push_back({w->topic, topic_name(impl_->options.ns, w->dds_name), w->type->dds_type, w->qos, w->depth});
  return out;
}

std::vector<std::string> DdsBridge::services() const {
  std::vector<std::string> out;
  for (const auto* e : impl_->endpoints) out.push_back(e->service_name());
  for (const auto* e : impl_->ros_params->endpoints()) out.push_back(e->service_name());
  std::sort(out.begin(), out.end());
  return out;
}

std::optional<std::vector<std::uint8_t>> DdsBridge::answer(const std::string& service, const std::vector<std::uint8_t>& request) {
  std::vector<ServiceEndpoint*> all = impl_->ros_params->endpoints();
  all.insert(all.end(), impl_->endpoints.begin(), impl_->endpoints.end());
  for (auto* e : all)
    if (e->service_name() == service) return e->answer(request);
  const std::string hint = service.size() <= kMaxEchoChars ? did_you_mean(service, services()) : "";  // (a distance per name)
  throw DdsError("DDS: no service '" + printable(service) + "' on this vehicle" + hint);
}

std::uint64_t DdsBridge::samples_written(const std::string& topic) const {
  std::lock_guard lk(impl_->writers_mu);
  for (const auto& w : impl_->writers)
    if (w->topic == topic) return w->written.load();
  return 0;
}

}  // namespace tern::core
