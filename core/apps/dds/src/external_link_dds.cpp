// The DDS endpoints of an external instance (external_link_dds.hpp, core/host/runners/external_link.hpp).
//
// Inputs are converted by the bridge's tern -> ROS 2 conversions (convert.cpp, find_type) and
// stamped with the tick's sim time. The one output binding, rosflight_msgs/msg/Command -> tern
// actuators, follows ROSplane's controller and ROSflight's fixed-wing mixer:
//   - ROSplane (rosplane/src/controller/controller_ros.cpp, actuator_controls_publish()) writes
//     mode MODE_PASS_THROUGH, ignore 0, u[0] = delta_t, u[3] = delta_a, u[4] = delta_e,
//     u[5] = delta_r, the surfaces in rad times pwm_rad_a/e/r (1.0 by default: radians);
//   - ROSflight's fixed-wing mixer (rosflight_firmware include/mixer.h, fixedwing_mixing) sends
//     u[3] (Q_x) to servo 0, u[4] (Q_y) to servo 1, u[5] (Q_z) to servo 2 and u[0] (F_x) to the
//     motor on output 4, unreversed unless REV_AILERON/REV_ELEVATOR/REV_RUDDER (src/mixer.cpp
//     mix_fixedwing(); param.cpp: default 0);
//   - rosflight_sim (fixedwing_forces_and_moments.cpp) applies them as delta_a, delta_e, delta_r
//     with C_m_delta_e < 0, C_ell_delta_a > 0, C_n_delta_r < 0 (anaconda_dynamics.yaml): the
//     uavbook's signs, which are tern's (msg::Actuators): no sign change.
// So delta_t = u[0], delta_a = u[3], delta_e = u[4], delta_r = u[5] (rad). A value whose IGNORE
// bit is set keeps its previous command. Other modes (rates, angles) are not actuator commands:
// take() throws, and the phase router engages the fallback.
#include "external_link_dds.hpp"

#include <condition_variable>
#include <deque>

#include "dds_internal.hpp"
#include "runners/external_link.hpp"
#include "rosflight_msgs/msg/CommandPubSubTypes.h"
#include "rosplane_msgs/msg/ControllerCommandsPubSubTypes.h"
#include "rosplane_msgs/msg/StatePubSubTypes.h"
#include "tern/msg/control.hpp"

