// The safety monitor and the state-loss recovery alone (no plugin, no host).
#include <doctest/doctest.h>

#include "safety/safety_monitor.hpp"
#include "safety/state_loss_recovery.hpp"

using namespace tern;
using namespace tern::core;

namespace {

msg::State cruising() {
  msg::State s;
  s.valid = true;
  s.status = msg::StateStatus::ok;
  s.p_d = -70.0;
  s.Va = 17.0;
  return s;
}

SafetyInputs step(Nanos now, const msg::State& s, const msg::Actuators& a, bool published = true) {
  SafetyInputs in;
  in.now = now;
  in.phase = msg::Phase::cruise;
  in.published = published;
  in.actuators = &a;
  in.state = &s;
  in.h_c = 70.0;
  in.Va_c = 17.0;
  return in;
}

constexpr Nanos kPeriod = 10'000'000;  // 100 Hz

}  // namespace

TEST_CASE("safety monitor: a silent controller is a cause after silent_periods steps, not before") {
  SafetyMonitor m;
  const msg::State s = cruising();
  const msg::Actuators a;
  for (int k = 1; k < 5; ++k) CHECK(m.check(step(k * kPeriod, s, a, false)).empty());
  CHECK(m.check(step(5 * kPeriod, s, a, false)) == "silent: stepped 5 times in a row without publishing actuators");
  m.restart();
  CHECK(m.check(step(6 * kPeriod, s, a, false)).empty());
}

TEST_CASE("safety monitor: an envelope limit must hold for `hold` seconds (hysteresis); an invalid estimate is no cause") {
  SafetyMonitor m;
  msg::State s = cruising();
  const msg::Actuators a;
  s.phi = 1.4;  // 80 deg > 75
  CHECK(m.check(step(0, s, a)).empty());
  CHECK(m.check(step(19 * kPeriod, s, a)).empty());
  s.phi = 0.0;  // one tick back inside: the timer starts again
  CHECK(m.check(step(20 * kPeriod, s, a)).empty());
  s.phi = 1.4;
  CHECK(m.check(step(21 * kPeriod, s, a)).empty());
  CHECK(m.check(step(41 * kPeriod, s, a)).rfind("envelope: roll 80 deg beyond 75 deg", 0) == 0);
  s.valid = false;
  CHECK(m.check(step(42 * kPeriod, s, a)).empty());
  s = cruising();
  s.v_d = 16.0;
  m.restart();
  CHECK(m.check(step(0, s, a)).empty());
  CHECK(m.check(step(20 * kPeriod, s, a)) == "envelope: sink rate 16.0 m/s above 15.0 m/s");
}

TEST_CASE("safety monitor: the floor counts once the aircraft has been above it in climb or cruise") {
  SafetyMonitor m;
  msg::State s = cruising();
  msg::Actuators a;
  a.delta_t = 0.5;  // (throttle off while sinking would be a cause of its own)
  s.p_d = -6.0;     // the climb starts at 5 m: below the 8-m floor, not armed yet
  CHECK(m.check(step(0, s, a)).empty());
  CHECK(m.check(step(30 * kPeriod, s, a)).empty());
  s.p_d = -9.0;
  CHECK(m.check(step(31 * kPeriod, s, a)).empty());
  s.p_d = -6.0;
  CHECK(m.check(step(32 * kPeriod, s, a)).empty());
  CHECK(m.check(step(52 * kPeriod, s, a)) == "envelope: altitude 6.0 m below the floor 8.0 m");
}

TEST_CASE("safety monitor: the landing descends through the floor: disarmed from the approach, re-armed above it after a go-around") {
  SafetyMonitor m;
  msg::State s = cruising();
  msg::Actuators a;
  a.delta_t = 0.5;
  CHECK(m.check(step(0, s, a)).empty());  // 70 m in cruise: armed
  SafetyInputs in = step(kPeriod, s, a);
  in.phase = msg::Phase::approach;
  CHECK(m.check(in).empty());
  s.p_d = -3.0;  // the flare, 3 m up: no cause
  for (int k = 2; k < 40; ++k) {
    in = step(k * kPeriod, s, a);
    in.phase = k < 20 ? msg::Phase::approach : msg::Phase::flare;
    CHECK(m.check(in).empty());
  }
  in = step(40 * kPeriod, s, a);  // a go-around from 3 m: climbing back, below the floor, no cause
  in.phase = msg::Phase::climb;
  CHECK(m.check(in).empty());
  CHECK(m.check(step(60 * kPeriod, s, a)).empty());
  s.p_d = -20.0;  // above it again: armed
  CHECK(m.check(step(61 * kPeriod, s, a)).empty());
  s.p_d = -6.0;
  CHECK(m.check(step(62 * kPeriod, s, a)).empty());
  CHECK(m.check(step(82 * kPeriod, s, a)) == "envelope: altitude 6.0 m below the floor 8.0 m");
}

