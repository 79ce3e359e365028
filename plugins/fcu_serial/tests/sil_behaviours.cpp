// The ROSflight firmware's behaviours that tern relies on (README.md "firmware behaviour" table,
// test_firmware.cpp "1." .. "11b."), checked over the link on BOTH FCU programs: the emulator
// (tern's re-implementation) and the real firmware (tern-fcu-sil). Each test runs once per
// program (SUBCASE "emulator" / "real firmware") and looks only at what comes over MAVLink.
// Times are the FCU's clock in s (1 s at the first sample; the --rc script's times + 1 s).
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <functional>
#include <numeric>
#include <set>

#include "fcu_process.hpp"
#include "tern_fcu_serial/status.hpp"

using namespace tern::fcu;
using namespace tern::fcu::testing;
namespace mav = tern::fcu::mavlink;

namespace {
constexpr const char* kArm = "0 throttle=0 aux1=-1 aux2=-1; 2 aux2=1; 2.1 aux1=1; 2.5 aux2=-1";  // armed at FCU 3.1 s

void both(const std::function<void(Program)>& body) {
  for (const Program p : {Program::emulator, Program::firmware}) {
    SUBCASE(to_string(p)) { body(p); }
  }
}

Setup with_rc(const std::string& rc, bool configured = true) {
  Setup s;
  s.rc = rc;
  s.configured = configured;
  return s;
}

void run_to(FcuProcess& f, double t) {
  f.run_until([&] { return f.now() >= t; }, t - f.now() + 1.0);
}

bool armed(const FcuProcess& f) {
  const auto s = f.last<mav::RosflightStatus>();
  return s && s->armed;
}

/// Armed by kArm (FCU 3.1 s), and the pilot's override switch released (3.5 s): tern flies.
bool arm(FcuProcess& f) {
  const bool ok = f.run_until([&] { return armed(f); }, 5.0);
  run_to(f, 3.55);
  return ok;
}

std::array<float, 14> outputs(const FcuProcess& f) {
  const auto o = f.last<mav::RosflightOutputRaw>();
  REQUIRE(o);
  return o->values;
}

/// OUTPUT_RAW values received in [t0, t1).
std::vector<std::array<float, 14>> outputs_between(const FcuProcess& f, double t0, double t1) {
  std::vector<std::array<float, 14>> v;
  for (const auto& [t, o] : f.all<mav::RosflightOutputRaw>(t0))
    if (t < t1) v.push_back(o.values);
  return v;
}

doctest::Approx near(double v) { return doctest::Approx(v).epsilon(1e-5); }

std::string param_name(const Received& r) {
  const auto* v = std::get_if<mav::ParamValue>(&r.msg);
  return v ? mav::to_string(v->param_id) : std::string();
}

/// PARAM_VALUE frames named `name` after log index `mark`.
std::vector<Received> echoes(const FcuProcess& f, std::size_t mark, const std::string& name) {
  std::vector<Received> out;
  for (std::size_t i = mark; i < f.log().size(); ++i)
    if (param_name(f.log()[i]) == name) out.push_back(f.log()[i]);
  return out;
}

/// The FCU time at which the first ROSFLIGHT_STATUS after `from` no longer has `bits` set.
std::optional<double> cleared(const FcuProcess& f, std::uint16_t bits, double from) {
  return f.first_status([&](const mav::RosflightStatus& s) { return (s.rc_override & bits) == 0; }, from);
}
}  // namespace

TEST_CASE("1. channel layout: Qx -> aileron servo, Qy elevator, Qz rudder, Fx motor (mixer.h fixedwing_mixing)") {
  both([](Program p) {
    FcuProcess f(p, with_rc(kArm));
    REQUIRE(arm(f));
    f.set_surfaces({0.5, -0.2, 0.1, 0.7});
    f.run_for(0.1);
    auto raw = outputs(f);
    CHECK(raw[0] == near(0.75));  // 0.5 + 0.5 u (mixer.cpp mix_output)
    CHECK(raw[1] == near(0.4));
    CHECK(raw[2] == near(0.55));
    CHECK(raw[3] == 0.0f);  // AUX: no aux command
    CHECK(raw[4] == near(0.7));
    mav::OffboardControl old;  // the old convention (aileron in u[0]) drives the motor
    old.u[0] = 0.5f;
    old.ignore = 0x3C0;
    f.set_command(old);
    f.run_for(0.1);
    raw = outputs(f);
    CHECK(raw[4] == near(0.5));
    CHECK(raw[0] == near(0.5));
  });
}

