// FcuClock (tern_fcu_serial/fcu_clock.hpp) alone: the FCU's boot time, the host's steady clock
// and flight time, under both clock policies, across a gap and a reboot.
#include <doctest/doctest.h>

#include <stdexcept>

#include "tern_fcu_serial/fcu_clock.hpp"

using namespace tern::fcu;

namespace {
constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kGap = 500 * kMs;  // the plugin's link_timeout

/// Reads and accepts the sample at FCU time t in the step of flight time now.
FlightTime take(FcuClock& c, std::int64_t t, std::int64_t now) {
  const auto i = c.imu(FcuTime{t}, HostTime{0}, FlightTime{now});
  (void)c.accept_imu(FcuTime{t}, i.stamp);
  return i.stamp;
}
}  // namespace

TEST_CASE("clock policy: parsed once, anything but fcu or wall is one line naming the value") {
  CHECK(parse_clock_policy("fcu") == ClockPolicy::fcu);
  CHECK(parse_clock_policy("wall") == ClockPolicy::wall);
  CHECK_THROWS_WITH_AS(parse_clock_policy("gps"), "clock 'gps' is not fcu or wall", std::invalid_argument);
}

TEST_CASE("clock fcu: the first IMU sample is the flight time of its step, later ones follow the FCU's clock") {
  FcuClock c(ClockPolicy::fcu, kGap);
  CHECK(c.reached(FcuTime{1'000 * kMs}, FlightTime{0}));  // not anchored: any sample will do
  CHECK(take(c, 1'000 * kMs, 0).ns == 0);                 // the FCU streams from 1 s after boot
  CHECK(c.reached(FcuTime{1'010 * kMs}, FlightTime{10 * kMs}));
  CHECK_FALSE(c.reached(FcuTime{1'005 * kMs}, FlightTime{10 * kMs}));
  CHECK(take(c, 1'010 * kMs, 10 * kMs).ns == 10 * kMs);
  // untimed messages take the stamp of the IMU sample before them; GNSS its own time, not later
  CHECK(c.untimed(HostTime{123}).ns == 10 * kMs);
  CHECK(c.timed(FcuTime{1'004 * kMs}, HostTime{0}, FlightTime{10 * kMs}).ns == 4 * kMs);
  CHECK(c.timed(FcuTime{1'020 * kMs}, HostTime{0}, FlightTime{10 * kMs}).ns == 10 * kMs);
}

TEST_CASE("clock fcu: a gap is reported once, when the sample after it is accepted; flight time jumps with the FCU's") {
  FcuClock c(ClockPolicy::fcu, kGap);
  take(c, 1'000 * kMs, 0);
  // 2 s of silence: the next sample belongs to flight time 2.0025 s; steps before it do not take it
  const auto early = c.imu(FcuTime{3'002'500'000}, HostTime{0}, FlightTime{2'500'000});
  CHECK(early.stamp.ns == 2'002'500'000);
  CHECK_FALSE(early.rebooted);
  const auto again = c.imu(FcuTime{3'002'500'000}, HostTime{0}, FlightTime{5'000'000});  // re-read next step
  CHECK(again.stamp.ns == 2'002'500'000);
  const auto gap = c.accept_imu(FcuTime{3'002'500'000}, again.stamp);
  REQUIRE(gap.has_value());
  CHECK(*gap == 2'002'500'000);
  CHECK_FALSE(c.accept_imu(FcuTime{3'005'000'000}, FlightTime{2'005'000'000}).has_value());
}

TEST_CASE("clock fcu: a reboot (the FCU's clock going back) re-anchors without going back in flight time") {
  FcuClock c(ClockPolicy::fcu, kGap);
  take(c, 1'000 * kMs, 0);
  take(c, 61'000 * kMs, 60'000 * kMs);
  CHECK(c.reached(FcuTime{1'000 * kMs}, FlightTime{60'010 * kMs}));  // older than the last: a reboot
  const auto i = c.imu(FcuTime{1'000 * kMs}, HostTime{0}, FlightTime{60'010 * kMs});
  CHECK(i.rebooted);
  CHECK(i.before.ns == 61'000 * kMs);
  CHECK(i.stamp.ns == 60'010 * kMs);
  CHECK_FALSE(c.accept_imu(FcuTime{1'000 * kMs}, i.stamp).has_value());                      // a new epoch, not a gap
  CHECK_FALSE(c.imu(FcuTime{1'000 * kMs}, HostTime{0}, FlightTime{60'010 * kMs}).rebooted);  // once
  CHECK(take(c, 1'010 * kMs, 60'020 * kMs).ns == 60'020 * kMs);
}

TEST_CASE("clock fcu: after the link comes back, FCU time is anchored at the current flight time") {
  FcuClock c(ClockPolicy::fcu, kGap);
  take(c, 1'000 * kMs, 0);
  c.follow_host(HostTime{5'000 * kMs}, FlightTime{100 * kMs});
  CHECK(c.host_deadline(FlightTime{350 * kMs}).ns == 5'250 * kMs);  // flight time follows the host
  c.reanchor();
  CHECK(take(c, 1'100 * kMs, 900 * kMs).ns == 900 * kMs);
}

TEST_CASE("clock wall: FCU times through TIMESYNC onto the host clock, flight time from the first step") {
  FcuClock c(ClockPolicy::wall, kGap);
  c.first_step(HostTime{10'000 * kMs}, FlightTime{0});
  c.first_step(HostTime{99'000 * kMs}, FlightTime{5 * kMs});  // only the first counts
  CHECK(c.untimed(HostTime{10'250 * kMs}).ns == 250 * kMs);
  const auto first = c.imu(FcuTime{1'000 * kMs}, HostTime{10'010 * kMs}, FlightTime{20 * kMs});
  CHECK(first.stamp.ns == 10 * kMs);  // not synced yet: its arrival time
  (void)c.accept_imu(FcuTime{1'000 * kMs}, first.stamp);
  CHECK(c.imu(FcuTime{1'001 * kMs}, HostTime{10'005 * kMs}, FlightTime{20 * kMs}).stamp.ns == 10 * kMs + 1);  // never back
  mavlink::Timesync answer;
  answer.ts1 = 10'100 * kMs;  // our request's time
  answer.tc1 = 3'000 * kMs;   // the FCU's time then (0 round trip)
  REQUIRE(c.timesync().on_answer(answer, 10'100 * kMs));
  CHECK(c.imu(FcuTime{3'200 * kMs}, HostTime{0}, FlightTime{0}).stamp.ns == 300 * kMs);
  c.restart();  // a new flight: the first step anchors again
  c.first_step(HostTime{20'000 * kMs}, FlightTime{0});
  CHECK(c.untimed(HostTime{20'001 * kMs}).ns == 1 * kMs);
}
