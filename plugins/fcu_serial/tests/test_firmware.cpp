// The ROSflight firmware's behaviour as the emulator plays it (tern_fcu_serial/firmware.hpp,
// fcu_side.hpp), one test per behaviour of issue 17, each naming the firmware function.
#include <doctest/doctest.h>

#include <bit>

#include "tern_fcu_serial/fcu_side.hpp"
#include "tern_fcu_serial/firmware.hpp"
#include "tern_fcu_serial/mapping.hpp"
#include "tern_fcu_serial/status.hpp"

using namespace tern::fcu;
namespace fw = tern::fcu::firmware;
namespace mav = tern::fcu::mavlink;
using namespace tern::fcu::firmware;

namespace {
constexpr std::int64_t kMs = 1'000'000;

/// A fixed wing configured as rosflight_sim's fixedwing_firmware.yaml says, gyro calibrated.
fw::Params configured() {
  fw::Params p;
  p.set_int("FIXED_WING", 1);
  p.set_int("PRIMARY_MIXER", 9);
  p.set_int("RC_F_AXIS", 0);
  p.set_int("RC_ARM_CHN", 4);
  p.set_int("RC_THR_OVRD_CHN", 5);
  p.set_int("RC_ATT_OVRD_CHN", 5);
  p.set_int("TAKE_MIN_THR", 0);
  p.set_int("ARM_SPIN_MOTORS", 0);
  p.set_int("RC_NUM_CHN", 8);
  p.set_float("GYRO_X_BIAS", 0.001f);
  p.take_changes();
  return p;
}

/// Transmitter channels 1..8 as PWM fractions: roll, pitch, throttle, yaw, arm, override.
fw::RcFrame tx(float roll, float throttle, bool arm, bool ovrd) {
  fw::RcFrame f;
  f.chan = {0.5f + 0.5f * roll, 0.5f, throttle, 0.5f, arm ? 1.0f : 0.0f, ovrd ? 1.0f : 0.0f, 0.0f, 0.0f};
  return f;
}

void loop(fw::Firmware& f, std::int64_t t) {
  std::array<float, 3> a{0, 0, -9.8f}, g{};
  f.imu(a, g, t);
}

/// Arms a configured firmware at time t with the override switch (state_manager.cpp), after a
/// first IMU sample (which only starts the firmware's clock: ROSflight::check_time_going_forwards).
void arm(fw::Firmware& f, std::int64_t& t) {
  loop(f, t);
  f.rc(tx(0, 0, false, true), t += 20 * kMs);
  f.rc(tx(0, 0, true, true), t += 20 * kMs);
  f.rc(tx(0, 0, true, false), t += 20 * kMs);
}

void command(fw::Firmware& f, const Surfaces& s, std::int64_t t) {
  const auto c = to_offboard(s, ActuatorMap{{3, 4, 5, 0}, {1, 1, 1}, {1, 1, 1, 1}});
  std::array<float, 10> u{};
  for (std::size_t i = 0; i < 10; ++i) u[i] = c.u[i];
  f.offboard(c.mode, u, c.ignore, t);
}
}  // namespace

TEST_CASE("1. channel layout: Qx -> aileron servo, Qy elevator, Qz rudder, Fx motor (mixer.h fixedwing_mixing)") {
  fw::Firmware f(configured());
  std::int64_t t = 2'000 * kMs;  // past the first RC_OVRD_LAG_T (stick_deviated counts from 0)
  arm(f, t);
  REQUIRE(f.armed());
  command(f, {0.5, -0.2, 0.1, 0.7}, t);
  f.rc(tx(0, 0, true, false), t += 20 * kMs);
  loop(f, t);
  CHECK(f.raw_outputs()[0] == doctest::Approx(0.75));  // 0.5 + 0.5 u (mixer.cpp mix_output)
  CHECK(f.raw_outputs()[1] == doctest::Approx(0.4));
  CHECK(f.raw_outputs()[2] == doctest::Approx(0.55));
  CHECK(f.raw_outputs()[4] == doctest::Approx(0.7));
  // the old convention (aileron in u[0]) would drive the motor
  std::array<float, 10> old{};
  old[0] = 0.5f;
  f.offboard(0, old, 0x3F0, t);
  f.rc(tx(0, 0, true, false), t += 20 * kMs);
  loop(f, t);
  CHECK(f.raw_outputs()[4] == doctest::Approx(0.5));
  CHECK(f.raw_outputs()[0] == doctest::Approx(0.5));
}

