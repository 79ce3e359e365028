// Channel mapping and scaling (actuators -> OFFBOARD_CONTROL, RC_CHANNELS -> sticks), time sync,
// and the FCU side of the parameter protocol.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "tern_fcu_serial/fcu_side.hpp"
#include "tern_fcu_serial/mapping.hpp"
#include "tern_fcu_serial/timesync.hpp"

using namespace tern::fcu;
namespace mav = tern::fcu::mavlink;

TEST_CASE("actuators -> pass-through: the firmware's layout Qx Qy Qz Fx, scaled, clamped, u[0..5] active") {
  // comm_manager.cpp offboard_control_callback reads u[] as Fx Fy Fz Qx Qy Qz; include/mixer.h
  // fixedwing_mixing routes Qx aileron, Qy elevator, Qz rudder, Fx motor.
  ActuatorMap map;
  map.max_deflection = {0.5, 0.4, 0.25};
  Surfaces s{0.25, -0.1, 0.5, 0.6};
  const auto c = to_offboard(s, map);
  CHECK(c.mode == 0);
  CHECK(c.u[3] == doctest::Approx(0.5));    // Qx: aileron
  CHECK(c.u[4] == doctest::Approx(-0.25));  // Qy: elevator
  CHECK(c.u[5] == doctest::Approx(1.0));    // Qz: rudder, 0.5 rad beyond the 0.25 rad limit: clamped
  CHECK(c.u[0] == doctest::Approx(0.6));    // Fx: throttle
  CHECK(c.u[1] == 0.0f);
  CHECK(c.u[2] == 0.0f);
  CHECK(c.ignore == 0x3C0);  // u[6..9] ignored; an ignored u[0..5] would go to the pilot
  s.delta_t = 1.7;
  CHECK(to_offboard(s, map).u[0] == doctest::Approx(1.0));
  s.delta_t = -0.2;
  CHECK(to_offboard(s, map).u[0] == doctest::Approx(0.0));
  s.delta_a = std::numeric_limits<double>::quiet_NaN();
  CHECK(to_offboard(s, map).u[3] == 0.0f);
}

TEST_CASE("channel names and map validation name the problem") {
  CHECK(channel_index("Qx") == 3);
  CHECK(channel_index("Fx") == 0);
  CHECK_THROWS_WITH_AS(channel_index("u3"), "'u3' is not one of the firmware's channels Fx Fy Fz Qx Qy Qz", std::invalid_argument);
  ActuatorMap map;
  map.channel = {3, 4, 4, 0};
  CHECK_THROWS_WITH_AS(map.validate(), "rudder and elevator share channel Qy", std::invalid_argument);
  map.channel = {3, 4, 5, 6};
  CHECK_THROWS_WITH_AS(map.validate(), "throttle channel 6 is outside 0..5 (Fx..Qz)", std::invalid_argument);
  map.channel = {3, 4, 5, 0};
  map.max_deflection[1] = 0;
  CHECK_THROWS_AS(map.validate(), std::invalid_argument);
}

TEST_CASE("RC_CHANNELS -> sticks: AETR mapping, PWM scaling, missing channels") {
  RcMap map;
  mav::RcChannels rc;
  rc.chancount = 8;
  rc.chan1_raw = 2000;  // roll full right
  rc.chan2_raw = 1250;  // pitch half down
  rc.chan3_raw = 1300;  // throttle 30 %
  rc.chan4_raw = 1500;  // yaw centred
  rc.chan5_raw = 1000;
  rc.chan6_raw = 2000;
  rc.chan7_raw = 0xFFFF;  // not reported
  rc.chan8_raw = 1600;
  const RcSticks s = from_rc(rc, map);
  CHECK(s.roll == doctest::Approx(1.0));
  CHECK(s.pitch == doctest::Approx(-0.5));
  CHECK(s.throttle == doctest::Approx(0.3));
  CHECK(s.yaw == doctest::Approx(0.0));
  CHECK(s.aux[0] == doctest::Approx(-1.0));
  CHECK(s.aux[1] == doctest::Approx(1.0));
  CHECK(s.aux[2] == 0.0);
  CHECK(s.aux[3] == doctest::Approx(0.2));
}

TEST_CASE("time sync: offset from request/answer pairs, RTT filter, reboot reset") {
  TimeSync ts({0.9, 20'000'000, 100'000'000});
  const std::int64_t true_offset = 5'000'000'000;  // FCU clock ahead by 5 s
  const std::int64_t one_way = 1'000'000;          // 1 ms each way
  std::int64_t now = 100'000'000'000;
  CHECK_FALSE(ts.synced());
  for (int i = 0; i < 20; ++i) {
    const auto req = TimeSync::request(now);
    const auto ans = TimeSync::respond(req, now + one_way + true_offset);
    REQUIRE(ans.has_value());
    CHECK(ts.on_answer(*ans, now + 2 * one_way));
    now += 100'000'000;
  }
  CHECK(ts.synced());
  CHECK(ts.offset() == true_offset);
  CHECK(ts.last_rtt() == 2 * one_way);
  CHECK(ts.to_companion(now + true_offset) == now);
  CHECK(ts.to_fcu(now) == now + true_offset);
  // an asymmetric sample moves the estimate only partly (smoothing)
  {
    const auto req = TimeSync::request(now);
    const auto ans = TimeSync::respond(req, now + 3 * one_way + true_offset);  // 3 ms out, 1 ms back
    ts.on_answer(*ans, now + 4 * one_way);
    CHECK(ts.offset() == true_offset + 100'000);  // sample off by 1 ms, weight 0.1
  }
  // a slow answer is ignored
  const auto slow = TimeSync::respond(TimeSync::request(now), now + true_offset);
  CHECK_FALSE(ts.on_answer(*slow, now + 50'000'000));
  CHECK(ts.rejected() == 1);
  // a request is not an answer; the FCU does not answer an answer
  CHECK_FALSE(ts.on_answer(TimeSync::request(now), now));
  CHECK_FALSE(TimeSync::respond(*slow, 1).has_value());
  // the FCU rebooted: its clock restarts near 0 -> the estimate restarts
  const auto after = TimeSync::respond(TimeSync::request(now), 2'000'000'000 + one_way);
  CHECK(ts.on_answer(*after, now + 2 * one_way));
  CHECK(ts.resets() == 1);
  CHECK(ts.offset() == 2'000'000'000 - now);
}

TEST_CASE("time sync: the round trips' p50, p99 and max over the accepted answers") {
  TimeSync ts({0.9, 20'000'000, 100'000'000});
  CHECK(ts.rtt_stats().count == 0);
  CHECK(ts.rtt_stats().max == 0);
  std::int64_t now = 1'000'000'000;
  for (int i = 1; i <= 200; ++i) {  // round trips 0.1 .. 20 ms, in reverse order
    const std::int64_t rtt = (201 - i) * 100'000;
    const auto ans = TimeSync::respond(TimeSync::request(now), now + rtt / 2);
    REQUIRE(ts.on_answer(*ans, now + rtt));
    now += 100'000'000;
  }
  const auto slow = TimeSync::respond(TimeSync::request(now), now);  // 30 ms: rejected, not counted
  CHECK_FALSE(ts.on_answer(*slow, now + 30'000'000));
  const TimeSync::RttStats r = ts.rtt_stats();
  CHECK(r.count == 200);
  CHECK(r.p50 == 10'000'000);  // the 100th of 200
  CHECK(r.p99 == 19'800'000);  // the 198th
  CHECK(r.max == 20'000'000);
}
