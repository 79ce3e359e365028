// plugin_link.cpp: fcu_serial's link to the FCU: opening it (or starting tern-fcu-emulator
// behind a pseudo-terminal), what we send (HEARTBEAT, TIMESYNC, OFFBOARD_CONTROL), link loss,
// and the flight summary. See fcu_serial_plugin.hpp.
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>

#include <sys/socket.h>
#include <unistd.h>

#include <spdlog/spdlog.h>

#include "fcu_serial_plugin.hpp"
#include "tern_fcu_serial/fcu_side.hpp"

namespace tern::fcu_serial {

namespace {
fcu::HostTime host_now() { return {fcu::steady_ns()}; }
constexpr std::int64_t kEmulatorPortTimeout = 10'000'000'000;  // ns: the emulator announces its port
}  // namespace

FcuSerial::~FcuSerial() { shutdown(); }

fcu::LinkOptions FcuSerial::link_options() const {
  fcu::LinkOptions o;
  o.kind = transport_() == "udp" ? fcu::LinkOptions::Kind::udp : fcu::LinkOptions::Kind::serial;
  o.device = device_();
  o.baud = static_cast<unsigned>(baud_());
  o.udp_host = udp_host_();
  o.udp_bind_port = static_cast<unsigned>(udp_bind_port_());
  o.udp_remote_port = static_cast<unsigned>(udp_remote_port_());
  return o;
}

void FcuSerial::start() {
  shutdown();
  take_start_params();
  fcu::LinkOptions o = link_options();
  if (emulator_()) {
    start_emulator();
    o.kind = emulator_socket_ >= 0 ? fcu::LinkOptions::Kind::socket : fcu::LinkOptions::Kind::serial;
    o.device = emulator_device_;
    o.socket_fd = emulator_socket_;
  }
  enc_ = std::make_unique<mav::Encoder>(static_cast<std::uint8_t>(system_id_()), static_cast<std::uint8_t>(component_id_()));
  link_ = std::make_unique<fcu::Link>(o);
  link_->start();
  log().info("link {} open", o.describe());
  s_ = Session{};
  s_.last_rx = host_now();
  clock_ = fcu::FcuClock(policy_, tern::from_seconds(link_timeout_()));
  send_heartbeat();
  send_timesync();
  mav::RosflightCmd ver;
  ver.command = static_cast<std::uint8_t>(fcu::RosflightCmd::send_version);
  send(ver);
  wait_first_imu(o);
  start_calibration();
}

/// `calibrate`: the ROSFLIGHT_CMD of that calibration, as `tern fcu calibrate` sends it; the
/// FCU's answer (CMD_ACK) and verdict (STATUSTEXT, e.g. "IMU offsets captured") are logged as
/// every FCU message is.
void FcuSerial::start_calibration() {
  static const std::map<std::string, fcu::RosflightCmd> kinds = {{"imu", fcu::RosflightCmd::accel_calibration},
                                                                 {"gyro", fcu::RosflightCmd::gyro_calibration},
                                                                 {"baro", fcu::RosflightCmd::baro_calibration},
                                                                 {"airspeed", fcu::RosflightCmd::airspeed_calibration}};
  const auto k = kinds.find(calibrate_());
  if (k == kinds.end()) return;
  mav::RosflightCmd cmd;
  cmd.command = static_cast<std::uint8_t>(k->second);
  send(cmd);
  log().info("asked the FCU for its {} calibration", calibrate_());
}

/// start(): the FCU's first IMU sample within connect_timeout, or one line saying so.
void FcuSerial::wait_first_imu(const fcu::LinkOptions& o) {
  const std::int64_t begin = fcu::steady_ns(), deadline = begin + tern::from_seconds(connect_timeout_());
  while (!has_imu_pending()) {
    const std::int64_t left = deadline - fcu::steady_ns();
    if (left <= 0) {
      const std::string what = o.describe();
      shutdown();
      throw std::runtime_error("no IMU data (SMALL_IMU) from the FCU on " + what + " within " + std::to_string(connect_timeout_()) +
                               " s: is it powered, on this port and streaming?");
    }
    link_->wait(left);
    pull();
  }
  log().info("FCU streaming (first IMU sample after {:.3f} s)", tern::to_seconds(fcu::steady_ns() - begin));
}

void FcuSerial::reset() {
  // Between flights the flight clock restarts: FCU time is anchored again on the next sample.
  clock_.restart();
  s_.last_cmd_index = -1;
  s_.first_step_now.reset();
}

void FcuSerial::stop() {
  if (link_) log_link_summary();
  shutdown();
}

void FcuSerial::shutdown() {
  if (link_) {
    final_stats_ = link_->stats();
    link_->stop();
    link_.reset();
  }
  if (emulator_proc_) {
    emulator_proc_->stop();
    emulator_proc_.reset();
  }
  if (emulator_socket_ >= 0) close(emulator_socket_);
  emulator_socket_ = -1;
}

/// emulator_path, else the emulator's program (tern-fcu-emulator, or tern-fcu-sil for the real
/// firmware) next to the tern command, else on PATH.
std::string FcuSerial::find_emulator() const {
  if (!emulator_path_().empty()) return emulator_path_();
  const bool sil = emulator_firmware_() == "rosflight";
  const std::string program = sil ? "tern-fcu-sil" : "tern-fcu-emulator";
  std::vector<std::filesystem::path> dirs{fcu::executable_dir()};
  if (const char* path = std::getenv("PATH")) {
    std::stringstream ss(path);
    for (std::string dir; std::getline(ss, dir, ':');) dirs.emplace_back(dir);
  }
  for (const auto& dir : dirs)
    if (!dir.empty() && std::filesystem::exists(dir / program)) return (dir / program).string();
  throw std::runtime_error("parameter '" + qname("emulator") + "': " + program + " not found next to the tern command nor on PATH" +
                           (sil ? " (it is built when CMake is given a rosflight_firmware tree: -DTERN_ROSFLIGHT_FIRMWARE_DIR=...)"
                                : " (set " + qname("emulator_path") + ")"));
}

/// emulator_link socket: a connected pair of local stream sockets (a byte stream without the
/// terminal layer); ours stays in emulator_socket_, the child's end is returned and argv names it.
int FcuSerial::socket_pair(std::vector<std::string>& argv) {
  int sv[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0)
    throw std::runtime_error("parameter '" + qname("emulator_link") + "': socketpair failed: " + std::strerror(errno));
  emulator_socket_ = sv[0];
  argv.insert(argv.end(), {"--fd", std::to_string(fcu::ChildProcess::kPassedFd)});
  return sv[1];
}

void FcuSerial::start_emulator() {
  const std::string exe = find_emulator();
  std::vector<std::string> argv{exe, "--exit-with-parent", "--seed", std::to_string(context().seed())};
  const std::filesystem::path ac = context().aircraft_file();
  if (!ac.empty()) argv.insert(argv.end(), {"--aircraft", ac.string()});
  if (lockstep_()) argv.push_back("--lockstep");
  if (!emulator_params_().empty()) {
    std::filesystem::path p = emulator_params_();
    if (p.is_relative() && !context().config_dir().empty()) p = context().config_dir() / p;
    argv.insert(argv.end(), {"--params", p.string()});
  }
  argv.insert(argv.end(), {"--rc", emulator_rc_()});
  std::stringstream ss(emulator_args_());
  for (std::string a; ss >> a;) argv.push_back(a);
  const int child_end = emulator_link_() == "socket" ? socket_pair(argv) : -1;
  try {
    emulator_proc_ = std::make_unique<fcu::ChildProcess>(argv, child_end);
  } catch (...) {
    if (child_end >= 0) close(child_end);
    throw;
  }
  if (child_end >= 0) close(child_end);
  for (;;) {
    std::string line;
    try {
      line = emulator_proc_->read_line(kEmulatorPortTimeout);
    } catch (const std::exception& e) {
      emulator_proc_.reset();
      throw std::runtime_error(exe + " did not report its port: " + e.what());
    }
    if (line.rfind("pty: ", 0) == 0 || line.rfind("fd: ", 0) == 0) {
      emulator_device_ = line.substr(line.find(' ') + 1);
      break;
    }
  }
  log().info("{} (pid {}) on {}", exe, emulator_proc_->pid(), emulator_device_);
}

void FcuSerial::send_heartbeat() {
  mav::Heartbeat h;
  h.type = 18;      // MAV_TYPE_ONBOARD_CONTROLLER
  h.autopilot = 8;  // MAV_AUTOPILOT_INVALID: not an autopilot of its own
  h.mavlink_version = 3;
  send(h);
  s_.last_heartbeat = host_now();
}

void FcuSerial::send_timesync() {
  s_.last_timesync = host_now();
  send(fcu::TimeSync::request(s_.last_timesync.ns));
}

void FcuSerial::send_command() {
  mav::OffboardControl c;
  if (actuators_in_.has_value()) {
    const msg::Actuators& a = actuators_in_.get();
    c = fcu::to_offboard({a.delta_a, a.delta_e, a.delta_r, a.delta_t}, map_);
  } else {
    c.mode = fcu::kModePassThrough;
    c.ignore = 0x3FF;  // nothing to command yet: every channel ignored (the FCU keeps RC)
  }
  send(c);
  ++s_.commands_sent;
}

/// Free-running: OFFBOARD_CONTROL at command_rate and whenever `actuators` changes (lockstep:
/// one per IMU sample, in step()); HEARTBEAT and TIMESYNC at their rates.
void FcuSerial::send_due(tern::Nanos now) {
  if (!lockstep_()) {
    const std::int64_t index = now / tern::period_from_hz(command_rate_());
    if (actuators_in_.updated() || index != s_.last_cmd_index) {
      s_.last_cmd_index = index;
      send_command();
    }
  }
  const fcu::HostTime h = host_now();
  if (h.ns - s_.last_heartbeat.ns >= tern::from_seconds(1.0 / heartbeat_rate_())) send_heartbeat();
  if (h.ns - s_.last_timesync.ns >= tern::from_seconds(1.0 / timesync_rate_())) send_timesync();
}

/// Nothing received for link_timeout: lost (one line, counted); frames again: restored, and
/// FCU time is anchored again at the current flight time.
void FcuSerial::check_link(fcu::HostTime host) {
  const std::int64_t timeout = tern::from_seconds(link_timeout_());
  if (!s_.link_lost && host.ns - s_.last_rx.ns > timeout) {
    s_.link_lost = true;
    s_.lost_at = s_.last_rx;
    clock_.follow_host(host, fcu::FlightTime{s_.last_step_now});
    ++s_.link_losses;
    log().warn("link to the FCU lost: nothing received for {:.2f} s ({}); the FCU flies its failsafe/RC",
               tern::to_seconds(host.ns - s_.last_rx.ns), link_->options().describe());
  } else if (s_.link_lost && host.ns - s_.last_rx.ns <= timeout) {
    s_.link_lost = false;
    clock_.reanchor();
    log().warn("link to the FCU restored after {:.2f} s", tern::to_seconds(s_.last_rx.ns - s_.lost_at.ns));
  }
}

void FcuSerial::log_link_summary() {
  const fcu::LinkStats s = link_->stats();
  const fcu::TimeSync& ts = clock_.timesync();
  const fcu::TimeSync::RttStats rtt = ts.rtt_stats();
  log().info(
      "link: {} frames, {} bad CRC, {} unknown id, {} bad length, {} bytes skipped, {} queue drops, "
      "{} commands sent, {} link losses, {} reboots, TIMESYNC offset {:.3f} s, round trip p50 {:.3f} p99 {:.3f} max {:.3f} ms "
      "({} answers, {} too slow)",
      s.parser.frames, s.parser.bad_crc, s.parser.unknown_id, s.parser.bad_length, s.parser.skipped, s.queue_dropped, s_.commands_sent,
      s_.link_losses, s_.reboots, ts.offset() * 1e-9, rtt.p50 * 1e-6, rtt.p99 * 1e-6, rtt.max * 1e-6, ts.samples(), ts.rejected());
}

std::string FcuSerial::health() const {
  const fcu::LinkStats s = final_stats_;
  if (s_.link_losses == 0 && s_.reboots == 0 && s.parser.bad_crc == 0 && s.parser.skipped == 0) return {};
  return fmt::format("{} link losses, {} FCU reboots, {} bad CRC, {} bytes skipped ({} frames)", s_.link_losses, s_.reboots,
                     s.parser.bad_crc, s.parser.skipped, s.parser.frames);
}

std::vector<std::pair<std::string, double>> FcuSerial::summary() const {
  const fcu::LinkStats s = final_stats_;
  auto n = [](std::uint64_t v) { return static_cast<double>(v); };
  return {{"fcu_bad_crc", n(s.parser.bad_crc)},
          {"fcu_skipped_bytes", n(s.parser.skipped)},
          {"fcu_unknown_id", n(s.parser.unknown_id)},
          {"fcu_bad_length", n(s.parser.bad_length)},
          {"fcu_seq_gaps", n(s.parser.seq_gaps)},
          {"fcu_queue_dropped", n(s.queue_dropped)},
          {"fcu_commands_sent", n(s_.commands_sent)},
          {"fcu_link_losses", n(s_.link_losses)},
          {"fcu_reboots", n(s_.reboots)},
          {"fcu_imu_superseded", n(s_.imu_superseded)},
          {"fcu_lockstep_resends", n(s_.lockstep_resends)}};
}

/// Wall-clock figures (timing.json): frames, and the TIMESYNC round trips of the flight (the
/// answers counted, so that a 0 without answers is not read as a 0-ms link).
std::vector<std::pair<std::string, double>> FcuSerial::timing() const {
  const fcu::TimeSync& ts = clock_.timesync();
  const fcu::TimeSync::RttStats rtt = ts.rtt_stats();
  return {
      {"fcu_frames", static_cast<double>(final_stats_.parser.frames)},  {"fcu_timesync_answers", static_cast<double>(rtt.count)},
      {"fcu_timesync_too_slow", static_cast<double>(ts.rejected())},    {"fcu_timesync_rtt_ms", static_cast<double>(ts.last_rtt()) * 1e-6},
      {"fcu_timesync_rtt_p50_ms", static_cast<double>(rtt.p50) * 1e-6}, {"fcu_timesync_rtt_p99_ms", static_cast<double>(rtt.p99) * 1e-6},
      {"fcu_timesync_rtt_max_ms", static_cast<double>(rtt.max) * 1e-6}};
}

}  // namespace tern::fcu_serial