TEST_CASE("2. RC_CHANNELS: chancount 0, channels 1-8 in PWM us as the firmware truncates them (send_rc_raw)") {
  both([](Program p) {
    FcuProcess f(p, with_rc("0 roll=0.5 pitch=-0.3 throttle=0.2 yaw=-1 aux1=1 aux3=0.4", false));
    f.run_for(0.2);
    const auto rc = f.last<mav::RcChannels>();
    REQUIRE(rc);
    CHECK(rc->chancount == 0);
    CHECK(rc->chan1_raw == 1750);
    // 1350 us is the float 0.35f (0.34999999) in the firmware's RcStruct; chan * 1000 + 1000
    // converted to uint16_t truncates it to 1349 (comm_manager.cpp CommManager::send_rc_raw)
    CHECK(rc->chan2_raw == 1349);
    CHECK(rc->chan3_raw == 1200);
    CHECK(rc->chan4_raw == 1000);
    CHECK(rc->chan5_raw == 2000);
    CHECK(rc->chan6_raw == 1000);
    CHECK(rc->chan7_raw == 1699);  // 0.7f = 0.69999999
    CHECK(rc->chan8_raw == 1000);
    CHECK(rc->chan9_raw == 0);
    CHECK(rc->chan18_raw == 0);
    CHECK(rc->rssi == 0);
    const RcSticks s = from_rc(*rc, RcMap{});  // as rosflight_io reads it
    CHECK(s.roll == doctest::Approx(0.5));
    CHECK(s.throttle == doctest::Approx(0.2));
    CHECK(s.aux[0] == doctest::Approx(1.0));
  });
}

TEST_CASE("3. outputs move only when an RC frame arrives (command_manager.cpp CommandManager::run)") {
  both([](Program p) {
    FcuProcess silent_rc(p, with_rc("none"));  // no receiver: the muxer never runs
    silent_rc.set_surfaces({0.5, 0, 0, 0});
    silent_rc.run_for(1.0);
    const auto still = outputs_between(silent_rc, 1.001, 10.0);  // the first sample mixes nothing (test 7)
    REQUIRE(still.size() >= 40);
    // tern's 0.5 never reaches the aileron (0.75). Deviation documented: until the first RC frame
    // the real firmware's combined command keeps its initial types (command_manager.h
    // combined_command_: roll and pitch ANGLE, yaw RATE), so its attitude controller drives the
    // servos (a few 1e-4 of travel at rest, controller.cpp run_pid_loops); the emulator has no
    // attitude controller and holds them at 0.5.
    for (const auto& o : still) CHECK(o[0] == doctest::Approx(0.5).epsilon(0.01));

    FcuProcess f(p, with_rc(kArm));
    f.run_for(0.5);
    const double t0 = f.now();
    f.set_surfaces({0.5, 0, 0, 0});
    REQUIRE(f.run_until([&] { return outputs(f)[0] > 0.7f; }, 0.2));
    const double moved = f.all<mav::RosflightOutputRaw>(t0).back().first;
    bool frame_between = false;
    for (const auto& [t, rc] : f.all<mav::RcChannels>(t0)) frame_between = frame_between || (t > t0 && t < moved);
    CHECK(frame_between);
  });
}

