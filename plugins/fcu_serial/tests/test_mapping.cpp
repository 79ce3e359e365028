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

TEST_CASE("actuators -> pass-through: scaled by the maximum deflections, clamped, ignore flags") {
  ActuatorMap map;
  map.max_deflection = {0.5, 0.4, 0.25};
  Surfaces s{0.25, -0.1, 0.5, 0.6};
  const auto c = to_offboard(s, map);
  CHECK(c.mode == 0);
  CHECK(c.u[0] == doctest::Approx(0.5));
  CHECK(c.u[1] == doctest::Approx(-0.25));
  CHECK(c.u[2] == doctest::Approx(1.0));  // 0.5 rad beyond the 0.25 rad limit: clamped
  CHECK(c.u[3] == doctest::Approx(0.6));
  CHECK(c.ignore == 0x3F0);  // channels 4..9 ignored
  // throttle outside 0..1 and NaN
  s.delta_t = 1.7;
  CHECK(to_offboard(s, map).u[3] == doctest::Approx(1.0));
  s.delta_t = -0.2;
  CHECK(to_offboard(s, map).u[3] == doctest::Approx(0.0));
  s.delta_a = std::numeric_limits<double>::quiet_NaN();
  CHECK(to_offboard(s, map).u[0] == 0.0f);
}

TEST_CASE("actuators -> pass-through: remapped channels and reversed signs, and back") {
  ActuatorMap map;
  map.channel = {3, 2, 1, 0};
  map.sign = {1, -1, 1, 1};
  map.max_deflection = {0.6981317, 0.6981317, 0.6981317};
  map.validate();
  const Surfaces s{0.1, 0.2, -0.3, 0.8};
  const auto c = to_offboard(s, map);
  CHECK(c.u[3] == doctest::Approx(0.1 / 0.6981317));
  CHECK(c.u[2] == doctest::Approx(-0.2 / 0.6981317));
  CHECK(c.u[1] == doctest::Approx(-0.3 / 0.6981317));
  CHECK(c.u[0] == doctest::Approx(0.8));
  const Surfaces back = from_offboard(c, map);
  CHECK(back.delta_a == doctest::Approx(0.1).epsilon(1e-6));
  CHECK(back.delta_e == doctest::Approx(0.2).epsilon(1e-6));
  CHECK(back.delta_r == doctest::Approx(-0.3).epsilon(1e-6));
  CHECK(back.delta_t == doctest::Approx(0.8).epsilon(1e-6));
  // an ignored channel reads 0 at the FCU
  auto c2 = c;
  c2.ignore |= 1u << 3;
  CHECK(from_offboard(c2, map).delta_a == 0.0);
}

TEST_CASE("actuator map validation names the problem") {
  ActuatorMap map;
  map.channel = {0, 1, 1, 3};
  CHECK_THROWS_WITH_AS(map.validate(), "rudder and elevator share channel 1", std::invalid_argument);
  map.channel = {0, 1, 2, 10};
  CHECK_THROWS_WITH_AS(map.validate(), "throttle channel 10 is outside 0..9", std::invalid_argument);
  map.channel = {0, 1, 2, 3};
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
  rc.chancount = 4;  // channels beyond chancount read 0
  CHECK(from_rc(rc, map).aux[0] == 0.0);
  // and the emulator's inverse
  RcSticks in{0.2, -0.4, 0.6, 0.7, {0.5, -0.5, 0, 1}};
  const RcSticks out = from_rc(to_rc(in, map, 10), map);
  CHECK(out.roll == doctest::Approx(0.2));
  CHECK(out.pitch == doctest::Approx(-0.4));
  CHECK(out.yaw == doctest::Approx(0.6));
  CHECK(out.throttle == doctest::Approx(0.7));
  CHECK(out.aux[3] == doctest::Approx(1.0));
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

TEST_CASE("FCU side: parameter list, read, set (typed), commands, time sync") {
  FcuSide fcu(FcuSide::default_params(), "v2.0.0-test");
  mav::Encoder companion(1, 50);
  mav::Parser parser;
  std::vector<std::uint8_t> out;
  auto send = [&](const auto& m) {
    out.clear();
    const auto bytes = companion.frame(m);
    mav::Parser p;
    p.feed(bytes.data(), bytes.size(), [&](const mav::Frame& f) { fcu.handle(f, 1'000'000, out); });
    std::vector<mav::Message> answers;
    parser.feed(out.data(), out.size(), [&](const mav::Frame& f) { answers.push_back(*mav::decode(f)); });
    return answers;
  };
  const auto all = send(mav::ParamRequestList{});
  CHECK(all.size() == fcu.params().size());
  const auto& first = std::get<mav::ParamValue>(all.front());
  CHECK(mav::to_string(first.param_id) == "ARM_SPIN_MOTORS");
  CHECK(first.param_count == fcu.params().size());

  mav::ParamRequestRead rd;
  rd.param_id = mav::to_chars<16>("RC_ATT_OVRD_CHN");
  rd.param_index = -1;
  auto a = send(rd);
  REQUIRE(a.size() == 1);
  const auto& pv = std::get<mav::ParamValue>(a[0]);
  CHECK(pv.param_type == kParamInt32);
  CHECK(param_number(pv.param_value, pv.param_type) == 5.0);

  mav::ParamSet set;
  set.param_id = mav::to_chars<16>("RC_ATT_OVRD_CHN");
  set.param_value = 6.0f;  // sent as a float: stored as the parameter's int32
  set.param_type = kParamReal32;
  a = send(set);
  REQUIRE(a.size() == 1);
  CHECK(param_number(std::get<mav::ParamValue>(a[0]).param_value, kParamInt32) == 6.0);
  set.param_id = mav::to_chars<16>("MOTOR_IDLE_THR");
  set.param_value = 0.15f;
  a = send(set);
  CHECK(std::get<mav::ParamValue>(a[0]).param_value == 0.15f);

  mav::RosflightCmd cmd;
  cmd.command = static_cast<std::uint8_t>(RosflightCmd::send_version);
  a = send(cmd);
  REQUIRE(a.size() == 2);
  CHECK(mav::to_string(std::get<mav::RosflightVersion>(a[0]).version) == "v2.0.0-test");
  CHECK(std::get<mav::RosflightCmdAck>(a[1]).success == 1);
  cmd.command = static_cast<std::uint8_t>(RosflightCmd::write_params);
  send(cmd);
  CHECK(fcu.writes() == 1);

  a = send(TimeSync::request(777));
  REQUIRE(a.size() == 1);
  CHECK(std::get<mav::Timesync>(a[0]).tc1 == 1'000'000);
  CHECK(std::get<mav::Timesync>(a[0]).ts1 == 777);

  mav::OffboardControl oc;
  oc.u[0] = 0.5f;
  send(oc);
  CHECK(fcu.commands() == 1);
  CHECK(fcu.command().u[0] == 0.5f);
}
