// fcu_serial_plugin.hpp: the tern plugin that flies through a ROSflight flight-control unit (FCU)
// over its MAVLink link (serial port or UDP), or through tern-fcu-emulator. See README.md.
//
// Time. With clock "fcu" (default) the FCU's clock drives the flight: the first IMU sample is
// flight time `now` of the first step, later samples are stamped with their FCU time relative
// to it, and step(now) waits (at most wait_timeout) until the FCU has sent the IMU sample of
// time `now`. The host's lockstep clock then follows the FCU: about wall time with a real FCU
// (with or without --realtime), faster with the emulator in lockstep. With clock "wall", FCU
// times are mapped to this computer's steady clock with TIMESYNC and flight time is that clock
// since the first step (for a host that runs in real time, `tern fly --realtime`); step() never
// waits. Messages without an FCU time stamp (SMALL_MAG, SMALL_BARO, DIFF_PRESSURE,
// ROSFLIGHT_STATUS) take the stamp of the IMU sample before them in the stream ("fcu") or their
// arrival time ("wall"). The host's base rate should equal the FCU's IMU rate (400 Hz).
#pragma once

#include <algorithm>
#include <cmath>
#include <deque>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include "tern/plugin.hpp"
#include "tern_fcu_serial/codec.hpp"
#include "tern_fcu_serial/fcu_side.hpp"
#include "tern_fcu_serial/link.hpp"
#include "tern_fcu_serial/mapping.hpp"
#include "tern_fcu_serial/process.hpp"
#include "tern_fcu_serial/status.hpp"
#include "tern_fcu_serial/timesync.hpp"

namespace tern::fcu_serial {

using tern::Nanos;
using tern::ParamError;
using tern::ParamSpec;
namespace msg = tern::msg;
namespace fcu = tern::fcu;
namespace mav = tern::fcu::mavlink;

class FcuSerial final : public tern::Plugin {
 public:
  ~FcuSerial() override { shutdown(); }