TEST_CASE("4. ignored channels go to the pilot and set OFFBOARD_*_INACTIVE (determine_override_status, do_muxing)") {
  both([](Program p) {
    FcuProcess f(p, with_rc(std::string(kArm) + "; 3 throttle=0.3"));
    REQUIRE(arm(f));
    mav::OffboardControl c;  // only Qx active
    c.u[3] = 0.5f;
    c.ignore = 0x3FF & ~0x008;
    f.set_command(c);
    run_to(f, 4.3);
    const auto s = f.last<mav::RosflightStatus>();
    REQUIRE(s);
    CHECK(s->rc_override ==
          (firmware::kOverrideOffboardYInactive | firmware::kOverrideOffboardZInactive | firmware::kOverrideOffboardTInactive));
    CHECK(s->offboard == 1);
    const auto raw = outputs(f);
    CHECK(raw[0] == near(0.75));  // tern's Qx
    CHECK(raw[1] == near(0.5));   // the pilot's centred pitch stick
    CHECK(raw[4] == near(0.3));   // the pilot's throttle
  });
}

TEST_CASE("5a. boots disarmed with errors; an FCU in error refuses to arm and says why, once a second (state_manager.cpp set_event)") {
  both([](Program p) {
    FcuProcess f(p, with_rc("0 throttle=0 yaw=1", false));  // no flash: the firmware's defaults, arming by sticks
    f.run_for(3.0);
    const auto s = f.last<mav::RosflightStatus>();
    REQUIRE(s);
    CHECK(f.first_status([](const mav::RosflightStatus& st) { return st.armed != 0; }) == std::nullopt);
    // invalid mixer, uncalibrated IMU, and a multirotor (FIXED_WING 0) without failsafe throttle
    // (FAILSAFE_THR -1: command_manager.cpp init_failsafe)
    CHECK(s->error_code == (firmware::kErrorInvalidMixer | firmware::kErrorUncalibratedImu | firmware::kErrorInvalidFailsafe));
    CHECK(arming_problems(false, s->error_code).find("run `tern fcu calibrate imu`") != std::string::npos);
    std::vector<std::string> boot;
    std::vector<double> refusals;
    for (const auto& [t, m] : f.all<mav::Statustext>()) {
      const std::string text = mav::to_string(m.text);
      if (text.rfind("Unable to arm", 0) != 0)
        boot.push_back(text);
      else if (text == "Unable to arm: Invalid mixer")
        refusals.push_back(t);
    }
    // param.cpp Params::init, mixer.cpp init_mixing, rc.cpp init_switches
    const std::vector<std::string> expected{"Unable to load parameters; using default values",
                                            "Invalid mixer choice for primary mixer",
                                            "Invalid mixer selected for secondary mixer!",
                                            "Secondary mixer defaulting to primary!",
                                            "ARM switch not mapped",
                                            "ATTITUDE OVERRIDE switch mapped to RC channel 4",
                                            "THROTTLE OVERRIDE switch mapped to RC channel 4",
                                            "ATTITUDE TYPE switch not mapped"};
    CHECK(boot == expected);
    CHECK(f.said("Unable to arm: IMU not calibrated"));
    CHECK(f.said("Unable to arm: Invalid failsafe setting"));
    // the sticks held from 0 s: the first request 20 ms after boot (rc.cpp counts from clock 0), then
    // whenever the last reasons are more than 1000 ms old: one RC frame later than 1 s
    REQUIRE(refusals.size() == 3);
    CHECK(refusals[0] == doctest::Approx(1.02));
    CHECK(refusals[1] == doctest::Approx(2.04));
    CHECK(refusals[2] == doctest::Approx(3.06));
  });
}

TEST_CASE("5b. arms only from the transmitter with the override switch; motor 0 disarmed; ROSFLIGHT_CMD refused armed") {
  both([](Program p) {
    FcuProcess f(p, with_rc("0 throttle=0 aux1=-1 aux2=-1; 2 aux1=1; 2.5 aux1=-1; 3 aux2=1; 3.1 aux1=1; 3.5 aux2=-1"));
    f.set_surfaces({0, 0, 0, 0.9});
    run_to(f, 2.0);
    const auto ack = f.command(RosflightCmd::send_version);
    REQUIRE(ack);
    CHECK(ack->success == 1);  // disarmed: carried out (comm_manager.cpp command_callback)
    CHECK(f.last<mav::RosflightVersion>());
    run_to(f, 3.9);  // the arm switch without the override switch: refused
    CHECK(f.said("RC throttle override must be active to arm"));
    CHECK_FALSE(armed(f));
    for (const auto& o : outputs_between(f, 1.0, 100.0)) CHECK(o[4] == 0.0f);  // disarmed: motor 0
    REQUIRE(f.run_until([&] { return armed(f); }, 1.0));
    CHECK(f.now() == doctest::Approx(4.1).epsilon(0.01));
    run_to(f, 4.6);  // the override switch released at 4.5 s
    CHECK(outputs(f)[4] == near(0.9));
    const auto refused = f.command(RosflightCmd::send_version);
    REQUIRE(refused);
    CHECK(refused->success == 0);
  });
}