TEST_CASE("2. RC_CHANNELS says chancount 0; tern reads channels 1-8 as rosflight_io does") {
  mav::RcChannels rc;  // CommManager::send_rc_raw / MavlinkAdapter::send_rc_raw
  rc.chancount = 0;
  rc.chan1_raw = 1750;
  rc.chan3_raw = 1200;
  rc.chan5_raw = 2000;
  const RcSticks s = from_rc(rc, RcMap{});
  CHECK(s.roll == doctest::Approx(0.5));
  CHECK(s.throttle == doctest::Approx(0.2));
  CHECK(s.aux[0] == doctest::Approx(1.0));
}

TEST_CASE("3. outputs move only when an RC frame arrives (command_manager.cpp run mixes on a new RC command)") {
  fw::Firmware f(configured());
  std::int64_t t = 2'000 * kMs;  // past the first RC_OVRD_LAG_T (stick_deviated counts from 0)
  arm(f, t);
  loop(f, t);
  const float before = f.raw_outputs()[0];
  command(f, {0.8, 0, 0, 0.5}, t += kMs);
  for (int i = 0; i < 7; ++i) loop(f, t += 2'500'000);
  CHECK(f.raw_outputs()[0] == before);  // no receiver frame: nothing moves
  f.rc(tx(0, 0, true, false), t += kMs);
  loop(f, t);
  CHECK(f.raw_outputs()[0] == doctest::Approx(0.9));
}

TEST_CASE("4. ignored channels go to the pilot and set override bits (determine_override_status)") {
  fw::Firmware f(configured());
  std::int64_t t = 2'000 * kMs;  // past the first RC_OVRD_LAG_T (stick_deviated counts from 0)
  arm(f, t);
  std::array<float, 10> u{};
  u[3] = 0.5f;
  f.offboard(0, u, 0x3F7 & ~0x008, t);  // only Qx active
  f.rc(tx(-0.6f, 0.3f, true, false), t += 20 * kMs);
  CHECK((f.rc_override() & (kOverrideOffboardYInactive | kOverrideOffboardZInactive | kOverrideOffboardTInactive)) ==
        (kOverrideOffboardYInactive | kOverrideOffboardZInactive | kOverrideOffboardTInactive));
  CHECK((f.rc_override() & kOverrideOffboardXInactive) == 0);
  loop(f, t);
  CHECK(f.raw_outputs()[4] == doctest::Approx(0.3));  // the pilot's throttle
}

TEST_CASE("5. boots disarmed with errors; arms only from the transmitter, error-free; motor 0 disarmed; commands refused armed") {
  fw::Firmware fresh;  // firmware defaults: PRIMARY_MIXER invalid, all IMU biases 0, a multirotor without failsafe throttle
  CHECK_FALSE(fresh.armed());
  CHECK(fresh.error_codes() ==
        (fw::kErrorInvalidMixer | fw::kErrorUncalibratedImu | fw::kErrorInvalidFailsafe));  // FIXED_WING 0, FAILSAFE_THR -1
  std::int64_t t = 0;
  fresh.rc(tx(0, 0, true, true), t += 20 * kMs);
  CHECK_FALSE(fresh.armed());
  CHECK(arming_problems(false, fresh.error_codes()).find("run `tern fcu calibrate imu`") != std::string::npos);

  fw::Params p = configured();
  p.set_int("TAKE_MIN_THR", 0);
  fw::Firmware f(p);
  f.rc(tx(0, 0, true, false), t += 20 * kMs);  // arm switch without the override switch: refused
  CHECK_FALSE(f.armed());
  command(f, {0, 0, 0, 0.9}, t);
  f.rc(tx(0, 0, false, false), t += 20 * kMs);
  loop(f, t);
  CHECK(f.raw_outputs()[4] == 0.0f);  // disarmed: motor 0 (mix_output)
  arm(f, t);
  CHECK(f.armed());
  FcuSide side(configured(), "v");
  std::vector<std::uint8_t> out;
  side.fw().rc(tx(0, 0, false, true), 20 * kMs);
  side.fw().rc(tx(0, 0, true, true), 40 * kMs);
  REQUIRE(side.fw().armed());
  mav::Encoder companion(1, 50);
  mav::RosflightCmd cmd;
  cmd.command = static_cast<std::uint8_t>(RosflightCmd::accel_calibration);
  const auto bytes = companion.frame(cmd);
  mav::Parser in, back;
  in.feed(bytes.data(), bytes.size(), [&](const mav::Frame& fr) { side.handle(fr, 50 * kMs, out); });
  int acks = 0;
  back.feed(out.data(), out.size(), [&](const mav::Frame& fr) {
    if (const auto m = mav::decode(fr); m && std::holds_alternative<mav::RosflightCmdAck>(*m)) {
      ++acks;
      CHECK(std::get<mav::RosflightCmdAck>(*m).success == 0);  // comm_manager.cpp command_callback
    }
  });
  CHECK(acks == 1);
}

