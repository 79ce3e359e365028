// The link thread over a pseudo-terminal, tern-fcu against the emulator, and the plugin flying
// the emulator's aircraft through a pseudo-terminal (sensors in SI units, actuators reaching the
// FCU, link loss, reboot, RC override, corrupted bytes).
#include <doctest/doctest.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <thread>

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include "../tools/emulator/uart.hpp"
#include "fcu_serial_plugin.hpp"
#include "tern/testing/harness.hpp"
#include "tern_fcu_serial/firmware.hpp"
#include "tern_fcu_serial/link.hpp"
#include "tern_fcu_serial/process.hpp"

using namespace tern::fcu;
namespace mav = tern::fcu::mavlink;

namespace {
struct Pty {
  int master = -1, slave = -1;
  char name[256] = {};
  Pty() {
    REQUIRE(openpty(&master, &slave, name, nullptr, nullptr) == 0);
    termios t{};
    tcgetattr(slave, &t);
    cfmakeraw(&t);
    tcsetattr(slave, TCSANOW, &t);
  }
  ~Pty() {
    close(master);
    close(slave);
  }
  std::vector<std::uint8_t> read_for(int ms) {
    std::vector<std::uint8_t> out;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    while (std::chrono::steady_clock::now() < end) {
      pollfd p{master, POLLIN, 0};
      if (poll(&p, 1, 10) > 0) {
        std::uint8_t b[1024];
        const ssize_t n = ::read(master, b, sizeof b);
        if (n > 0) out.insert(out.end(), b, b + n);
      }
    }
    return out;
  }
};

/// A UDP port pair of this test process (two test runs at once, e.g. two build trees, would
/// otherwise share fixed ports: the sockets reuse addresses, and frames go to either).
unsigned udp_port(unsigned offset) { return 20000u + static_cast<unsigned>(getpid()) % 20000u * 2u + offset; }

}  // namespace

