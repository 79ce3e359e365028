// sil/sil.cpp: see sil.hpp. The world side of each loop is in sil_world.cpp, the parameter
// upload in sil_params.cpp.
#include "sil.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <unistd.h>

#include "tern/math.hpp"
#include "../emulator/uart.hpp"
#include "../emulator/util.hpp"
#include "../emulator/world.hpp"
#include "mavlink_adapter.hpp"
#include "rosflight.h"
#include "tern_fcu_serial/messages.hpp"
#include "tern_sim_aero/profiles.hpp"

namespace tern::fcu::sil {

namespace {
/// A fresh flash file for one run: in TMPDIR, named after the process.
std::string temporary_flash() {
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  return (dir / ("tern-fcu-sil-" + std::to_string(getpid()) + ".flash")).string();
}

/// The raw sensors of a profile: no calibration at boot or stored in the world (the firmware's
/// calibrations take their place). The accelerometer keeps its turn-on offset: `realistic`
/// models what is left after a calibration stored in an earlier session (0.05 m/s^2);
/// uncalibrated, the ICM-20602's zero-g offset is +-25 mg (DS-000176), 0.245 m/s^2. A profile
/// whose calibration is taken at power-up (`rosflight`) already draws the raw turn-on offset: the
/// firmware refuses to arm until it is calibrated (ERROR_UNCALIBRATED_IMU, set in Sensors::init_imu
/// and checked in StateManager, source/src/sensors.cpp and state_manager.cpp), and its
/// Sensors::calibrate_accel stores the mean of 1000 samples plus gravity as ACC_X/Y/Z_BIAS; here
/// the SIL's firmware itself runs that calibration on the raw sensors.
sim::SensorParams raw_sensors(const std::string& profile) {
  sim::SensorParams p = sim::sensor_profile(profile);
  if (p.accel_calibrated_level && !p.accel_calibrated_at_power_up)
    p.accel_bias_range = std::max(p.accel_bias_range, 0.025 * tern::kStandardGravity);
  p.calibrate_at_boot = false;
  p.accel_calibrated_level = p.accel_calibrated_at_power_up = false;
  p.accel_calibration_tilt_range = 0.0;
  return p;
}
/// --outputs: the firmware outputs of aileron, elevator, rudder and motor.
std::array<int, 4> parse_outputs(const std::string& text) {
  const auto out = emulator::numbers(text, 4, "--outputs");
  std::array<int, 4> idx{};
  for (std::size_t i = 0; i < 4; ++i) {
    if (out[i] < 0 || out[i] >= static_cast<double>(SilBoard::kOutputs) || out[i] != std::floor(out[i]))
      throw std::runtime_error("--outputs: '" + text + "': each output is an integer 0.." + std::to_string(SilBoard::kOutputs - 1));
    idx[i] = static_cast<int>(out[i]);
  }
  return idx;
}
}  // namespace

const char* firmware_version() { return GIT_VERSION_STRING; }

Sil::Sil(const SilOptions& o, emulator::Port& port)
    : o_(o),
      port_(port),
      ac_(tern::load_aircraft(o.world.aircraft)),
      sim_(ac_, o.world.seed),
      sensors_(raw_sensors(o.sensor_profile), o.world.seed ^ 0x9E3779B97F4A7C15ull),
      rc_script_(o.world.rc),
      board_(o.flash.empty() ? temporary_flash() : o.flash) {
  temporary_flash_ = o.flash.empty();
  if (temporary_flash_) std::filesystem::remove(board_.flash_file());
  outputs_ = parse_outputs(o.outputs);
  throw_ = emulator::servo_throw(ac_, o.world.max_deflection);
  sim_.set_actuators(sim::actuator_profile(o.sensor_profile));
  emulator::place_aircraft(sim_, ac_, o.world);
  silence_ = emulator::time_window(o.world.silence, "--silence");
  deaf_ = emulator::time_window(o.companion_silence, "--companion-silence");
  imu_ = emulator::every(400);
  mag_ = emulator::every(50);
  baro_ = emulator::every(100);
  diff_ = emulator::every(100);
  gnss_ = emulator::every(10);
  rc_ = emulator::every(50);
  dt_ = imu_.period;
  gnss_latency_ = emulator::ns(sensors_.params().gnss_latency);
  board_.set_time_us(static_cast<std::uint64_t>(board_us(0)));
  if (!o.world.truth.empty()) truth_log_.emplace(o.world.truth);
  upload_params();
  if (o.bench_calibration) bench_calibration();
  boot();
}

Sil::~Sil() {
  fw_.reset();
  adapter_.reset();
  if (temporary_flash_) std::filesystem::remove(board_.flash_file());
}

/// The firmware as src/main.cpp starts it: the adapter on the board, ROSflight, init().
void Sil::boot() {
  fw_.reset();
  adapter_ = std::make_unique<rosflight_firmware::MavlinkAdapter>(board_);
  fw_ = std::make_unique<rosflight_firmware::ROSflight>(board_, *adapter_);
  fw_->init();
}

/// Frames go out at the end of each loop; a silent link loses them.
bool Sil::flush() {
  std::vector<std::uint8_t> sent = board_.take_sent();
  out_.insert(out_.end(), sent.begin(), sent.end());
  if (out_.empty()) return true;
  const bool silent = silence_ && t_ >= silence_->first && t_ < silence_->second;
  const bool ok = !silent && port_.write(out_.data(), out_.size());
  if (!ok) ++dropped_;
  out_.clear();
  return ok;
}

/// Moves what the companion sent (waiting at most timeout_ns) to the firmware's serial port,
/// counting its OFFBOARD_CONTROL frames on the way (the board's UART does not parse). True when
/// bytes came.
bool Sil::service(std::int64_t timeout_ns) {
  pollfd p{port_.fd(), POLLIN, 0};
  const std::int64_t wait = std::max<std::int64_t>(0, timeout_ns);
  const timespec ts{static_cast<time_t>(wait / 1'000'000'000), static_cast<long>(wait % 1'000'000'000)};
  if (ppoll(&p, 1, &ts, nullptr) <= 0) return false;
  std::uint8_t buf[4096];
  const bool deaf = deaf_ && t_ >= deaf_->first && t_ < deaf_->second;
  bool got = false;
  for (std::size_t n; (n = port_.read(buf, sizeof buf)) > 0;) {
    got = true;
    if (!deaf) board_.receive_bytes(buf, n);
    monitor_.feed(buf, n, [&](const mavlink::Frame& f) {
      if (f.msgid == mavlink::OffboardControl::kId) ++commands_;
    });
  }
  return got && !deaf;
}

void Sil::run_firmware() {
  fw_->run();
  if (board_.reboot_requested()) {
    board_.clear_reboot();
    ++reboots_;
    std::cerr << "tern-fcu-sil: reboot at t = " << static_cast<double>(t_) * 1e-9 << " s\n";
    flush();
    boot();
  }
}

/// --lockstep: one OFFBOARD_CONTROL per IMU sample that reached the companion.
void Sil::wait_for_command(std::uint64_t& used) {
  static bool warned = false;
  const std::int64_t deadline = emulator::mono_ns() + emulator::ns(o_.world.stall_timeout);
  while (!emulator::g_emulator_stop && commands_ <= used) {
    const std::int64_t left = deadline - emulator::mono_ns();
    if (used > 0 && left <= 0) {
      if (!warned) std::cerr << "tern-fcu-sil: no command for " << o_.world.stall_timeout << " s; running on\n";
      warned = true;
      break;
    }
    service(used > 0 ? std::min<std::int64_t>(left, 100'000'000) : 100'000'000);
  }
  used = commands_;
}

/// Free-running: waits for the next IMU period at --speed times real time. The board's main loop
/// spins meanwhile (ROSflight::run() over and over: src/main.cpp, `while (true) { firmware.run(); }`),
/// so what the companion sends is received, handled and answered (TIMESYNC: ROSflight::run ->
/// MavlinkAdapter::receive -> handle_msg_timesync, src/mavlink_adapter.cpp ->
/// CommManager::timesync_callback, src/comm_manager.cpp, which replies at once) when it arrives,
/// with the board clock at that moment, not at the next IMU sample.
void Sil::wait_free_running(std::int64_t wall0) {
  const double speed = o_.world.speed;
  const std::int64_t target = wall0 + static_cast<std::int64_t>(static_cast<double>(t_ + dt_) / speed);
  for (std::int64_t left; !emulator::g_emulator_stop && (left = target - emulator::mono_ns()) > 0;) {
    if (!service(left)) continue;
    const auto now = static_cast<std::int64_t>(static_cast<double>(emulator::mono_ns() - wall0) * speed);
    board_.set_time_us(static_cast<std::uint64_t>(board_us(std::clamp(now, t_, t_ + dt_ - 1000))));
    run_firmware();
    flush();
  }
  service(0);  // the board clock stays where the last run left it (never back)
}

int Sil::run() {
  const std::int64_t wall0 = emulator::mono_ns();
  const std::int64_t end = o_.world.duration > 0 ? emulator::ns(o_.world.duration) : INT64_MAX;
  std::uint64_t used = 0;
  while (!emulator::g_emulator_stop && t_ <= end) {
    board_.set_time_us(static_cast<std::uint64_t>(board_us(t_)));
    put_sensors(t_);
    if (truth_log_) truth_log_->write(t_, sim_, truth().fm.air.Va);
    run_firmware();
    const bool delivered = flush() && imu_sent_;
    if (o_.world.lockstep && delivered) {
      wait_for_command(used);  // it read everything up to the command
    } else if (!o_.world.lockstep) {
      wait_free_running(wall0);
    } else {
      service(0);
    }
    run_firmware();
    flush();
    apply_outputs(t_);
    sim_.step(static_cast<double>(dt_) * 1e-9);
    t_ += dt_;
  }
  std::cerr << "tern-fcu-sil: stopped at t = " << static_cast<double>(t_) * 1e-9 << " s after " << commands_ << " commands (" << dropped_
            << " writes lost, " << reboots_ << " reboots)\n";
  if (const auto* uart = dynamic_cast<const emulator::UartPort*>(&port_)) {
    const emulator::UartPort::Stats u = uart->stats();
    const double wall = static_cast<double>(emulator::mono_ns() - wall0) * 1e-9;
    std::cerr << "tern-fcu-sil: UART " << u.sent << " bytes sent (" << 100.0 * static_cast<double>(u.sent * uart->byte_ns()) * 1e-9 / wall
              << " % of the line over " << wall << " s), " << u.received << " received, " << u.dropped_writes
              << " writes dropped (transmit buffer full), longest wait in the transmit buffer "
              << static_cast<double>(u.max_tx_queue_ns) * 1e-6 << " ms\n";
  }
  return 0;
}

}  // namespace tern::fcu::sil