TEST_CASE("6. parameters: echo only on a change, wrong type ignored, other target system ignored (param.cpp, comm_manager.cpp)") {
  both([](Program p) {
    FcuProcess f(p, with_rc("none", false));
    f.run_for(0.05);
    std::size_t mark = f.log().size();
    f.param_set("RC_OVRD_DEV", 0.1, kParamReal32);  // its current value: no echo
    f.run_for(0.1);
    CHECK(echoes(f, mark, "RC_OVRD_DEV").empty());
    mark = f.log().size();
    f.param_set("RC_OVRD_DEV", 0.3, kParamReal32);
    f.run_for(0.1);
    const auto echo = echoes(f, mark, "RC_OVRD_DEV");
    REQUIRE(echo.size() == 1);
    CHECK(echo[0].frame.compid == 0);  // PARAM_VALUE goes out as component 0 (mavlink_adapter.cpp)
    CHECK(std::get<mav::ParamValue>(echo[0].msg).param_value == 0.3f);
    mark = f.log().size();
    f.param_set("RC_OVRD_DEV", 1, kParamInt32);        // the wrong type: ignored
    f.param_set("RC_OVRD_DEV", 0.5, kParamReal32, 2);  // not SYS_ID: ignored
    f.run_for(0.1);
    CHECK(echoes(f, mark, "RC_OVRD_DEV").empty());
    CHECK(f.param_get("RC_OVRD_DEV") == doctest::Approx(0.3f));
  });
}

TEST_CASE("6b. the parameter list, one a loop; a valid PRIMARY_MIXER clears the error (send_next_param, init_mixing)") {
  both([](Program p) {
    FcuProcess f(p, with_rc("none", false));
    f.run_for(0.05);
    // PARAM_REQUEST_LIST: one parameter a loop, param_count of them, each index once
    std::size_t mark = f.log().size();
    mav::ParamRequestList list;
    list.target_system = 1;
    f.send(list);
    std::set<int> seen;
    int count = -1;
    f.run_until(
        [&] {
          for (std::size_t i = mark; i < f.log().size(); ++i)
            if (const auto* v = std::get_if<mav::ParamValue>(&f.log()[i].msg)) {
              seen.insert(v->param_index);
              count = v->param_count;
            }
          mark = f.log().size();
          return count > 0 && static_cast<int>(seen.size()) == count;
        },
        3.0);
    REQUIRE(count > 0);
    CHECK(static_cast<int>(seen.size()) == count);
    CHECK(*seen.rbegin() == count - 1);
    // a valid mixer: the error clears. Deviation documented: the real firmware's init_mixing also
    // saves the mixer's matrix (mixer.cpp save_primary_mixer_params, save_secondary_mixer_params),
    // echoing every PRI_MIXER_* / SEC_MIXER_* parameter that changed; the emulator's table holds
    // only the parameters it uses (its param_count is smaller) and echoes PRIMARY_MIXER alone.
    mark = f.log().size();
    f.param_set("PRIMARY_MIXER", 9, kParamInt32);
    f.run_for(0.1);
    std::set<std::string> names;
    for (std::size_t i = mark; i < f.log().size(); ++i)
      if (const auto n = param_name(f.log()[i]); !n.empty()) names.insert(n);
    CHECK(names.count("PRIMARY_MIXER") == 1);
    CHECK((f.last<mav::RosflightStatus>()->error_code & firmware::kErrorInvalidMixer) == 0);
    if (p == Program::firmware) {
      CHECK(names.count("PRI_MIXER_3_0") == 1);  // Qx -> output 0
      CHECK(names.count("SEC_MIXER_3_0") == 1);
      CHECK(count > static_cast<int>(firmware::Params{}.size()));
    } else {
      CHECK(names.size() == 1);
      CHECK(count == static_cast<int>(firmware::Params{}.size()));
    }
  });
}