namespace tern::core {

namespace {

using namespace ddsi;

builtin_interfaces::msg::Time ros_time(Nanos t) {
  builtin_interfaces::msg::Time r;
  r.sec(static_cast<std::int32_t>(t / 1'000'000'000));
  r.nanosec(static_cast<std::uint32_t>(t % 1'000'000'000));
  return r;
}

Nanos to_nanos(const builtin_interfaces::msg::Time& t) { return static_cast<Nanos>(t.sec()) * 1'000'000'000 + t.nanosec(); }

void set_stamp(std::string_view ros_type, void* sample, Nanos t) {
  if (ros_type == "rosplane_msgs/msg/State")
    static_cast<rosplane_msgs::msg::State*>(sample)->header().stamp(ros_time(t));
  else if (ros_type == "rosplane_msgs/msg/ControllerCommands")
    static_cast<rosplane_msgs::msg::ControllerCommands*>(sample)->header().stamp(ros_time(t));
  else
    throw std::logic_error("external module: no stamp for " + std::string(ros_type));
}

// rosflight Command (pass-through) -> tern actuators, on top of the previous command (see above).
msg::Actuators to_actuators(const rosflight_msgs::msg::Command& c, const msg::Actuators& previous, Nanos stamp) {
  if (c.mode() != rosflight_msgs::msg::Command_Constants::MODE_PASS_THROUGH)
    throw std::runtime_error("rosflight_msgs/Command mode " + std::to_string(c.mode()) +
                             " is not MODE_PASS_THROUGH (0): not surface and throttle commands");
  msg::Actuators a = previous;
  const auto use = [&](int k, double& out) {
    if ((c.ignore() & (1u << k)) == 0) out = static_cast<double>(c.u()[k]);
  };
  use(0, a.delta_t);
  use(3, a.delta_a);
  use(4, a.delta_e);
  use(5, a.delta_r);
  a.stamp = stamp;
  return a;
}

struct Writer {
  fdds::DataWriter* writer = nullptr;
  const TypeEntry* type = nullptr;
  std::shared_ptr<void> sample;
  std::string_view ros_type;
};

// A Command reader: the listener wakes take() when samples arrive.
class CommandReader final : public fdds::DataReaderListener {
 public:
  void on_data_available(fdds::DataReader*) override {
    std::lock_guard lk(mu);
    arrived = true;
    cv.notify_all();
  }
  fdds::DataReader* reader = nullptr;
  std::mutex mu;
  std::condition_variable cv;
  bool arrived = false;
  std::deque<rosflight_msgs::msg::Command> pending;  // taken, stamped later than asked for so far
  msg::Actuators last{};
};

class DdsExternalLink final : public ExternalLink {
 public:
  DdsExternalLink(const ExternalSpec& spec, const MissionConfig& config) {
    const DdsOptions o = parse_dds_options(config.dds, config.file);
    participant_ = make_participant(o, "tern_external_" + spec.instance);
    pub_ = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    sub_ = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    if (pub_ == nullptr || sub_ == nullptr) throw DdsError("DDS: cannot create the publisher or subscriber");
    for (const auto& t : spec.inputs) add_writer(spec.dds_name(t), t.binding);
    for (const auto& t : spec.outputs) add_reader(spec.dds_name(t), t.binding);
  }
  ~DdsExternalLink() override { delete_participant(participant_); }

  std::vector<std::string> wait_matched(std::chrono::milliseconds timeout) override {
    std::vector<std::string> missing;
    wait_until(
        [&] {
          missing.clear();
          for (const auto& w : writers_) {
            fdds::PublicationMatchedStatus s;
            w.writer->get_publication_matched_status(s);
            if (s.current_count == 0) missing.push_back(w.writer->get_topic()->get_name());
          }
          for (const auto& r : readers_) {
            fdds::SubscriptionMatchedStatus s;
            r->reader->get_subscription_matched_status(s);
            if (s.current_count == 0) missing.push_back(r->reader->get_topicdescription()->get_name());
          }
          return missing.empty();
        },
        timeout);
    return missing;
  }

  void publish(std::size_t i, const void* tern_msg, Nanos stamp) override {
    Writer& w = writers_.at(i);
    // epoch 0: sim time; then the tick's time as the stamp, whatever the message's own
    w.type->convert(tern_msg, w.sample.get(), 0, [&] {
      set_stamp(w.ros_type, w.sample.get(), stamp);
      w.writer->write(w.sample.get());
    });
  }

  bool take(std::size_t o, Nanos stamp, void* tern_msg, std::chrono::microseconds timeout) override {
    CommandReader& r = *readers_.at(o);
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      {
        std::lock_guard lk(r.mu);
        r.arrived = false;
      }
      // taken outside the lock: Fast DDS may hold the reader's own lock while calling the listener
      rosflight_msgs::msg::Command c;
      fdds::SampleInfo info;
      while (r.reader->take_next_sample(&c, &info) == ReturnCode_t::RETCODE_OK)
        if (info.valid_data) r.pending.push_back(c);
      while (!r.pending.empty() && to_nanos(r.pending.front().header().stamp()) < stamp) r.pending.pop_front();  // late
      if (!r.pending.empty() && to_nanos(r.pending.front().header().stamp()) == stamp) {
        r.last = to_actuators(r.pending.front(), r.last, stamp);
        r.pending.pop_front();
        *static_cast<msg::Actuators*>(tern_msg) = r.last;
        return true;
      }
      std::unique_lock lk(r.mu);
      if (!r.cv.wait_until(lk, deadline, [&] { return r.arrived; })) return false;
    }
  }

  bool take_latest(std::size_t o, Nanos stamp, void* tern_msg) override {
    CommandReader& r = *readers_.at(o);
    rosflight_msgs::msg::Command c;
    fdds::SampleInfo info;
    bool any = false;
    while (r.reader->take_next_sample(&c, &info) == ReturnCode_t::RETCODE_OK)
      if (info.valid_data) {
        r.pending.clear();  // newer than anything held back
        r.pending.push_back(c);
        any = true;
      }
    if (!any && r.pending.empty()) return false;
    r.last = to_actuators(r.pending.back(), r.last, stamp);
    r.pending.clear();
    *static_cast<msg::Actuators*>(tern_msg) = r.last;
    return true;
  }

 private:
  void add_writer(const std::string& name, const ExternalBinding* b) {
    Writer w;
    w.type = find_type(b->tern_type, b->ros_type);
    if (w.type == nullptr) throw DdsError("DDS: no conversion for " + std::string(b->tern_type));
    fdds::TypeSupport ts(w.type->make_type());
    if (participant_->find_type(ts.get_type_name()).empty()) ts.register_type(participant_);
    fdds::Topic* topic = participant_->find_topic(name, Duration(0, 0));
    if (topic == nullptr) topic = participant_->create_topic(name, ts.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    w.writer = topic ? pub_->create_datawriter(topic, writer_qos(DdsQos::reliable)) : nullptr;
    if (w.writer == nullptr) throw DdsError("DDS: cannot create a writer on '" + name + "'");
    w.sample = w.type->make_sample();
    w.ros_type = b->ros_type;
    writers_.push_back(std::move(w));
  }
  void add_reader(const std::string& name, const ExternalBinding* b) {
    if (b->ros_type != "rosflight_msgs/msg/Command") throw std::logic_error("external module: no reader for " + std::string(b->ros_type));
    auto r = std::make_unique<CommandReader>();
    r->reader = sub_->create_datareader(make_topic<rosflight_msgs::msg::CommandPubSubType>(participant_, name),
                                        reader_qos(DdsQos::reliable), r.get());
    if (r->reader == nullptr) throw DdsError("DDS: cannot create a reader on '" + name + "'");
    readers_.push_back(std::move(r));
  }

  fdds::DomainParticipant* participant_ = nullptr;
  fdds::Publisher* pub_ = nullptr;
  fdds::Subscriber* sub_ = nullptr;
  std::vector<Writer> writers_;
  std::vector<std::unique_ptr<CommandReader>> readers_;
};

}  // namespace

void register_dds_external_links() {
  set_external_link_factory([](const ExternalSpec& spec, const MissionConfig& config) -> std::unique_ptr<ExternalLink> {
    return std::make_unique<DdsExternalLink>(spec, config);
  });
}

}  // namespace tern::core
