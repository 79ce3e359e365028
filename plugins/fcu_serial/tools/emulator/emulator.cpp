// emulator/emulator.cpp: see emulator.hpp.
#include "emulator.hpp"

#include <chrono>
#include <cmath>
#include <iostream>
#include <sstream>
#include <utility>

#include <yaml-cpp/yaml.h>

#include "tern/aero/model.hpp"
#include "tern_sim_aero/wind.hpp"
#include "util.hpp"
#include "world.hpp"

namespace tern::fcu::emulator {

namespace {
// ROSFLIGHT_VERSION's text (at most 50 characters: rosflight.xml): this program and the
// firmware commit it plays
constexpr const char* kVersion = "tern-fcu-emulator 0.2 (rosflight_firmware e8cf6a0)";

}  // namespace

firmware::Params load_params(const std::string& file) {
  firmware::Params p;
  if (file.empty()) return p;
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(file);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("--params " + file + ": " + e.what());
  }
  if (!doc.IsMap()) throw std::runtime_error("--params " + file + ": expected a map NAME: value");
  for (const auto& kv : doc) {
    const std::string name = kv.first.as<std::string>();
    const auto i = p.find(name);
    if (!i) throw std::runtime_error("--params " + file + ": " + name + " is not a parameter the emulator knows");
    const bool is_int = p.at(*i).type == firmware::ParamType::int32;
    const auto bad = [&](const std::string& value) {
      return std::runtime_error("--params " + file + ": " + name + ": " + value + " is not " + (is_int ? "an int32" : "a finite number"));
    };
    if (!kv.second.IsScalar()) throw bad(kv.second.IsNull() ? "an empty value" : "a list or map");
    try {
      if (is_int)
        p.set_int(*i, kv.second.as<std::int32_t>());
      else if (const float v = kv.second.as<float>(); std::isfinite(v))
        p.set_float(*i, v);
      else
        throw bad("'" + kv.second.Scalar() + "'");
    } catch (const YAML::Exception&) {
      throw bad("'" + kv.second.Scalar() + "'");
    }
  }
  p.take_changes();
  return p;
}

Emulator::Emulator(const Options& o, Port& port)
    : o_(o),
      port_(port),
      ac_(tern::load_aircraft(o.aircraft)),
      sim_(ac_, o.seed),
      sensors_(sim::SensorParams{}, o.seed ^ 0x9E3779B97F4A7C15ull),
      boot_params_(load_params(o.params)),
      rc_script_(o.rc),
      rng_(o.seed ^ 0xC0FFEEull) {
  // no --params: a board with an empty flash (the firmware takes its defaults and says so)
  fcu_.emplace(o.params.empty() ? std::nullopt : std::optional<firmware::Params>(boot_params_), kVersion);
  throw_ = servo_throw(ac_, o.max_deflection);
  place_aircraft(sim_, ac_, o);
  silence_ = time_window(o.silence, "--silence");
  imu_ = every(400);
  mag_ = every(50);
  baro_ = every(100);
  diff_ = every(100);
  gnss_ = every(10);
  rc_ = every(50);
  status_ = every(10);
  heartbeat_ = every(1);
  dt_ = imu_.period;
  if (!o.truth.empty()) truth_log_.emplace(o.truth);
}

/// Frames are written at the end of each loop; a silent link or a full port loses them.
bool Emulator::flush() {
  corrupt_frames();
  bool ok = true;
  if (!out_.empty() && !silent(t_))
    ok = port_.write(out_.data(), out_.size());
  else if (!out_.empty())
    ok = false;
  if (!ok && !out_.empty()) ++dropped_;
  out_.clear();
  return ok;
}

void Emulator::corrupt_frames() {
  const std::optional<std::size_t> imu = std::exchange(imu_at_, std::nullopt);
  if (o_.corrupt <= 0) return;
  // out_ holds whole MAVLink 1 frames: header, payload of length out_[at + 1], checksum
  for (std::size_t at = 0, n; at < out_.size(); at += n) {
    n = mavlink::kHeaderLength + out_[at + 1] + 2;
    if (std::uniform_real_distribution<double>(0, 1)(rng_) >= o_.corrupt) continue;
    const std::size_t i = at + std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_);
    out_[i] ^= static_cast<std::uint8_t>(1 + std::uniform_int_distribution<int>(0, 254)(rng_));
    if (imu && *imu == at) imu_delivered_ = false;
  }
}