TEST_CASE("link: frames both ways over a pseudo-terminal; stop() joins") {
  Pty pty;
  LinkOptions o;
  o.device = pty.name;
  Link link(o);
  link.start();
  CHECK(link.running());
  mav::Encoder fcu(1, 1);
  std::vector<std::uint8_t> bytes;
  for (int i = 0; i < 100; ++i) {
    mav::SmallImu imu;
    imu.time_boot_us = static_cast<std::uint64_t>(i);
    fcu.append(imu, bytes);
  }
  const std::uint8_t junk[] = {1, 2, 3, 0xFE, 0xFE, 9};
  bytes.insert(bytes.begin() + 50 * 44, std::begin(junk), std::end(junk));  // between two frames
  const auto t0 = steady_ns();
  REQUIRE(::write(pty.master, bytes.data(), bytes.size()) == static_cast<ssize_t>(bytes.size()));
  std::deque<Received> rx;
  while (rx.size() < 100 && steady_ns() - t0 < 2'000'000'000) {
    link.wait(100'000'000);
    link.drain(rx);
  }
  REQUIRE(rx.size() == 100);
  CHECK(mav::SmallImu::unpack(rx.back().frame.payload.data()).time_boot_us == 99);
  CHECK(rx.front().rx_ns >= t0);
  CHECK(link.stats().parser.skipped > 0);

  mav::Encoder companion(1, 50);
  link.send(companion.frame(TimeSync::request(42)));
  const auto back = pty.read_for(200);
  mav::Parser p;
  int n = 0;
  p.feed(back.data(), back.size(), [&](const mav::Frame& f) {
    ++n;
    CHECK(f.msgid == mav::Timesync::kId);
    CHECK(f.compid == 50);
  });
  CHECK(n == 1);
  const auto s0 = steady_ns();
  link.stop();
  CHECK_FALSE(link.running());
  CHECK(steady_ns() - s0 < 1'000'000'000);
}

TEST_CASE("link: a port that cannot be opened is one clear error") {
  LinkOptions o;
  o.device = "/dev/tern-no-such-device";
  Link link(o);
  CHECK_THROWS_WITH_AS(link.start(), doctest::Contains("cannot open serial /dev/tern-no-such-device @ 921600"), std::runtime_error);
  CHECK_FALSE(link.running());
}

TEST_CASE("link: UDP both ways (ROSflight SIL ports)") {
  LinkOptions a, b;
  a.kind = b.kind = LinkOptions::Kind::udp;
  a.udp_bind_port = udp_port(0);
  a.udp_remote_port = udp_port(1);
  b.udp_bind_port = udp_port(1);
  b.udp_remote_port = udp_port(0);
  Link companion(a), fcu_end(b);
  companion.start();
  fcu_end.start();
  mav::Encoder enc(1, 1);
  fcu_end.send(enc.frame(mav::SmallMag{}));
  std::deque<Received> rx;
  for (int i = 0; i < 20 && rx.empty(); ++i) {
    companion.wait(100'000'000);
    companion.drain(rx);
  }
  REQUIRE(rx.size() == 1);
  CHECK(rx[0].frame.msgid == mav::SmallMag::kId);
}

TEST_CASE("plugin: bad parameters and a missing port are one clear line each") {
  using tern::fcu_serial::FcuSerial;
  auto make = [](std::map<std::string, tern::ParamValue> p) { return tern::testing::Harness(std::make_unique<FcuSerial>(), std::move(p)); };
  CHECK_THROWS_WITH_AS(make({{"channels", std::string("Qx Qy Qy Fx")}}), doctest::Contains("rudder and elevator share channel Qy"),
                       tern::ParamError);
  CHECK_THROWS_WITH_AS(make({{"channels", std::string("Qx Qy u5 Fx")}}), doctest::Contains("'u5' is not one of the firmware's channels"),
                       tern::ParamError);
  CHECK_THROWS_WITH_AS(make({{"signs", std::vector<double>{1, 0.5, 1, 1}}}), doctest::Contains("sign must be +1 or -1"), tern::ParamError);
  CHECK_THROWS_WITH_AS(make({{"rc_channels", std::vector<double>{0, 1, 3, 4}}}), doctest::Contains("mapped twice"), tern::ParamError);
  CHECK_THROWS_AS(make({{"command_rate", 20.0}}), tern::ParamError);  // below the FCU's 50 Hz
  CHECK_THROWS_AS(make({{"transport", std::string("can")}}), tern::ParamError);
  auto h = make({{"device", std::string("/dev/tern-no-such-fcu")}});
  CHECK_THROWS_WITH_AS(h.start(), doctest::Contains("cannot open serial /dev/tern-no-such-fcu @ 921600"), std::runtime_error);
  auto quiet = make({{"max_deflection", std::vector<double>{0.5, 0.4, 0.3}}});
  CHECK(static_cast<FcuSerial&>(quiet.plugin()).actuator_mapping().max_deflection[2] == 0.3);
}

TEST_CASE("plugin: start() fails in one line when the FCU does not stream") {
  Pty pty;  // a port where nobody answers
  tern::testing::Harness h(std::make_unique<tern::fcu_serial::FcuSerial>(), {{"device", std::string(pty.name)}, {"connect_timeout", 0.3}});
  CHECK_THROWS_WITH_AS(h.start(), doctest::Contains("no IMU data (SMALL_IMU) from the FCU on serial"), std::runtime_error);
}

namespace {
/// Reads from fd until n bytes came or 5 s passed.
std::vector<std::uint8_t> read_n(int fd, std::size_t n) {
  std::vector<std::uint8_t> out;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (out.size() < n && std::chrono::steady_clock::now() < end) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 10) > 0) {
      std::uint8_t b[4096];
      const ssize_t r = ::read(fd, b, sizeof b);
      if (r > 0) out.insert(out.end(), b, b + r);
    }
  }
  return out;
}
}  // namespace

