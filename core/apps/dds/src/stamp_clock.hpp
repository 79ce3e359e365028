// core/apps/dds/src/stamp_clock.hpp: ROS time for the bridge's header stamps, and ROS 2's /clock.
// In sim time a stamp is the flight time (ns from the flight's first tick: sim time starts at 0,
// as gazebo's), and rt/clock (rosgraph_msgs/Clock) carries it at `clock_rate` Hz with rclcpp's
// ClockQoS (best-effort, volatile, keep-last 1: rclcpp/src/rclcpp/qos.cpp), so that a node with
// use_sim_time runs on tern's flight time. In wall time (a real FCU) a stamp is the UNIX time of
// the flight's first tick plus the flight time, and there is no /clock.
#pragma once

#include "dds_internal.hpp"

namespace tern::core {
struct MissionConfig;
}

namespace tern::core::ddsi {

/// DdsTime::automatic -> wall when an instance runs plugin fcu_serial (a real FCU), else sim.
DdsTime resolve_time(const MissionConfig& config, DdsTime requested);

class StampClock {
 public:
  /// `time`: sim or wall (resolved); `clock_rate`: Hz of rt/clock in sim time (0: none).
  StampClock(DdsTime time, double clock_rate);
  /// Creates the rt/clock writer (sim time with clock_rate > 0).
  void start(fdds::DomainParticipant* participant, fdds::Publisher* publisher);
  /// At the end of each tick (flight thread): a new flight (flight time going back) takes a new
  /// epoch; writes rt/clock when its period has passed.
  void tick(Nanos now);
  /// ROS time of flight time 0, ns (0 in sim time).
  Nanos epoch() const { return epoch_; }
  /// The rt/clock writer, or nullptr.
  const fdds::DataWriter* writer() const { return writer_; }
  /// Clock messages written so far.
  std::uint64_t clocks_written() const { return written_; }
  /// One line for the log: which time and the /clock rate.
  std::string describe() const;

 private:
  DdsTime time_;
  Nanos period_ = 0;
  fdds::DataWriter* writer_ = nullptr;
  Nanos epoch_ = 0;
  Nanos last_now_ = -1;
  Nanos last_clock_ = -1;
  std::uint64_t written_ = 0;
};

}  // namespace tern::core::ddsi