TEST_CASE("7. OUTPUT_RAW: every 8th IMU sample, stamp in ms, servos 0.5 + 0.5 u clamped, motor 0..1 (send_output_raw, mix_output)") {
  both([](Program p) {
    FcuProcess f(p, with_rc(kArm));
    REQUIRE(arm(f));
    mav::OffboardControl c;
    c.u[3] = -1.5f;  // aileron beyond full throw: output 0
    c.u[4] = 0.3f;
    c.u[0] = 1.4f;  // motor beyond full: 1
    c.ignore = 0x3C0;
    f.set_command(c);
    const double t0 = f.now();
    f.run_for(0.2);
    const auto raw = outputs(f);
    const auto first = f.all<mav::RosflightOutputRaw>().front();  // the first sample only starts the clock:
    CHECK(first.first == doctest::Approx(1.0));                   // nothing mixed yet (check_time_going_forwards)
    for (float v : first.second.values) CHECK(v == 0.0f);
    CHECK(raw[0] == 0.0f);
    CHECK(raw[1] == near(0.65));
    CHECK(servo_command(raw[1]) == doctest::Approx(0.3).epsilon(1e-5));
    CHECK(raw[4] == 1.0f);
    int imus = -1;  // SMALL_IMU since the last OUTPUT_RAW (-1: none yet)
    for (const Received& r : f.log()) {
      if (r.t < t0) continue;
      if (std::holds_alternative<mav::SmallImu>(r.msg) && imus >= 0) ++imus;
      if (const auto* o = std::get_if<mav::RosflightOutputRaw>(&r.msg)) {
        CHECK(o->stamp == static_cast<std::uint64_t>(std::llround(r.t * 1e6)) / 1000);  // clock_millis of its loop
        if (imus >= 0) CHECK(imus == 8);                                                // every 8th sample: 50 Hz
        imus = 0;
      }
    }
  });
}

TEST_CASE("8. component 250, PARAM_VALUE from component 0, one sequence counter; boot log lines under clock_micros() as system id") {
  both([](Program p) {
    FcuProcess f(p, with_rc(kArm));
    f.run_for(1.0);
    const double t_set = f.now();
    f.param_set("SWITCH_8_DIR", -1, kParamInt32);  // RC::init_switches logs its 4 lines again, now connected
    REQUIRE(arm(f));
    f.run_for(0.5);
    int params = 0, others = 0, wrong_component = 0, seq_breaks = 0;
    std::vector<std::string> boot, later;
    for (std::size_t i = 0; i < f.log().size(); ++i) {
      const Received& r = f.log()[i];
      const bool param = std::holds_alternative<mav::ParamValue>(r.msg);
      params += param;
      wrong_component += r.frame.compid != (param ? 0 : kFirmwareComponent);
      if (i > 0) seq_breaks += r.frame.seq != static_cast<std::uint8_t>(f.log()[i - 1].frame.seq + 1);
      if (const auto* text = std::get_if<mav::Statustext>(&r.msg)) {
        // lines held from before the companion's first HEARTBEAT go out one a loop with the
        // clock's microseconds as system id (comm_manager.cpp send_buffered_log_messages)
        const auto clock_sysid = static_cast<std::uint8_t>(std::llround(r.t * 1e6));
        CHECK(r.frame.sysid == (r.t < t_set ? clock_sysid : 1));
        (r.t < t_set ? boot : later).push_back(mav::to_string(text->text));
      } else {
        ++others;
        CHECK(r.frame.sysid == 1);
      }
    }
    CHECK(params >= 1);
    CHECK(others > 1000);
    CHECK(wrong_component == 0);
    CHECK(seq_breaks == 0);
    CHECK(f.stats().seq_gaps == 0);
    CHECK(f.stats().bad_crc == 0);
    const std::vector<std::string> switches{"ARM switch mapped to RC channel 4", "ATTITUDE OVERRIDE switch mapped to RC channel 5",
                                            "THROTTLE OVERRIDE switch mapped to RC channel 5", "ATTITUDE TYPE switch not mapped"};
    std::vector<std::string> expected{"Invalid mixer selected for secondary mixer!", "Secondary mixer defaulting to primary!"};
    expected.insert(expected.end(), switches.begin(), switches.end());
    CHECK(boot == expected);  // mixer.cpp init_mixing, rc.cpp init_switches
    CHECK(later == switches);
  });
}