  void configure() override {
    declare(actuators_in_, "actuators", "surface deflections (rad) and throttle (0..1) sent to the FCU",
            tern::Need::optional);
    declare(imu_out_, "imu", "FCU accelerometer and gyro (SMALL_IMU)");
    declare(gnss_out_, "gnss", "FCU GNSS receiver (ROSFLIGHT_GNSS)");
    declare(baro_out_, "baro", "FCU barometer (SMALL_BARO)");
    declare(diff_out_, "diff_pressure", "FCU pitot differential pressure (DIFF_PRESSURE)");
    declare(mag_out_, "mag", "FCU magnetometer (SMALL_MAG)");
    declare(rc_out_, "rc", "RC receiver as the FCU reports it (RC_CHANNELS), with override and failsafe");
    declare(status_out_, "fcu_status", "FCU status (ROSFLIGHT_STATUS)");

    declare(transport_, "transport", "serial",
            ParamSpec("", 0, 0, "link to the FCU: serial port or UDP (ROSflight SIL)").one_of({"serial", "udp"}));
    declare(device_, "device", "/dev/ttyACM0", ParamSpec("", 0, 0, "serial device of the FCU"));
    declare(baud_, "baud", std::int64_t{921600}, ParamSpec("baud", 9600, 4000000, "serial baud rate"));
    declare(udp_host_, "udp_host", "127.0.0.1", ParamSpec("", 0, 0, "IP address of both UDP ends"));
    declare(udp_bind_port_, "udp_bind_port", std::int64_t{14520}, ParamSpec("", 1, 65535, "our UDP port (rosflight_io: 14520)"));
    declare(udp_remote_port_, "udp_remote_port", std::int64_t{14525}, ParamSpec("", 1, 65535, "the FCU's UDP port (ROSflight SIL: 14525)"));
    declare(clock_, "clock", "fcu",
            ParamSpec("", 0, 0, "time source: the FCU's IMU stamps pace the flight, or the wall clock (TIMESYNC)").one_of({"fcu", "wall"}));
    declare(lockstep_, "lockstep", false,
            ParamSpec("", 0, 0, "one OFFBOARD_CONTROL per IMU sample, before waiting for the next (tern-fcu-emulator --lockstep)"));
    declare(connect_timeout_, "connect_timeout", 5.0, ParamSpec("s", 0.1, 120, "start() fails without an IMU sample within this time"));
    declare(wait_timeout_, "wait_timeout", 0.25, ParamSpec("s", 0, 10, "clock fcu: longest wait of one step for the FCU's sample"));
    declare(link_timeout_, "link_timeout", 0.5, ParamSpec("s", 0.01, 60, "no frame for this long: link lost (reported)"));
    declare(command_rate_, "command_rate", 100.0, ParamSpec("Hz", 50, 1000, "least rate of OFFBOARD_CONTROL (the FCU falls back to RC after 100 ms)"));
    declare(heartbeat_rate_, "heartbeat_rate", 1.0, ParamSpec("Hz", 0.1, 50, "rate of our HEARTBEAT"));
    declare(timesync_rate_, "timesync_rate", 10.0, ParamSpec("Hz", 0.1, 100, "rate of TIMESYNC requests"));
    declare(max_deflection_, "max_deflection", std::vector<double>{},
            ParamSpec("rad", 0.01, 3.2, "aileron, elevator, rudder deflection at full pass-through command; empty: the aircraft file's servos limits (else 45 deg)"));
    declare(channels_, "channels", "Qx Qy Qz Fx",
            ParamSpec("", 0, 0, "the firmware's channel (Fx Fy Fz Qx Qy Qz) of aileron, elevator, rudder, throttle: "
                                "its fixed-wing mixer routes Qx Qy Qz to the aileron, elevator, rudder servos and Fx to the motor"));
    declare(signs_, "signs", std::vector<double>{1, 1, 1, 1},
            ParamSpec("", -1, 1, "+1 or -1 per aileron, elevator, rudder, throttle").of_size(4));
    declare(rc_channels_, "rc_channels", std::vector<double>{0, 1, 3, 2},
            ParamSpec("", 0, 17, "RC channel (0-based) of roll, pitch, yaw, throttle (ROSflight AETR)").of_size(4));
    declare(rc_aux_channels_, "rc_aux_channels", std::vector<double>{4, 5, 6, 7},
            ParamSpec("", 0, 17, "RC channels of aux[0..3]").of_size(4));
    declare(rc_signs_, "rc_signs", std::vector<double>{1, 1, 1},
            ParamSpec("", -1, 1, "+1 or -1 per roll, pitch, yaw stick").of_size(3));
    declare(mag_scale_, "mag_scale", 1.0, ParamSpec("T", 1e-12, 1, "tesla per unit of SMALL_MAG (1: the FCU reports T)"));
    declare(system_id_, "system_id", std::int64_t{1}, ParamSpec("", 1, 255, "our MAVLink system id"));
    declare(component_id_, "component_id", std::int64_t{50}, ParamSpec("", 0, 255, "our MAVLink component id (rosflight_io: 50)"));
    declare(emulator_, "emulator", false,
            ParamSpec("", 0, 0, "start tern-fcu-emulator (sim_aero's aircraft behind a pseudo-terminal) and fly through it"));
    declare(emulator_args_, "emulator_args", "",
            ParamSpec("", 0, 0, "extra arguments of tern-fcu-emulator, e.g. \"--wind 3.5,-3.5,0 --turbulence light\""));
    declare(emulator_params_, "emulator_params", "",
            ParamSpec("", 0, 0, "the emulated FCU's stored parameters (YAML NAME: value, relative to the mission file); empty: firmware defaults"));
    declare(emulator_rc_, "emulator_rc", "0 throttle=0 aux1=-1 aux2=-1; 2 aux2=1; 2.1 aux1=1; 2.5 aux2=-1",
            ParamSpec("", 0, 0, "the emulated pilot's transmitter over time (tern-fcu-emulator --rc), or none"));
    declare(emulator_path_, "emulator_path", "",
            ParamSpec("", 0, 0, "tern-fcu-emulator executable; empty: next to the tern command, then PATH"));

    map_ = actuator_map(default_max_deflection());
    rc_map_ = rc_map();
    (void)tern::period_from_hz(command_rate_());
    if (context().describing()) return;
    if (max_deflection_().empty()) {
      map_ = actuator_map(aircraft_max_deflection());
      log().info("pass-through scaling: max deflection a {:.4f}, e {:.4f}, r {:.4f} rad", map_.max_deflection[0],
                 map_.max_deflection[1], map_.max_deflection[2]);
    }
  }

  void start() override {
    shutdown();
    fcu::LinkOptions o;
    o.kind = transport_() == "udp" ? fcu::LinkOptions::Kind::udp : fcu::LinkOptions::Kind::serial;
    o.device = device_();
    o.baud = static_cast<unsigned>(baud_());
    o.udp_host = udp_host_();
    o.udp_bind_port = static_cast<unsigned>(udp_bind_port_());
    o.udp_remote_port = static_cast<unsigned>(udp_remote_port_());
    if (emulator_()) {
      start_emulator();
      o.kind = fcu::LinkOptions::Kind::serial;
      o.device = emulator_device_;
    }
    enc_ = std::make_unique<mav::Encoder>(static_cast<std::uint8_t>(system_id_()), static_cast<std::uint8_t>(component_id_()));
    link_ = std::make_unique<fcu::Link>(o);
    link_->start();
    log().info("link {} open", o.describe());
    initialise_state();
    send_heartbeat();
    send_timesync();
    mav::RosflightCmd ver;
    ver.command = static_cast<std::uint8_t>(fcu::RosflightCmd::send_version);
    send(ver);
    // Wait for the FCU's first IMU sample.
    const std::int64_t deadline = fcu::steady_ns() + tern::from_seconds(connect_timeout_());
    while (!has_imu_pending()) {
      const std::int64_t left = deadline - fcu::steady_ns();
      if (left <= 0) {
        const std::string what = o.describe();
        shutdown();
        throw std::runtime_error("no IMU data (SMALL_IMU) from the FCU on " + what + " within " +
                                 std::to_string(connect_timeout_()) + " s: is it powered, on this port and streaming?");
      }
      link_->wait(left);
      pull();
    }
    log().info("FCU streaming (first IMU sample after {:.3f} s)",
               tern::to_seconds(fcu::steady_ns() - (deadline - tern::from_seconds(connect_timeout_()))));
  }