TEST_CASE("safety monitor: delta_e at its stop is a cause only once the altitude error grows") {
  SafetyMonitor m;
  msg::State s = cruising();
  msg::Actuators a;
  a.delta_e = 0.69;
  CHECK(m.check(step(0, s, a)).empty());
  s.p_d = -68.5;  // 1.5 m below h_c
  CHECK(m.check(step(kPeriod, s, a)).empty());
  s.p_d = -67.5;  // 2.5 m below
  CHECK(m.check(step(2 * kPeriod, s, a)) == "saturated: delta_e 0.69 rad at its stop while the altitude error grew to 2.5 m");
  // at the stop while the error shrinks: no cause
  m.restart();
  s.p_d = -60.0;
  CHECK(m.check(step(3 * kPeriod, s, a)).empty());
  s.p_d = -69.0;
  CHECK(m.check(step(4 * kPeriod, s, a)).empty());
  s.p_d = -67.5;  // the error grows again, 1.5 m from its smallest (1 m): not yet
  CHECK(m.check(step(5 * kPeriod, s, a)).empty());
  // full throttle (a climb) is no cause; throttle off while sinking below h_c is, when slow too
  a.delta_e = 0.0;
  a.delta_t = 1.0;
  s.p_d = -50.0;
  CHECK(m.check(step(6 * kPeriod, s, a)).empty());
  a.delta_t = 0.0;
  s.p_d = -66.0;
  CHECK(m.check(step(7 * kPeriod, s, a)).empty());
  s.p_d = -60.0;
  s.Va = 18.0;  // fast: the throttle is right to be off (a dive)
  CHECK(m.check(step(8 * kPeriod, s, a)).empty());
  s.Va = 16.0;
  s.p_d = -66.0;
  CHECK(m.check(step(9 * kPeriod, s, a)).empty());
  s.p_d = -60.0;
  CHECK(m.check(step(10 * kPeriod, s, a)) == "saturated: delta_t 0 while the aircraft sank to 10.0 m below h_c");
}

TEST_CASE("state-loss recovery: trim from the good commands, throttle up, wings level on the gyros") {
  StateLossRecovery r;
  msg::Actuators good;
  good.delta_e = 0.17;
  good.delta_t = 0.55;
  good.delta_a = 0.01;
  msg::State s = cruising();
  s.phi = 0.3;
  s.b_x = 0.02;
  for (int k = 0; k < 1000; ++k) r.observe(k * kPeriod, good, &s);  // 10 s: the average settled
  r.begin(1000 * kPeriod);
  CHECK(r.active());
  msg::Imu imu;
  imu.stamp = 1001 * kPeriod;
  imu.gyro.x() = 0.02;  // the bias alone: no roll rate
  const msg::Actuators c = r.command(1001 * kPeriod, &imu);
  CHECK(c.delta_e == doctest::Approx(0.17));
  CHECK(c.delta_t == doctest::Approx(0.75));
  CHECK(c.delta_a == doctest::Approx(0.01 - 0.5 * 0.3));  // rolled right: aileron left
  // without a gyro sample the aileron holds
  CHECK(r.command(1002 * kPeriod, nullptr).delta_a == doctest::Approx(c.delta_a));
  // a roll rate to the left integrates the roll back towards level
  imu.stamp = 1101 * kPeriod;
  imu.gyro.x() = 0.02 - 0.3;  // 1 s at -0.3 rad/s
  const msg::Actuators d = r.command(1101 * kPeriod, &imu);
  CHECK(d.delta_a == doctest::Approx(0.01 - 0.5 * 0.0 - 0.1 * -0.3));
}