TEST_CASE("UartPort (--baud): every byte through, in order, both ways; a write larger than the transmit buffer dropped whole") {
  using tern::fcu::emulator::UartPort;
  auto pty = std::make_unique<tern::fcu::emulator::PtyPort>();
  const int slave = open(pty->name(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  REQUIRE(slave >= 0);
  UartPort uart(std::move(pty), 921600);
  CHECK(uart.byte_ns() == 10850);  // 10 bit times at 921600 baud, ns (rounded down)
  std::vector<std::uint8_t> out(3000), in(700);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<std::uint8_t>(i * 7);
  for (std::size_t i = 0; i < in.size(); ++i) in[i] = static_cast<std::uint8_t>(i * 13 + 1);
  CHECK(uart.write(out.data(), 1000));  // three writes: the line keeps their order
  CHECK(uart.write(out.data() + 1000, 1000));
  CHECK(uart.write(out.data() + 2000, 1000));
  CHECK(::write(slave, in.data(), in.size()) == static_cast<ssize_t>(in.size()));
  CHECK(read_n(slave, out.size()) == out);
  CHECK(read_n(uart.fd(), in.size()) == in);
  const std::vector<std::uint8_t> big(UartPort::kTxBuffer + 1, 0x55);
  CHECK_FALSE(uart.write(big.data(), big.size()));
  const UartPort::Stats st = uart.stats();
  CHECK(st.sent == out.size());
  CHECK(st.received == in.size());
  CHECK(st.dropped_writes == 1);
  CHECK(st.dropped_bytes == big.size());
  close(slave);
  CHECK_THROWS_WITH_AS(UartPort(std::make_unique<tern::fcu::emulator::PtyPort>(), 100), doctest::Contains("--baud 100: not a UART's rate"),
                       std::runtime_error);
}

#ifdef TERN_FCU_EMULATOR

namespace {
const std::string kAircraft = TERN_AIRCRAFT_DIR "/anaconda.yaml";

std::string run(const std::string& cmd, int& status) {
  std::string out;
  FILE* f = popen(cmd.c_str(), "r");
  REQUIRE(f != nullptr);
  char buf[512];
  while (std::fgets(buf, sizeof buf, f)) out += buf;
  status = pclose(f);
  return out;
}

std::string start_emulator(std::unique_ptr<ChildProcess>& p, std::vector<std::string> args) {
  std::vector<std::string> argv{TERN_FCU_EMULATOR, "--aircraft", kAircraft};
  argv.insert(argv.end(), args.begin(), args.end());
  p = std::make_unique<ChildProcess>(argv);
  const std::string line = p->read_line(10'000'000'000);
  REQUIRE(line.rfind("pty: ", 0) == 0);
  return line.substr(5);
}
}  // namespace

TEST_CASE("tern fcu param list/get/set against the emulator") {
  std::unique_ptr<ChildProcess> emu;
  const std::string pty = start_emulator(emu, {"--speed", "1"});
  const std::string tool = std::string(TERN_FCU_TERN_FCU) + " --device " + pty + " ";
  int st = -1;
  std::string out = run(tool + "param get RC_ATT_OVRD_CHN", st);
  CHECK(st == 0);
  CHECK(out == "4\n");  // the firmware's default (param.cpp)
  out = run(tool + "param set MOTOR_IDLE_THR 0.15 --write", st);
  CHECK(st == 0);
  CHECK(out == "MOTOR_IDLE_THR = 0.150000006\nwritten to flash\n");
  out = run(tool + "param get MOTOR_IDLE_THR", st);
  CHECK(out == "0.150000006\n");
  out = run(tool + "param list", st);
  CHECK(st == 0);
  CHECK(std::count(out.begin(), out.end(), '\n') == static_cast<long>(tern::fcu::firmware::Params::defaults().size()));
  CHECK(out.find("PRIMARY_MIXER               255  int32") != std::string::npos);
  out = run(tool + "param set MOTOR_IDLE_THR 0.15", st);  // the current value: confirmed by reading back
  CHECK(st == 0);
  out = run(tool + "param set RC_ATT_OVRD_CHN 2.5 2>&1", st);
  CHECK(st != 0);
  CHECK(out.find("integer parameter") != std::string::npos);
  out = run(tool + "param get NO_SUCH_PARAM 2>&1", st);
  CHECK(st != 0);
  CHECK(out.find("has no parameter NO_SUCH_PARAM") != std::string::npos);
}

TEST_CASE("tern fcu status against the emulator over a UART-paced pseudo-terminal: state and the TIMESYNC round trip") {
  std::unique_ptr<ChildProcess> emu;
  const std::string pty = start_emulator(emu, {"--speed", "1", "--baud", "921600", "--rc", "0 throttle=0"});
  int st = -1;
  const std::string out = run(std::string(TERN_FCU_TERN_FCU) + " --device " + pty + " status --samples 5 --rate 20", st);
  CHECK(st == 0);
  CHECK(out.find("FCU:        system 1 on serial " + pty + " @ 921600, firmware ") == 0);
  CHECK(out.find("\nstate:      disarmed, failsafe off") != std::string::npos);  // the pilot never arms (--rc)
  double p50 = 0, p99 = 0, mx = 0;
  int answered = 0, sent = 0;
  const auto at = out.find("\nround trip: ");
  REQUIRE(at != std::string::npos);
  REQUIRE(std::sscanf(out.c_str() + at, "\nround trip: p50 %lf ms, p99 %lf ms, max %lf ms (TIMESYNC, %d of %d", &p50, &p99, &mx, &answered,
                      &sent) == 5);
  CHECK(sent == 5);
  CHECK(answered >= 1);
  CHECK(0 < p50);  // ordered, not timed
  CHECK(p50 <= p99);
  CHECK(p99 <= mx);
  int bad = -1;
  CHECK(run(std::string(TERN_FCU_TERN_FCU) + " --device " + pty + " status --samples 0 2>&1", bad).find("--samples") != std::string::npos);
  CHECK(bad != 0);
}

TEST_CASE("plugin: flies the emulator's aircraft in lockstep over a pseudo-terminal") {
  tern::testing::HarnessOptions ho;
  ho.aircraft_file = kAircraft;
  tern::testing::Harness h(std::make_unique<tern::fcu_serial::FcuSerial>(),
                           {{"emulator", true},
                            {"emulator_path", std::string(TERN_FCU_EMULATOR)},
                            {"lockstep", true},
                            {"emulator_params", std::string(TERN_FCU_PARAMS)},
                            {"emulator_rc", std::string("0 throttle=0 aux1=-1 aux2=-1; 0.02 aux2=1; 0.04 aux1=1; 0.06 aux2=-1")},
                            {"emulator_args", std::string("--init-mode air --init-altitude 100 --init-airspeed 17")}},
                           ho);
  auto& plugin = static_cast<tern::fcu_serial::FcuSerial&>(h.plugin());
  // The aircraft file's servo limits scale the pass-through commands (40 deg on the Anaconda).
  CHECK(plugin.actuator_mapping().max_deflection[1] == doctest::Approx(0.6981317));
  h.start();
  tern::msg::Actuators a;
  a.delta_e = -0.05;
  a.delta_t = 0.5;
  std::uint64_t imu_count = 0;
  tern::Nanos last_imu = -1;
  bool offboard_seen = false;
  const tern::Nanos dt = 2'500'000;
  for (tern::Nanos t = 0; t <= tern::from_seconds(3.0); t += dt) {
    a.stamp = t;
    h.set_input("actuators", a);
    h.step(t);
    const auto& imu = h.output<tern::msg::Imu>("imu");
    if (h.published("imu") > imu_count) {
      imu_count = h.published("imu");
      CHECK(imu.stamp == t);  // lockstep: the sample of this step's time, every step
      CHECK(imu.stamp > last_imu);
      last_imu = imu.stamp;
    }
    if (h.published("fcu_status") > 0 && h.output<tern::msg::FcuStatus>("fcu_status").offboard) offboard_seen = true;
  }
  CHECK(imu_count == 1201);
  // Sensors in SI units, FRD body axes.
  const auto& imu = h.output<tern::msg::Imu>("imu");
  CHECK(imu.accel.norm() > 5.0);
  CHECK(imu.accel.norm() < 15.0);
  CHECK(imu.accel.z() < -5.0);  // lift: specific force points up (-z)
  CHECK(imu.gyro.norm() < 1.0);
  CHECK(imu.temperature > 250.0);
  const auto& baro = h.output<tern::msg::Baro>("baro");
  CHECK(baro.pressure > 80000.0);  // Provo origin (1387 m) + 100 m
  CHECK(baro.pressure < 88000.0);
  const auto& dp = h.output<tern::msg::DiffPressure>("diff_pressure");
  CHECK(dp.pressure > 20.0);  // 0.5 rho Va^2: flying (17 m/s at the start)
  CHECK(dp.pressure < 400.0);
  const auto& mag = h.output<tern::msg::Mag>("mag");
  CHECK(mag.field.norm() == doctest::Approx(5.07e-5).epsilon(0.2));
  const auto& gnss = h.output<tern::msg::Gnss>("gnss");
  CHECK(gnss.fix_type == tern::msg::FixType::fix_3d);
  CHECK(gnss.lat == doctest::Approx(40.2463724).epsilon(1e-3));
  CHECK(gnss.alt == doctest::Approx(1487.0).epsilon(0.02));
  CHECK(gnss.vel.head<2>().norm() > 5.0);
  CHECK(gnss.stamp <= tern::from_seconds(3.0));
  CHECK(h.published("mag") >= 145);
  CHECK(h.published("baro") >= 295);
  CHECK(h.published("gnss") >= 29);
  CHECK(h.published("rc") >= 145);
  const auto& rc = h.output<tern::msg::Rc>("rc");
  CHECK(rc.aux[1] == doctest::Approx(-1.0));  // override switch off
  CHECK_FALSE(rc.rc_override);
  CHECK(offboard_seen);
  CHECK(h.output<tern::msg::FcuStatus>("fcu_status").armed);
  // The commands reached the FCU: its servo outputs (ROSFLIGHT_OUTPUT_RAW) are the commands.
  REQUIRE(plugin.last_output_raw().has_value());
  CHECK(plugin.last_output_raw()->values[1] == doctest::Approx(0.5 - 0.5 * 0.05 / 0.6981317).epsilon(0.01));
  CHECK(plugin.last_output_raw()->values[4] == doctest::Approx(0.5).epsilon(0.01));
  CHECK(plugin.commands_sent() == 1200);
  CHECK(plugin.timesync().synced());
  CHECK(plugin.fcu_version().find("tern-fcu-emulator") == 0);
  const auto stats = plugin.link_stats();
  CHECK(stats.parser.bad_crc == 0);
  CHECK(stats.queue_dropped == 0);
  h.stop();
}

TEST_CASE("plugin: in lockstep an FCU that falls silent ends the flight in one line (no commands on a frozen state)") {
  std::unique_ptr<ChildProcess> emu;  // the FCU stops after 0.5 s of its time (power lost, cable pulled)
  const std::string pty = start_emulator(emu, {"--lockstep", "--duration", "0.5", "--init-mode", "air", "--params", TERN_FCU_PARAMS});
  tern::testing::HarnessOptions ho;
  ho.aircraft_file = kAircraft;
  tern::testing::Harness h(std::make_unique<tern::fcu_serial::FcuSerial>(),
                           {{"device", pty}, {"lockstep", true}, {"wait_timeout", 0.1}, {"link_timeout", 0.3}}, ho);
  h.start();
  std::string error;
  tern::Nanos t = 0;
  const auto wall0 = std::chrono::steady_clock::now();
  try {
    for (; t <= tern::from_seconds(10.0); t += 2'500'000) h.step(t);
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  CHECK(error.find("lockstep: nothing from the FCU for") == 0);
  CHECK(t > tern::from_seconds(0.49));  // the last sample it sent
  CHECK(t < tern::from_seconds(0.6));
  CHECK(std::chrono::steady_clock::now() - wall0 < std::chrono::seconds(3));
  h.stop();
}

TEST_CASE("plugin: link loss, FCU reboot, RC override and corrupted bytes are reported and survived") {
  tern::testing::HarnessOptions ho;
  ho.aircraft_file = kAircraft;
  tern::testing::Harness h(
      std::make_unique<tern::fcu_serial::FcuSerial>(),
      {{"emulator", true},
       {"emulator_path", std::string(TERN_FCU_EMULATOR)},
       {"link_timeout", 0.3},
       {"wait_timeout", 0.1},
       {"emulator_args",
        std::string("--init-mode air --speed 1 --silence 0.5:1.2 --reboot-at 1.6 --corrupt 0.01 --params " + std::string(TERN_FCU_PARAMS))},
       {"emulator_rc", std::string("0 throttle=0 aux1=-1 aux2=-1; 0.1 aux2=1; 0.15 aux1=1; 0.2 aux2=-1; 2.0 aux2=1; 2.4 aux2=-1")}},
      ho);
  auto& plugin = static_cast<tern::fcu_serial::FcuSerial&>(h.plugin());
  h.start();
  tern::msg::Actuators a;
  a.delta_t = 0.5;
  bool override_seen = false, override_cleared = false;
  tern::Nanos t = 0;
  const auto wall0 = std::chrono::steady_clock::now();
  tern::Nanos last_imu = -1;
  bool monotonic = true;
  while (std::chrono::steady_clock::now() - wall0 < std::chrono::milliseconds(3000)) {
    h.set_input("actuators", a);
    h.step(t);
    if (h.published("imu") > 0) {
      const auto s = h.output<tern::msg::Imu>("imu").stamp;
      if (s < last_imu) monotonic = false;
      last_imu = s;
    }
    if (h.published("fcu_status") > 0) {
      const auto& st = h.output<tern::msg::FcuStatus>("fcu_status");
      if (st.rc_override) override_seen = true;
      if (override_seen && !st.rc_override) override_cleared = true;
    }
    t += 2'500'000;
  }
  CHECK(plugin.link_losses() >= 1);  // the silence (a loaded machine may add a late one)
  CHECK(plugin.reboots() == 1);
  CHECK(override_seen);
  CHECK(override_cleared);
  CHECK(monotonic);  // flight time never goes back, across the silence and the reboot
  const auto stats = plugin.link_stats();
  CHECK(stats.parser.bad_crc + stats.parser.bad_length + stats.parser.unknown_id > 0);
  CHECK(stats.parser.frames > 1000);  // about 820 frames per second, 1 s of silence
  h.stop();
}

TEST_CASE("plugin: UDP (ROSflight SIL ports) and the wall clock mapped with TIMESYNC") {
  std::unique_ptr<ChildProcess> emu;
  {
    // a configured FCU (mixer, arm switch) that the emulated pilot arms within 0.06 s: the
    // firmware boots disarmed and its motor output stays 0 until then (state_manager.cpp)
    std::vector<std::string> argv{TERN_FCU_EMULATOR,
                                  "--aircraft",
                                  kAircraft,
                                  "--udp",
                                  "--udp-port",
                                  std::to_string(udp_port(1)),
                                  "--udp-remote-port",
                                  std::to_string(udp_port(0)),
                                  "--speed",
                                  "1",
                                  "--init-mode",
                                  "air",
                                  "--params",
                                  TERN_FCU_PARAMS,
                                  "--rc",
                                  "0 throttle=0 aux1=-1 aux2=-1; 0.02 aux2=1; 0.04 aux1=1; 0.06 aux2=-1"};
    emu = std::make_unique<ChildProcess>(argv);
    REQUIRE(emu->read_line(10'000'000'000) == "udp: 127.0.0.1:" + std::to_string(udp_port(1)));
  }
  tern::testing::HarnessOptions ho;
  ho.aircraft_file = kAircraft;
  tern::testing::Harness h(std::make_unique<tern::fcu_serial::FcuSerial>(),
                           {{"transport", std::string("udp")},
                            {"udp_bind_port", std::int64_t{udp_port(0)}},
                            {"udp_remote_port", std::int64_t{udp_port(1)}},
                            {"clock", std::string("wall")},
                            {"timesync_rate", 50.0}},
                           ho);
  auto& plugin = static_cast<tern::fcu_serial::FcuSerial&>(h.plugin());
  h.start();
  tern::msg::Actuators a;
  a.delta_a = 0.1;
  a.delta_t = 0.7;
  // step on the wall clock, as `tern fly --realtime` does
  const auto wall0 = std::chrono::steady_clock::now();
  tern::Nanos now = 0;
  while (now < tern::from_seconds(1.5)) {
    h.set_input("actuators", a);
    h.step(now);
    if (h.published("imu") > 0) {
      const auto stamp = h.output<tern::msg::Imu>("imu").stamp;
      CHECK(stamp <= now);
    }
    now += 2'500'000;
    std::this_thread::sleep_until(wall0 + std::chrono::nanoseconds(now));
  }
  CHECK(plugin.timesync().synced());
  CHECK(plugin.timesync().last_rtt() < 20'000'000);
  CHECK(plugin.timesync().samples() >= 20);
  // the samples are recent: stamped within a few ticks of the wall clock
  const auto& imu = h.output<tern::msg::Imu>("imu");
  CHECK(imu.stamp > now - 250'000'000);
  CHECK(h.published("imu") > 400);
  CHECK(h.published("baro") > 100);
  REQUIRE(plugin.last_output_raw().has_value());
  CHECK(plugin.last_output_raw()->values[0] == doctest::Approx(0.5 + 0.5 * 0.1 / 0.6981317).epsilon(0.02));
  CHECK(plugin.last_output_raw()->values[4] == doctest::Approx(0.7).epsilon(0.01));
  CHECK(h.output<tern::msg::FcuStatus>("fcu_status").armed);
  h.stop();
}

#endif