  void reset() override {
    // Between flights the flight clock restarts: re-anchor FCU time on the next IMU sample.
    anchored_ = false;
    last_cmd_index_ = -1;
  }

  void stop() override {
    if (link_) log_link_summary();
    shutdown();
  }

  void step(Nanos now) override {
    if (!link_) throw std::runtime_error("fcu_serial: step() before start()");
    for (auto& e : link_->take_events()) log().warn("{}", e);
    const std::int64_t wall = fcu::steady_ns();
    if (!wall_anchored_) {
      wall_anchored_ = true;
      wall_anchor_ = wall;
      wall_anchor_now_ = now;
    }
    if (lockstep_() && owed_command_) {
      send_command();  // the command for the IMU period that ends at `now` (before waiting for it)
      owed_command_ = false;
    }
    pull();
    if (clock_() == "fcu") {
      if (!link_lost_ && !imu_stalled_) {
        wait_for(now);
      } else {
        // The FCU is silent: flight time follows the wall clock until it speaks again (so the
        // host neither races ahead nor floods the link with commands).
        for (std::int64_t left; (left = lost_wall_ + (now - lost_now_) - fcu::steady_ns()) > 0;) {
          if (link_lost_ ? !pending_.empty() : !imu_stalled_) break;  // data again / an IMU sample again
          link_->wait(left);
          pull();
        }
      }
    }
    process(now);
    if (!first_step_now_) first_step_now_ = now;
    if (!rc_seen_ && !rc_warned_ && now - *first_step_now_ >= tern::from_seconds(1.0)) {
      rc_warned_ = true;
      log().warn("no RC_CHANNELS from the FCU in the first second: without a receiver the firmware never mixes "
                 "(command_manager.cpp mixes on a new RC frame), so the outputs will not move");
    }
    last_step_now_ = now;
    check_link(fcu::steady_ns());
    if (!lockstep_()) {
      const Nanos period = tern::period_from_hz(command_rate_());
      const std::int64_t index = now / period;
      if (actuators_in_.updated() || index != last_cmd_index_) {
        last_cmd_index_ = index;
        send_command();
      }
    }
    const std::int64_t w = fcu::steady_ns();
    if (w - last_heartbeat_ >= tern::from_seconds(1.0 / heartbeat_rate_())) send_heartbeat();
    if (w - last_timesync_ >= tern::from_seconds(1.0 / timesync_rate_())) send_timesync();
  }

  std::vector<std::pair<std::string, double>> summary() const override {
    const fcu::LinkStats s = final_stats_;
    return {{"fcu_frames", static_cast<double>(s.parser.frames)},
            {"fcu_bad_crc", static_cast<double>(s.parser.bad_crc)},
            {"fcu_skipped_bytes", static_cast<double>(s.parser.skipped)},
            {"fcu_unknown_id", static_cast<double>(s.parser.unknown_id)},
            {"fcu_bad_length", static_cast<double>(s.parser.bad_length)},
            {"fcu_seq_gaps", static_cast<double>(s.parser.seq_gaps)},
            {"fcu_queue_dropped", static_cast<double>(s.queue_dropped)},
            {"fcu_commands_sent", static_cast<double>(commands_sent_)},
            {"fcu_link_losses", static_cast<double>(link_losses_)},
            {"fcu_reboots", static_cast<double>(reboots_)},
            {"fcu_imu_superseded", static_cast<double>(imu_superseded_)},
            {"fcu_lockstep_resends", static_cast<double>(lockstep_resends_)},
            {"fcu_timesync_rtt_ms", static_cast<double>(timesync_.last_rtt()) * 1e-6}};
  }

  // ---- for tests ----
  std::uint64_t link_losses() const { return link_losses_; }
  std::uint64_t reboots() const { return reboots_; }
  std::uint64_t commands_sent() const { return commands_sent_; }
  const fcu::TimeSync& timesync() const { return timesync_; }
  const fcu::ActuatorMap& actuator_mapping() const { return map_; }
  const std::optional<mav::RosflightOutputRaw>& last_output_raw() const { return output_raw_; }
  const std::string& fcu_version() const { return version_; }
  fcu::LinkStats link_stats() const { return link_ ? link_->stats() : final_stats_; }