/// Reads what the companion sent (waiting at most timeout_ns) and answers it.
void Emulator::service(std::int64_t timeout_ns) {
  pollfd p{port_.fd(), POLLIN, 0};
  const int r = poll(&p, 1, static_cast<int>(std::max<std::int64_t>(0, timeout_ns) / 1'000'000));
  if (r <= 0) return;
  std::uint8_t buf[4096];
  for (std::size_t n; (n = port_.read(buf, sizeof buf)) > 0;)
    parser_.feed(buf, n, [&](const mavlink::Frame& f) { fcu_->handle(f, fcu_time(), out_); });
  flush();
}

/// A reboot (--reboot-at or ROSFLIGHT_CMD_REBOOT): the firmware boots again from its stored
/// parameters (disarmed, its calibrations redone) and its clock restarts.
void Emulator::reboot() {
  firmware::Params stored = fcu_->stored();
  fcu_.emplace(stored, kVersion);
  boot_ = t_;
  std::cerr << "tern-fcu-emulator: reboot at t = " << static_cast<double>(t_) * 1e-9 << " s\n";
}

const sim::Truth& Emulator::truth() {
  if (!truth_) {
    truth_.emplace();
    truth_->x = sim_.state();
    truth_->fm = sim_.evaluate();
    truth_->mass = ac_.mass;
    truth_->rho = ac_.rho;
    truth_->throttle = sim_.surfaces().delta_t;
  }
  return *truth_;
}

int Emulator::run() {
  const std::int64_t wall0 = mono_ns();
  const std::int64_t end = o_.duration > 0 ? ns(o_.duration) : INT64_MAX;
  std::uint64_t used = 0;
  bool warned_stall = false;
  while (!g_emulator_stop && t_ <= end) {
    if ((o_.reboot_at >= 0 && !rebooted_ && t_ >= ns(o_.reboot_at)) || fcu_->reboot_requested()) {
      rebooted_ = rebooted_ || t_ >= ns(o_.reboot_at);
      reboot();
    }
    const std::int64_t loop_start = mono_ns();
    step_sensors(t_);
    if (truth_log_) truth_log_->write(t_, sim_, truth().fm.air.Va);
    fcu_->set_loop_time_us(static_cast<std::uint16_t>(std::min<std::int64_t>((mono_ns() - loop_start) / 1000, 65535)));
    const bool delivered = flush() && imu_delivered_;
    if (o_.lockstep && delivered) {
      // one command per IMU sample that reached the companion (a lost or corrupted sample is
      // never answered: waiting for it would stall the link)
      const std::int64_t stall_deadline = mono_ns() + ns(o_.stall_timeout);
      while (!g_emulator_stop && fcu_->commands() <= used) {
        const std::int64_t left = stall_deadline - mono_ns();
        if (used > 0 && left <= 0) {
          if (!warned_stall) std::cerr << "tern-fcu-emulator: no command for " << o_.stall_timeout << " s; running on\n";
          warned_stall = true;
          break;
        }
        service(used > 0 ? std::min<std::int64_t>(left, 100'000'000) : 100'000'000);
      }
      used = fcu_->commands();
    } else if (!o_.lockstep) {
      const std::int64_t target = wall0 + static_cast<std::int64_t>(static_cast<double>(t_ + dt_) / o_.speed);
      for (std::int64_t left; !g_emulator_stop && (left = target - mono_ns()) > 0;) service(left);
      service(0);
    } else {
      service(0);
    }
    apply_outputs();
    sim_.step(static_cast<double>(dt_) * 1e-9);
    t_ += dt_;
  }
  std::cerr << "tern-fcu-emulator: stopped at t = " << static_cast<double>(t_) * 1e-9 << " s after " << fcu_->commands() << " commands ("
            << dropped_ << " writes lost)\n";
  return 0;
}

/// The aircraft's servos and motor follow the mixer's raw outputs (Mixer::raw_outputs).
void Emulator::apply_outputs() {
  const auto& raw = fcu_->fw().raw_outputs();
  auto servo = [&](int o, double max) { return (2.0 * raw[static_cast<std::size_t>(o)] - 1.0) * max; };
  // With an invalid mixer the outputs stay 0 (Mixer::mix_output returns early) and the board
  // still writes them (ROSflight::run, pwm_write): 1000 us, servos at an end stop.
  sim::Deltas d;
  d.delta_a = servo(0, throw_[0]);
  d.delta_e = servo(1, throw_[1]);
  d.delta_r = servo(2, throw_[2]);
  d.delta_t = raw[4];
  sim_.set_command({d.delta_e, d.delta_a, d.delta_r, d.delta_t});
}

}  // namespace tern::fcu::emulator