TEST_CASE("6. parameters: echo only on a change, wrong type ignored, other target system ignored (comm_manager.cpp)") {
  FcuSide side(configured(), "v");
  mav::Encoder companion(1, 50);
  std::vector<std::uint8_t> out;
  auto send = [&](const auto& m) {
    out.clear();
    const auto bytes = companion.frame(m);
    mav::Parser in, back;
    in.feed(bytes.data(), bytes.size(), [&](const mav::Frame& fr) { side.handle(fr, kMs, out); });
    std::vector<std::pair<mav::Frame, mav::Message>> got;
    back.feed(out.data(), out.size(), [&](const mav::Frame& fr) { got.emplace_back(fr, *mav::decode(fr)); });
    return got;
  };
  mav::ParamSet s;
  s.target_system = 1;
  s.param_id = mav::to_chars<16>("RC_OVRD_DEV");
  s.param_type = kParamReal32;
  s.param_value = 0.1f;  // the current value: no echo
  CHECK(send(s).empty());
  s.param_value = 0.3f;
  const auto echo = send(s);
  REQUIRE(echo.size() == 1);
  CHECK(echo[0].first.compid == 0);  // PARAM_VALUE goes out as component 0
  CHECK(std::get<mav::ParamValue>(echo[0].second).param_value == 0.3f);
  s.param_type = kParamInt32;  // the wrong type: ignored
  s.param_value = std::bit_cast<float>(std::int32_t{1});
  CHECK(send(s).empty());
  CHECK(side.fw().params().get_float("RC_OVRD_DEV") == 0.3f);
  s.param_type = kParamReal32;
  s.param_value = 0.5f;
  s.target_system = 2;  // not SYS_ID
  CHECK(send(s).empty());
  CHECK(side.fw().params().get_float("RC_OVRD_DEV") == 0.3f);
}

TEST_CASE("7. OUTPUT_RAW values are PWM fractions: servo 0.5 + 0.5 u, decoded back to u") {
  CHECK(servo_command(0.75f) == doctest::Approx(0.5));
  CHECK(servo_command(0.5f) == doctest::Approx(0.0));
  fw::Firmware f(configured());
  std::int64_t t = 2'000 * kMs;  // past the first RC_OVRD_LAG_T (stick_deviated counts from 0)
  arm(f, t);
  command(f, {-1.5, 0, 0, 0}, t);  // clamped to -1: output 0 at 0
  f.rc(tx(0, 0, true, false), t += 20 * kMs);
  loop(f, t);
  CHECK(f.raw_outputs()[0] == doctest::Approx(0.0));
}

TEST_CASE("8. one sequence counter over components 250 and 0: no phantom gaps, a lost frame is one gap") {
  mav::Encoder fcu(1, 250);
  std::vector<std::uint8_t> bytes;
  fcu.append(mav::SmallImu{}, bytes);
  fcu.append_as(mav::ParamValue{}, bytes, 1, 0);
  fcu.append(mav::SmallImu{}, bytes);
  mav::Parser p;
  p.feed(bytes.data(), bytes.size(), [](const mav::Frame&) {});
  CHECK(p.stats().seq_gaps == 0);
  std::vector<std::uint8_t> lost;
  fcu.append(mav::SmallImu{}, lost);  // never delivered
  std::vector<std::uint8_t> next;
  fcu.append(mav::SmallImu{}, next);
  p.feed(next.data(), next.size(), [](const mav::Frame&) {});
  CHECK(p.stats().seq_gaps == 1);
}

TEST_CASE("8b. a log line under a clock-byte system id is on the same counter: no phantom gap") {
  // comm_manager.cpp send_buffered_log_messages passes clock_micros() as the system id
  mav::Encoder fcu(1, 250);
  std::vector<std::uint8_t> bytes;
  fcu.append(mav::SmallImu{}, bytes);
  fcu.append_as(mav::Statustext{}, bytes, 0xA7, 250);
  fcu.append(mav::SmallImu{}, bytes);
  mav::Parser p;
  int frames = 0;
  p.feed(bytes.data(), bytes.size(), [&](const mav::Frame&) { ++frames; });
  CHECK(frames == 3);
  CHECK(p.stats().seq_gaps == 0);
}