 private:
  // ---------------------------------------------------------------- configuration helpers
  std::array<double, 3> default_max_deflection() const {
    const auto& v = max_deflection_();
    if (v.empty()) return {0.785398, 0.785398, 0.785398};
    if (v.size() != 3)
      throw ParamError("parameter '" + qname("max_deflection") + "': needs 3 values [aileron, elevator, rudder], got " +
                       std::to_string(v.size()));
    return {v[0], v[1], v[2]};
  }
  std::array<double, 3> aircraft_max_deflection() const {
    std::array<double, 3> m{0.785398, 0.785398, 0.785398};
    const std::filesystem::path f = context().aircraft_file();
    if (f.empty() || !std::filesystem::exists(f)) return m;
    try {
      const YAML::Node doc = YAML::LoadFile(f.string());
      const YAML::Node s = doc["servos"];
      if (!s || !s.IsMap()) return m;
      const char* keys[] = {"max_delta_a", "max_delta_e", "max_delta_r"};
      for (int i = 0; i < 3; ++i)
        if (s[keys[i]]) m[i] = s[keys[i]].as<double>();
    } catch (const YAML::Exception& e) {
      throw std::runtime_error(f.string() + ": servos: " + e.what());
    }
    return m;
  }
  std::string qname(const std::string& p) const { return context().instance_name() + "." + p; }
  static int as_index(double v, const std::string& name) {
    if (v != std::floor(v)) throw ParamError("parameter '" + name + "': channel " + std::to_string(v) + " is not a whole number");
    return static_cast<int>(v);
  }
  fcu::ActuatorMap actuator_map(std::array<double, 3> maxd) const {
    fcu::ActuatorMap m;
    std::stringstream words(channels_());
    std::vector<std::string> names;
    for (std::string w; words >> w;) names.push_back(w);
    if (names.size() != 4)
      throw ParamError("parameter '" + qname("channels") + "': needs 4 names (aileron elevator rudder throttle), got '" + channels_() + "'");
    for (int i = 0; i < 4; ++i) {
      try {
        m.channel[i] = fcu::channel_index(names[static_cast<std::size_t>(i)]);
      } catch (const std::invalid_argument& e) {
        throw ParamError("parameter '" + qname("channels") + "': " + e.what());
      }
      m.sign[i] = signs_()[i];
    }
    m.max_deflection = maxd;
    try {
      m.validate();
    } catch (const std::invalid_argument& e) {
      throw ParamError("parameter '" + qname("channels/signs/max_deflection") + "': " + e.what());
    }
    return m;
  }
  fcu::RcMap rc_map() const {
    fcu::RcMap m;
    for (int i = 0; i < 4; ++i) {
      m.stick_channel[i] = as_index(rc_channels_()[i], qname("rc_channels"));
      m.aux_channel[i] = as_index(rc_aux_channels_()[i], qname("rc_aux_channels"));
    }
    for (int i = 0; i < 3; ++i) m.sign[i] = rc_signs_()[i];
    try {
      m.validate();
    } catch (const std::invalid_argument& e) {
      throw ParamError("parameter '" + qname("rc_channels/rc_aux_channels/rc_signs") + "': " + e.what());
    }
    return m;
  }

