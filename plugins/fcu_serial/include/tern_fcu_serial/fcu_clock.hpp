// tern_fcu_serial/fcu_clock.hpp: the three clocks of a flight through an FCU, and how the
// messages of one are stamped in another. Plain C++, no tern host types; tested alone in
// tests/test_clock.cpp.
//
//   FcuTime     the FCU's clock since its boot (SMALL_IMU time_boot_us, GNSS rosflight_timestamp),
//               ns; goes back when the FCU reboots
//   HostTime    this computer's steady clock (frame arrival, TIMESYNC), ns
//   FlightTime  the host's flight time (tern::Nanos of step(now) and of every stamp), ns
//
// Policy `fcu` (ClockPolicy::fcu): the FCU's IMU samples pace the flight. The first sample
// after an anchor (start, reset, link restored, reboot) is the flight time of the step that
// reads it (never earlier than the last published sample); every later one is stamped
// anchor_flight + (t - anchor_fcu). Messages without an FCU time take the stamp of the IMU
// sample before them in the stream. While the FCU is silent, flight time follows HostTime
// (follow_host / host_deadline) so that the host neither races nor stalls.
// Policy `wall` (ClockPolicy::wall): FCU times are mapped to HostTime with TIMESYNC
// (timesync.hpp) and flight time is HostTime since the first step; untimed messages take
// their arrival time.
// Reboot: an IMU sample more than kRebootStep older than the last one. Gap: two accepted IMU
// samples more than `gap` apart in FCU time (the link was silent or frames were lost).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "tern_fcu_serial/timesync.hpp"

namespace tern::fcu {

struct FcuTime {
  std::int64_t ns = 0;
};
struct HostTime {
  std::int64_t ns = 0;
};
struct FlightTime {
  std::int64_t ns = 0;
};

/// The time source of a flight through an FCU (the plugin's `clock` parameter).
enum class ClockPolicy { fcu, wall };
/// "fcu" or "wall"; anything else throws std::invalid_argument naming the value.
ClockPolicy parse_clock_policy(std::string_view s);

class FcuClock {
 public:
  static constexpr std::int64_t kRebootStep = 1'000'000'000;  ///< ns: an FCU clock going back this far rebooted

  /// What one IMU sample means (imu()).
  struct Imu {
    FlightTime stamp;       ///< its flight time (never before the last accepted sample)
    bool rebooted = false;  ///< the FCU's clock went back: a new epoch, re-anchored
    FcuTime before;         ///< the last accepted sample's FCU time (when rebooted)
  };

  FcuClock(ClockPolicy policy, std::int64_t gap_ns) : policy_(policy), gap_(gap_ns) {}
  ClockPolicy policy() const { return policy_; }

  /// The first step of a flight at flight time `now` and host time `host` (policy wall: the
  /// origin of flight time). Later calls do nothing until restart().
  void first_step(HostTime host, FlightTime now);
  /// A new flight (reset) or a new connection: forget the anchors and the samples.
  void restart();
  /// Policy fcu: the next IMU sample anchors FCU time again (the link came back).
  void reanchor() { anchored_ = false; }

  /// An IMU sample at FCU time t, received at `rx`, read in the step of flight time `now`.
  /// Detects a reboot (re-anchors, clears TIMESYNC) and anchors; the sample is not yet
  /// accepted (a stamp after `now` belongs to a later step).
  Imu imu(FcuTime t, HostTime rx, FlightTime now);
  /// The sample of imu() is published with stamp `stamp`. Returns the FCU-time gap since the
  /// previously accepted sample when it exceeds `gap` (reported once), else nullopt.
  std::optional<std::int64_t> accept_imu(FcuTime t, FlightTime stamp);
  /// The stamp of a message without an FCU time, received at `rx`.
  FlightTime untimed(HostTime rx) const;
  /// The stamp of a message with FCU time t (GNSS): never after `stream`, the stamp untimed()
  /// gives it; before the first anchor (policy fcu) or without a time (t = 0), `stream`.
  FlightTime timed(FcuTime t, HostTime rx, FlightTime stream) const;

  /// Policy fcu: has the IMU sample of flight time `now` arrived, given the newest FCU time
  /// received? (True before the first anchor, and after a reboot: that sample re-anchors.)
  bool reached(FcuTime newest, FlightTime now) const;
  /// Policy fcu, FCU silent: from now on flight time follows host time, starting at (host, now).
  void follow_host(HostTime host, FlightTime now) { silent_host_ = host, silent_flight_ = now; }
  /// The host time at which flight time `now` is due while following host time.
  HostTime host_deadline(FlightTime now) const { return {silent_host_.ns + (now.ns - silent_flight_.ns)}; }

  TimeSync& timesync() { return timesync_; }
  const TimeSync& timesync() const { return timesync_; }
  bool anchored() const { return anchored_; }

 private:
  FlightTime of_host(HostTime h) const { return {host_origin_flight_.ns + (h.ns - host_origin_.ns)}; }
  FlightTime of_fcu(FcuTime t, HostTime rx) const;

  ClockPolicy policy_;
  std::int64_t gap_;
  TimeSync timesync_;
  bool anchored_ = false, host_anchored_ = false;
  FcuTime anchor_fcu_;
  FlightTime anchor_flight_;
  HostTime host_origin_;
  FlightTime host_origin_flight_;
  std::optional<FcuTime> last_imu_;  ///< the last accepted (or rebooted-to) sample
  FlightTime last_stamp_, stream_;
  HostTime silent_host_;
  FlightTime silent_flight_;
};

}  // namespace tern::fcu
