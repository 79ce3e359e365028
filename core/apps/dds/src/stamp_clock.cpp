// core/apps/dds/src/stamp_clock.cpp: see stamp_clock.hpp.
#include "stamp_clock.hpp"

#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "config/config.hpp"
#include "rosgraph_msgs/msg/ClockPubSubTypes.h"

namespace tern::core::ddsi {

DdsTime resolve_time(const MissionConfig& config, DdsTime requested) {
  if (requested != DdsTime::automatic) return requested;
  for (const auto& p : config.plugins)
    if (p.plugin == "fcu_serial" || p.plugin.find("tern_fcu_serial") != std::string::npos) return DdsTime::wall;
  return DdsTime::sim;
}

StampClock::StampClock(DdsTime time, double clock_rate)
    : time_(time), period_(time == DdsTime::sim && clock_rate > 0 ? static_cast<Nanos>(std::llround(1e9 / clock_rate)) : 0) {}

void StampClock::start(fdds::DomainParticipant* participant, fdds::Publisher* publisher) {
  if (period_ == 0) return;
  // /clock is absolute (no vehicle namespace), as ROS 2's
  fdds::Topic* t = make_topic<rosgraph_msgs::msg::ClockPubSubType>(participant, topic_name("", "clock"));
  writer_ = publisher->create_datawriter(t, writer_qos(DdsQos::best_effort, 1));
  if (writer_ == nullptr) throw DdsError("DDS: cannot create a writer for rt/clock");
}

void StampClock::tick(Nanos now) {
  if (now < last_now_ || last_now_ < 0) {  // a new flight
    epoch_ = time_ == DdsTime::wall
                 ? std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count() - now
                 : 0;
    last_clock_ = -1;
  }
  last_now_ = now;
  if (writer_ == nullptr || (last_clock_ >= 0 && now - last_clock_ < period_)) return;
  rosgraph_msgs::msg::Clock c;
  const Nanos t = now + epoch_;
  c.clock().sec(static_cast<std::int32_t>(t / 1000000000));
  c.clock().nanosec(static_cast<std::uint32_t>(t % 1000000000));
  writer_->write(&c);
  last_clock_ = now;
  ++written_;
}

std::string StampClock::describe() const {
  if (time_ == DdsTime::wall) return "wall time (UNIX time of the flight's start + flight time; no /clock)";
  if (period_ == 0) return "sim time (flight time from 0; /clock off)";
  return fmt::format("sim time (flight time from 0), published on rt/clock at {:g} Hz", 1e9 / static_cast<double>(period_));
}

}  // namespace tern::core::ddsi