  void start_emulator() {
    std::string exe = emulator_path_();
    if (exe.empty()) {
      const std::filesystem::path here = fcu::executable_dir();
      const std::filesystem::path beside = here / "tern-fcu-emulator";
      if (!here.empty() && std::filesystem::exists(beside)) {
        exe = beside.string();
      } else if (const char* path = std::getenv("PATH")) {
        std::stringstream ss(path);
        std::string dir;
        while (std::getline(ss, dir, ':'))
          if (std::filesystem::exists(std::filesystem::path(dir) / "tern-fcu-emulator")) {
            exe = (std::filesystem::path(dir) / "tern-fcu-emulator").string();
            break;
          }
      }
      if (exe.empty())
        throw std::runtime_error("parameter '" + qname("emulator") +
                                 "': tern-fcu-emulator not found next to the tern command nor on PATH (set " +
                                 qname("emulator_path") + ")");
    }
    std::vector<std::string> argv{exe, "--exit-with-parent", "--seed", std::to_string(context().seed())};
    const std::filesystem::path ac = context().aircraft_file();
    if (!ac.empty()) {
      argv.push_back("--aircraft");
      argv.push_back(ac.string());
    }
    if (lockstep_()) argv.push_back("--lockstep");
    if (!emulator_params_().empty()) {
      std::filesystem::path p = emulator_params_();
      if (p.is_relative() && !context().config_dir().empty()) p = context().config_dir() / p;
      argv.insert(argv.end(), {"--params", p.string()});
    }
    argv.insert(argv.end(), {"--rc", emulator_rc_()});
    std::stringstream ss(emulator_args_());
    for (std::string a; ss >> a;) argv.push_back(a);
    emulator_proc_ = std::make_unique<fcu::ChildProcess>(argv);
    for (;;) {
      std::string line;
      try {
        line = emulator_proc_->read_line(10'000'000'000);
      } catch (const std::exception& e) {
        emulator_proc_.reset();
        throw std::runtime_error("tern-fcu-emulator (" + exe + ") did not report its port: " + e.what());
      }
      if (line.rfind("pty: ", 0) == 0) {
        emulator_device_ = line.substr(5);
        break;
      }
    }
    log().info("tern-fcu-emulator (pid {}) on {}", emulator_proc_->pid(), emulator_device_);
  }

  void shutdown() {
    if (link_) {
      final_stats_ = link_->stats();
      link_->stop();
      link_.reset();
    }
    if (emulator_proc_) {
      emulator_proc_->stop();
      emulator_proc_.reset();
    }
  }

  void initialise_state() {
    pending_.clear();
    anchored_ = false;
    wall_anchored_ = false;
    link_lost_ = false;
    imu_stalled_ = false;
    owed_command_ = false;
    last_cmd_index_ = -1;
    last_rx_ns_ = fcu::steady_ns();
    last_heartbeat_ = last_timesync_ = 0;
    newest_imu_fcu_.reset();
    last_imu_fcu_.reset();
    last_imu_stamp_ = 0;
    stream_stamp_ = 0;
    status_.reset();
    raw_status_.reset();
    rc_seen_ = rc_warned_ = false;
    first_step_now_.reset();
    timesync_ = fcu::TimeSync();
  }

  // ---------------------------------------------------------------- sending
  template <class T>
  void send(const T& m) {
    if (link_) link_->send(enc_->frame(m));
  }
  void send_heartbeat() {
    mav::Heartbeat h;
    h.type = 18;       // MAV_TYPE_ONBOARD_CONTROLLER
    h.autopilot = 8;   // MAV_AUTOPILOT_INVALID: not an autopilot of its own
    h.mavlink_version = 3;
    send(h);
    last_heartbeat_ = fcu::steady_ns();
  }
  void send_timesync() {
    const std::int64_t t = fcu::steady_ns();
    send(fcu::TimeSync::request(t));
    last_timesync_ = t;
  }
  void send_command() {
    mav::OffboardControl c;
    if (actuators_in_.has_value()) {
      const msg::Actuators& a = actuators_in_.get();
      c = fcu::to_offboard({a.delta_a, a.delta_e, a.delta_r, a.delta_t}, map_);
    } else {
      c.mode = fcu::kModePassThrough;
      c.ignore = 0x3FF;  // nothing to command yet: every channel ignored (the FCU keeps RC)
    }
    send(c);
    ++commands_sent_;
  }

  // ---------------------------------------------------------------- receiving
  void pull() {
    const std::size_t before = pending_.size();
    link_->drain(pending_);
    for (std::size_t i = before; i < pending_.size(); ++i) {
      last_rx_ns_ = std::max(last_rx_ns_, pending_[i].rx_ns);
      if (pending_[i].frame.msgid == mav::SmallImu::kId) {
        imu_stalled_ = false;
        newest_imu_fcu_ = static_cast<std::int64_t>(mav::SmallImu::unpack(pending_[i].frame.payload.data()).time_boot_us) * 1000;
      }
    }
  }
  bool has_imu_pending() const {
    return std::any_of(pending_.begin(), pending_.end(), [](const fcu::Received& r) { return r.frame.msgid == mav::SmallImu::kId; });
  }

  /// Flight time of FCU time t (ns) with clock "fcu".
  Nanos fcu_stamp(std::int64_t t) const { return anchor_now_ + (t - anchor_fcu_); }
  /// Flight time of a steady-clock instant with clock "wall".
  Nanos wall_stamp(std::int64_t steady) const { return wall_anchor_now_ + (steady - wall_anchor_); }
  Nanos stamp_of_fcu_time(std::int64_t t_fcu, std::int64_t rx_ns) const {
    if (clock_() == "fcu") return fcu_stamp(t_fcu);
    return wall_stamp(timesync_.synced() ? timesync_.to_companion(t_fcu) : rx_ns);
  }

  /// Clock "fcu": waits until the IMU sample of time `now` has arrived (or wait_timeout passes).
  void wait_for(Nanos now) {
    std::int64_t deadline = fcu::steady_ns() + tern::from_seconds(wait_timeout_());
    for (;;) {
      if (newest_imu_fcu_) {
        if (!anchored_) return;  // the first sample anchors the clock at `now`
        if (last_imu_fcu_ && *newest_imu_fcu_ < *last_imu_fcu_) return;  // reboot: handled in process()
        if (fcu_stamp(*newest_imu_fcu_) >= now) return;
      }
      std::int64_t left = deadline - fcu::steady_ns();
      if (left <= 0 && lockstep_()) {
        // Lockstep: the FCU waits for one command per IMU sample it delivered. Send the last one
        // again (our command may have been lost); with nothing at all for link_timeout the
        // link is gone: end the flight in one line rather than fly commands on a frozen state.
        if (fcu::steady_ns() - last_rx_ns_ > tern::from_seconds(link_timeout_()))
          throw std::runtime_error(fmt::format("lockstep: nothing from the FCU for {:.2f} s at t={:.3f} s (link_timeout): "
                                               "the emulator stopped, or is not running with --lockstep",
                                               tern::to_seconds(fcu::steady_ns() - last_rx_ns_), tern::to_seconds(now)));
        send_command();
        ++lockstep_resends_;
        deadline = fcu::steady_ns() + tern::from_seconds(wait_timeout_());
        left = deadline - fcu::steady_ns();
      }
      if (left <= 0) {
        // No IMU sample: until one arrives, flight time follows the wall clock (each step
        // waiting wait_timeout would crawl). A silent link is reported by check_link().
        imu_stalled_ = true;
        lost_wall_ = fcu::steady_ns();
        lost_now_ = now;
        if (fcu::steady_ns() - last_rx_ns_ < tern::from_seconds(link_timeout_()))
          log().warn("t={:.3f} s: no IMU sample from the FCU for {:.2f} s while other data arrives; flight time follows the wall clock",
                     tern::to_seconds(now), wait_timeout_());
        return;
      }
      link_->wait(left);
      pull();
    }
  }

  void process(Nanos now) {
    // Latest of each kind due in this step (a port holds one message per step).
    std::optional<msg::Imu> imu;
    std::optional<msg::Mag> mag;
    std::optional<msg::Baro> baro;
    std::optional<msg::DiffPressure> diff;
    std::optional<msg::Gnss> gnss;
    std::optional<msg::Rc> rc;
    bool status_new = false;
    bool imu_published_now = false;
    while (!pending_.empty()) {
      const fcu::Received& r = pending_.front();
      const auto m = mav::decode(r.frame);
      if (!m) {
        pending_.pop_front();
        continue;
      }
      if (const auto* s = std::get_if<mav::SmallImu>(&*m)) {
        const std::int64_t t = static_cast<std::int64_t>(s->time_boot_us) * 1000;
        if (last_imu_fcu_ && t <= *last_imu_fcu_ - 1'000'000) {
          ++reboots_;
          log().warn("FCU rebooted: its clock went back from {:.3f} s to {:.3f} s; time re-anchored", *last_imu_fcu_ * 1e-9, t * 1e-9);
          anchored_ = false;
          timesync_.clear();
          last_imu_fcu_ = t;  // the new epoch: a sample kept for the next step is not a second reboot
        }
        if (last_imu_fcu_ && t - *last_imu_fcu_ > tern::from_seconds(link_timeout_())) {
          ++link_losses_;
          log().warn("t={:.3f} s: no IMU sample for {:.2f} s of FCU time (link silent or frames lost); resumed",
                     tern::to_seconds(now), (t - *last_imu_fcu_) * 1e-9);
        }
        if (!anchored_ && clock_() == "fcu") {
          anchored_ = true;
          anchor_fcu_ = t;
          anchor_now_ = last_imu_fcu_ ? std::max(now, last_imu_stamp_ + 1) : now;
        }
        Nanos stamp = stamp_of_fcu_time(t, r.rx_ns);
        // IMU stamps never go back (clock wall: the TIMESYNC estimate can move by a little)
        if (last_imu_fcu_ && stamp <= last_imu_stamp_) stamp = last_imu_stamp_ + 1;
        if (stamp > now) break;  // a later sample: the next step publishes it
        msg::Imu out;
        out.stamp = stamp;
        out.accel = Eigen::Vector3d(s->xacc, s->yacc, s->zacc);
        out.gyro = Eigen::Vector3d(s->xgyro, s->ygyro, s->zgyro);
        out.temperature = s->temperature < 150.0f ? s->temperature + 273.15 : s->temperature;  // deg C or K
        if (imu) ++imu_superseded_;
        imu = out;
        last_imu_fcu_ = t;
        last_imu_stamp_ = stamp;
        stream_stamp_ = stamp;
        imu_published_now = true;
      } else {
        const Nanos stream = clock_() == "fcu" ? stream_stamp_ : wall_stamp(r.rx_ns);
        if (clock_() == "wall" && stream > now) break;
        handle_other(*m, r, stream, mag, baro, diff, gnss, rc, status_new);
      }
      pending_.pop_front();
    }
    if (imu) imu_out_.publish(*imu);
    if (mag) mag_out_.publish(*mag);
    if (baro) baro_out_.publish(*baro);
    if (diff) diff_out_.publish(*diff);
    if (gnss) gnss_out_.publish(*gnss);
    if (rc) rc_out_.publish(*rc);
    if (status_new && status_) status_out_.publish(*status_);
    if (imu_published_now && lockstep_()) owed_command_ = true;
  }

  void handle_other(const mav::Message& m, const fcu::Received& r, Nanos stream, std::optional<msg::Mag>& mag,
                    std::optional<msg::Baro>& baro, std::optional<msg::DiffPressure>& diff, std::optional<msg::Gnss>& gnss,
                    std::optional<msg::Rc>& rc, bool& status_new) {
    if (const auto* s = std::get_if<mav::SmallMag>(&m)) {
      msg::Mag out;
      out.stamp = stream;
      out.field = Eigen::Vector3d(s->xmag, s->ymag, s->zmag) * mag_scale_();
      mag = out;
    } else if (const auto* s = std::get_if<mav::SmallBaro>(&m)) {
      msg::Baro out;
      out.stamp = stream;
      out.pressure = s->pressure;
      out.temperature = s->temperature;
      baro = out;
    } else if (const auto* s = std::get_if<mav::DiffPressure>(&m)) {
      msg::DiffPressure out;
      out.stamp = stream;
      out.pressure = s->diff_pressure;
      out.temperature = s->temperature;
      diff = out;
    } else if (const auto* s = std::get_if<mav::RosflightGnss>(&m)) {
      msg::Gnss out;
      const std::int64_t t = static_cast<std::int64_t>(s->rosflight_timestamp) * 1000;
      out.stamp = (anchored_ || clock_() == "wall") && t > 0 ? std::min(stamp_of_fcu_time(t, r.rx_ns), stream) : stream;
      out.fix_type = static_cast<msg::FixType>(fcu::fix_type(s->fix_type));
      out.num_sats = s->num_sat;
      out.lat = s->lat;
      out.lon = s->lon;
      out.alt = s->height;
      out.vel = Eigen::Vector3d(s->vel_n, s->vel_e, s->vel_d);
      out.h_acc = s->h_acc;
      out.v_acc = s->v_acc;
      out.s_acc = s->s_acc;
      // rosflight_timestamp is the FCU's time the fix was read from the receiver (firmware
      // src/mavlink_adapter.cpp, MavlinkAdapter::send_gnss, packs GnssStruct::header.timestamp,
      // "time of data read complete" in include/interface/board.h): the best time of validity
      // the link offers; the receiver's own solution-to-output latency is not reported.
      out.time_of_validity = out.stamp;
      gnss = out;
    } else if (const auto* s = std::get_if<mav::RcChannels>(&m)) {
      rc_seen_ = true;
      const fcu::RcSticks k = fcu::from_rc(*s, rc_map_);
      msg::Rc out;
      out.stamp = stream;
      out.roll = k.roll;
      out.pitch = k.pitch;
      out.yaw = k.yaw;
      out.throttle = k.throttle;
      out.aux = k.aux;
      out.rc_override = status_ && status_->rc_override;
      out.failsafe = status_ && status_->failsafe;
      rc = out;
    } else if (const auto* s = std::get_if<mav::RosflightStatus>(&m)) {
      on_status(*s, stream);
      status_new = true;
    } else if (const auto* s = std::get_if<mav::Timesync>(&m)) {
      timesync_.on_answer(*s, r.rx_ns);
    } else if (const auto* s = std::get_if<mav::Statustext>(&m)) {
      const std::string text = mav::to_string(s->text);
      if (s->severity <= 3) log().error("FCU: {}", text);
      else if (s->severity <= 4) log().warn("FCU: {}", text);
      else log().info("FCU: {}", text);
    } else if (const auto* s = std::get_if<mav::RosflightVersion>(&m)) {
      version_ = mav::to_string(s->version);
      log().info("FCU firmware {}", version_);
    } else if (const auto* s = std::get_if<mav::RosflightCmdAck>(&m)) {
      if (!s->success) log().warn("FCU refused command {}", static_cast<int>(s->command));
    } else if (const auto* s = std::get_if<mav::RosflightOutputRaw>(&m)) {
      output_raw_ = *s;  // stamp: the FCU's clock_millis (CommManager::send_output_raw)
    } else if (const auto* s = std::get_if<mav::AttitudeQuaternion>(&m)) {
      attitude_ = *s;
    }
  }

  /// ROSFLIGHT_STATUS: published; every change of arming, errors, failsafe or override is one
  /// log line saying what it means and what is missing.
  void on_status(const mav::RosflightStatus& s, Nanos stream) {
    msg::FcuStatus st = status_.value_or(msg::FcuStatus{});
    const std::optional<mav::RosflightStatus> was = raw_status_;
    st.stamp = stream;
    st.armed = s.armed != 0;
    st.failsafe = s.failsafe != 0;
    st.rc_override = (s.rc_override & fcu::kPilotOverride) != 0;  // the pilot flies (not: tern's command missing)
    st.offboard = s.offboard != 0;
    st.error_code = s.error_code;
    const double t = tern::to_seconds(stream);
    if (!was || was->armed != s.armed || was->error_code != s.error_code) {
      const std::string why = fcu::arming_problems(st.armed, s.error_code);
      if (why.empty()) log().info("t={:.3f} s: FCU armed, no errors", t);
      else log().warn("t={:.3f} s: {}", t, why);
    }
    if (!was || was->failsafe != s.failsafe) {
      if (st.failsafe) log().warn("t={:.3f} s: FCU failsafe ON (RC lost: throttle 0, surfaces neutral)", t);
      else if (was) log().warn("t={:.3f} s: FCU failsafe off", t);
    }
    if (!was || was->rc_override != s.rc_override) {
      const std::string why = fcu::describe_override(s.rc_override);
      if (why.empty()) {
        if (was) log().info("t={:.3f} s: RC override off: tern flies", t);
      } else {
        log().warn("t={:.3f} s: RC override 0x{:03x}: {}", t, s.rc_override, why);
      }
    }
    raw_status_ = s;
    status_ = st;
  }

  void check_link(std::int64_t wall) {
    const std::int64_t timeout = tern::from_seconds(link_timeout_());
    if (!link_lost_ && wall - last_rx_ns_ > timeout) {
      link_lost_ = true;
      lost_at_ = last_rx_ns_;
      lost_wall_ = wall;
      lost_now_ = last_step_now_;
      ++link_losses_;
      log().warn("link to the FCU lost: nothing received for {:.2f} s ({}); the FCU flies its failsafe/RC",
                 tern::to_seconds(wall - last_rx_ns_), link_->options().describe());
    } else if (link_lost_ && wall - last_rx_ns_ <= timeout) {
      link_lost_ = false;
      anchored_ = false;  // FCU time restarts from the current flight time
      log().warn("link to the FCU restored after {:.2f} s", tern::to_seconds(last_rx_ns_ - lost_at_));
    }
  }

  void log_link_summary() {
    const fcu::LinkStats s = link_->stats();
    log().info("link: {} frames, {} bad CRC, {} unknown id, {} bad length, {} bytes skipped, {} queue drops, "
               "{} commands sent, {} link losses, {} reboots, TIMESYNC offset {:.3f} s rtt {:.3f} ms ({} answers, {} too slow)",
               s.parser.frames, s.parser.bad_crc, s.parser.unknown_id, s.parser.bad_length, s.parser.skipped,
               s.queue_dropped, commands_sent_, link_losses_, reboots_, timesync_.offset() * 1e-9,
               timesync_.last_rtt() * 1e-6, timesync_.samples(), timesync_.rejected());
  }

  tern::Input<msg::Actuators> actuators_in_;
  tern::Output<msg::Imu> imu_out_;
  tern::Output<msg::Gnss> gnss_out_;
  tern::Output<msg::Baro> baro_out_;
  tern::Output<msg::DiffPressure> diff_out_;
  tern::Output<msg::Mag> mag_out_;
  tern::Output<msg::Rc> rc_out_;
  tern::Output<msg::FcuStatus> status_out_;

  tern::Param<std::string> transport_, device_, udp_host_, clock_, emulator_args_, emulator_path_, channels_, emulator_params_,
      emulator_rc_;
  tern::Param<std::int64_t> baud_, udp_bind_port_, udp_remote_port_, system_id_, component_id_;
  tern::Param<bool> lockstep_, emulator_;
  tern::Param<double> connect_timeout_, wait_timeout_, link_timeout_, command_rate_, heartbeat_rate_, timesync_rate_, mag_scale_;
  tern::Param<std::vector<double>> max_deflection_, signs_, rc_channels_, rc_aux_channels_, rc_signs_;

  fcu::ActuatorMap map_;
  fcu::RcMap rc_map_;
  std::unique_ptr<fcu::ChildProcess> emulator_proc_;
  std::string emulator_device_;
  std::unique_ptr<fcu::Link> link_;
  std::unique_ptr<mav::Encoder> enc_;
  std::deque<fcu::Received> pending_;
  fcu::TimeSync timesync_;
  fcu::LinkStats final_stats_;

  bool anchored_ = false, wall_anchored_ = false, link_lost_ = false, imu_stalled_ = false, owed_command_ = false;
  std::int64_t anchor_fcu_ = 0, wall_anchor_ = 0;
  Nanos anchor_now_ = 0, wall_anchor_now_ = 0, last_imu_stamp_ = 0, stream_stamp_ = 0, lost_now_ = 0;
  std::optional<std::int64_t> newest_imu_fcu_, last_imu_fcu_;
  std::int64_t last_cmd_index_ = -1, last_rx_ns_ = 0, lost_at_ = 0, lost_wall_ = 0, last_step_now_ = 0, last_heartbeat_ = 0, last_timesync_ = 0;
  std::uint64_t link_losses_ = 0, reboots_ = 0, commands_sent_ = 0, imu_superseded_ = 0, lockstep_resends_ = 0;
  bool rc_seen_ = false, rc_warned_ = false;
  std::optional<Nanos> first_step_now_;
  std::optional<msg::FcuStatus> status_;
  std::optional<mav::RosflightStatus> raw_status_;
  std::optional<mav::RosflightOutputRaw> output_raw_;
  std::optional<mav::AttitudeQuaternion> attitude_;
  std::string version_;
};

}  // namespace tern::fcu_serial