TEST_CASE("9. boot calibration: the pitot zeroes itself (in wind, 0 afterwards), the baro sets BARO_BIAS; GNSS fix types") {
  fw::Firmware f(configured());
  float reported = 0;
  for (std::int64_t t = 0; t < 12'000 * kMs; t += 10 * kMs) {
    reported = f.diff_pressure(40.0f, t);  // 8 m/s of wind at boot
    f.baro(95000.0f, t);
  }
  CHECK(f.params().get_float("DIFF_PRESS_BIAS") == doctest::Approx(40.0));
  CHECK(reported == doctest::Approx(0.0));
  CHECK(f.params().get_float("BARO_BIAS") == doctest::Approx(95000.0));
  CHECK(fix_type(4) == 3);  // GNSS + dead reckoning: a 3D fix
  CHECK(fix_type(5) == 0);  // time only: no position
  CHECK(fix_type(6) == 3);
}

TEST_CASE("10. RC lost while armed: failsafe, throttle 0, surfaces neutral (state_manager.cpp, fixedwing_failsafe_command_)") {
  fw::Firmware f(configured());
  std::int64_t t = 2'000 * kMs;  // past the first RC_OVRD_LAG_T (stick_deviated counts from 0)
  arm(f, t);
  command(f, {0.5, 0.5, 0.5, 0.8}, t);
  f.rc(tx(0, 0, true, false), t += 20 * kMs);
  loop(f, t);
  CHECK(f.raw_outputs()[4] == doctest::Approx(0.8));
  fw::RcFrame lost = tx(0, 0, true, false);
  lost.lost = true;
  f.rc(lost, t += 20 * kMs);
  loop(f, t);
  CHECK(f.failsafe());
  CHECK(f.armed());
  CHECK(f.raw_outputs()[4] == 0.0f);
  CHECK(f.raw_outputs()[0] == doctest::Approx(0.5));
  f.rc(tx(0, 0, true, false), t += 20 * kMs);
  CHECK_FALSE(f.failsafe());
}

TEST_CASE("11. stick past RC_OVRD_DEV hands the axis to the pilot until RC_OVRD_LAG_T after it returns (stick_deviated)") {
  fw::Firmware f(configured());
  std::int64_t t = 2'000 * kMs;
  arm(f, t);
  command(f, {0.2, 0, 0, 0.5}, t);
  f.rc(tx(0.5f, 0, true, false), t += 20 * kMs);
  CHECK((f.rc_override() & kOverrideX) != 0);
  loop(f, t);
  CHECK(f.raw_outputs()[0] == doctest::Approx(0.75));  // the pilot's roll
  command(f, {0.2, 0, 0, 0.5}, t += 500 * kMs);
  f.rc(tx(0, 0, true, false), t);
  CHECK((f.rc_override() & kOverrideX) != 0);  // within the lag
  command(f, {0.2, 0, 0, 0.5}, t += 600 * kMs);
  f.rc(tx(0, 0, true, false), t);
  CHECK(f.rc_override() == 0);
  loop(f, t);
  CHECK(f.raw_outputs()[0] == doctest::Approx(0.6));  // tern's again
}

TEST_CASE("11b. the override lag is renewed only once per RC_OVRD_LAG_T: tern flies again 0..1 s after the stick is centred") {
  // CommandManager::stick_deviated returns true inside the lag without renewing
  // last_override_time; only the first deviated frame after the lag renews it. A stick held from
  // T0 to T0 + 2 s renews it at T0 and T0 + 1 s, so tern flies again at T0 + 2 s whether the
  // stick is centred at T0 + 2 s (no lag seen) or at T0 + 1.5 s (0.5 s of lag).
  for (const std::int64_t centred_ms : {2'000, 1'500}) {
    fw::Firmware f(configured());
    std::int64_t t = 2'000 * kMs;
    arm(f, t);
    const std::int64_t t0 = t + 20 * kMs;
    std::int64_t back = -1;
    for (t = t0; t <= t0 + 3'000 * kMs; t += 20 * kMs) {
      command(f, {0.2, 0, 0, 0.5}, t);
      f.rc(tx(t - t0 < centred_ms * kMs ? 0.5f : 0.0f, 0, true, false), t);
      if (back < 0 && t > t0 && (f.rc_override() & kOverrideX) == 0) back = t - t0;
    }
    CAPTURE(centred_ms);
    CHECK(back == 2'000 * kMs);
  }
}