TEST_CASE("9. boot calibration: baro and pitot zero themselves (PARAM_VALUE, STATUSTEXT); altitude; GNSS fix (sensors.cpp)") {
  both([](Program p) {
    Setup s = with_rc("none", false);
    s.args = {"--wind", "-8,0,0"};  // 8 m/s of headwind on the pitot at boot (39 Pa): facing north, wind from the north
    FcuProcess f(p, s);
    REQUIRE(f.run_until([&] { return f.said("Baro ground pressure cal successful!") && f.said("Airspeed Cal Successful!"); }, 9.0));
    // 255 cycles of > 20 ms with 100 Hz samples: 30 ms each, 7.65 s after the first sample
    CHECK(*f.said("Baro ground pressure cal successful!") == doctest::Approx(8.65).epsilon(0.005));
    CHECK(*f.said("Airspeed Cal Successful!") == doctest::Approx(8.65).epsilon(0.005));
    const double t_cal = *f.said("Airspeed Cal Successful!");
    f.run_for(0.5);
    std::optional<double> diff_bias, baro_bias, ground;
    for (const auto& [t, v] : f.all<mav::ParamValue>()) {
      const std::string n = mav::to_string(v.param_id);
      if (n == "DIFF_PRESS_BIAS") diff_bias = v.param_value;
      if (n == "BARO_BIAS") baro_bias = v.param_value;
      if (n == "GROUND_LEVEL") ground = v.param_value;
    }
    REQUIRE(diff_bias);
    REQUIRE(baro_bias);
    REQUIRE(ground);
    std::vector<double> raw;  // what the pitot read while averaged: the last 127 cycles of 30 ms (bias still 0)
    for (const auto& [t, m] : f.all<mav::DiffPressure>(t_cal - 127 * 0.03))
      if (t < t_cal) raw.push_back(m.diff_pressure);
    REQUIRE(raw.size() > 350);
    const double wind = std::accumulate(raw.begin(), raw.end(), 0.0) / static_cast<double>(raw.size());
    CHECK(wind > 5.0);
    CHECK(*diff_bias == doctest::Approx(wind).epsilon(0.05));
    double diff = 0, pressure = 0;
    const auto d = f.all<mav::DiffPressure>(t_cal + 0.05);
    for (const auto& [t, m] : d) {
      diff += m.diff_pressure / static_cast<double>(d.size());
      CHECK(m.velocity == doctest::Approx(std::copysign(std::sqrt(std::fabs(m.diff_pressure) / (0.5 * 1.225)), m.diff_pressure)));
    }
    CHECK(std::fabs(diff) < 3.0);  // the wind is the zero now
    const auto b = f.all<mav::SmallBaro>(t_cal);
    for (const auto& [t, m] : b) {
      pressure += m.pressure / static_cast<double>(b.size());
      // turbomath::alt: ISA pressure altitude of the raw pressure
      const double alt = (1.0 - std::pow(m.pressure / 101325.0, 0.190326730028458)) * 44318.1386038261;
      CHECK(m.altitude == doctest::Approx(alt).epsilon(1e-5));
    }
    CHECK(*baro_bias == doctest::Approx(pressure).epsilon(1e-4));
    CHECK(*ground == doctest::Approx((1.0 - std::pow(*baro_bias / 101325.0, 0.190326730028458)) * 44318.1386038261).epsilon(1e-4));
    const auto gnss = f.last<mav::RosflightGnss>();
    REQUIRE(gnss);
    CHECK(gnss->fix_type == 3);  // board.h GNSS_FIX_TYPE_3D_FIX
    CHECK(fix_type(gnss->fix_type) == 3);
  });
}

TEST_CASE("10. RC lost while armed: failsafe, throttle 0, surfaces neutral, then back (state_manager.cpp, fixedwing_failsafe_command_)") {
  both([](Program p) {
    FcuProcess f(p, with_rc(std::string(kArm) + "; 4 lost=1; 5 lost=0"));
    REQUIRE(arm(f));
    f.set_surfaces({0.5, 0.5, 0.5, 0.8});
    run_to(f, 6.5);
    const auto lost = f.first_status([](const mav::RosflightStatus& s) { return s.failsafe != 0; });
    REQUIRE(lost);
    CHECK(*lost == doctest::Approx(5.0).epsilon(0.005));
    const auto during = f.first_status([](const mav::RosflightStatus& s) { return s.failsafe != 0; }, 5.5);
    REQUIRE(during);
    const auto s = f.all<mav::RosflightStatus>(5.5).front().second;
    CHECK(s.armed == 1);
    CHECK((s.error_code & firmware::kErrorRcLost) != 0);
    for (const auto& o : outputs_between(f, 5.1, 5.95)) {
      CHECK(o[4] == 0.0f);
      CHECK(o[0] == near(0.5));
      CHECK(o[1] == near(0.5));
    }
    const auto back = f.first_status([](const mav::RosflightStatus& st) { return st.failsafe == 0; }, *lost + 1e-3);
    REQUIRE(back);
    CHECK(*back == doctest::Approx(6.0).epsilon(0.005));
    CHECK(f.last<mav::RosflightStatus>()->armed == 1);
    CHECK(outputs(f)[4] == near(0.8));
    CHECK(outputs(f)[0] == near(0.75));
  });
}

TEST_CASE("11. stick past RC_OVRD_DEV hands the axis to the pilot until RC_OVRD_LAG_T after it deviated (stick_deviated)") {
  both([](Program p) {
    FcuProcess f(p, with_rc(std::string(kArm) + "; 4 roll=0.5; 4.5 roll=0"));
    REQUIRE(arm(f));
    f.set_surfaces({0.2, 0, 0, 0.5});
    run_to(f, 6.5);
    // from 4.5 s: a status the real firmware sends during its boot carries an uninitialised rc_override
    const auto over = f.first_status([](const mav::RosflightStatus& s) { return (s.rc_override & firmware::kOverrideX) != 0; }, 4.5);
    REQUIRE(over);
    CHECK(*over == doctest::Approx(5.0).epsilon(0.005));
    for (const auto& o : outputs_between(f, 5.05, 5.45)) CHECK(o[0] == near(0.75));  // the pilot's roll
    const auto back = cleared(f, firmware::kOverrideX, *over + 1e-3);
    REQUIRE(back);
    CHECK(*back - *over == doctest::Approx(1.0).epsilon(0.025));  // RC_OVRD_LAG_T 1000 ms, the stick centred at 0.5 s
    CHECK(outputs(f)[0] == near(0.6));                            // tern's again
  });
}

TEST_CASE("11b. the override lag is renewed once per RC_OVRD_LAG_T: tern flies again 2 s after a 1.5 or 2 s deviation") {
  both([](Program p) {
    for (const char* centred : {"6", "5.5"}) {
      CAPTURE(centred);
      FcuProcess f(p, with_rc(std::string(kArm) + "; 4 roll=0.5; " + centred + " roll=0"));
      REQUIRE(arm(f));
      f.set_surfaces({0.2, 0, 0, 0.5});
      run_to(f, 7.5);
      const auto over = f.first_status([](const mav::RosflightStatus& s) { return (s.rc_override & firmware::kOverrideX) != 0; }, 4.5);
      REQUIRE(over);
      const auto back = cleared(f, firmware::kOverrideX, *over + 1e-3);
      REQUIRE(back);
      CHECK(*back - *over == doctest::Approx(2.0).epsilon(0.0125));
    }
  });
}
