// sil/sil_world.cpp: the world's side of each SIL loop (sil.hpp, steps 1 and 5): sim_aero's
// raw sensors into the board's structs (include/interface/board.h), and the firmware's PWM
// outputs back to the aircraft's servos and motor.
#include <cmath>

#include "../emulator/util.hpp"
#include "tern/aero/model.hpp"
#include "sil.hpp"

namespace tern::fcu::sil {

namespace {
using Poll = sim::SensorSchedule::Poll;
using rosflight_firmware::GnssStruct;
using rosflight_firmware::PressureStruct;

void copy3(float (&out)[3], const Eigen::Vector3d& v) {
  for (int i = 0; i < 3; ++i) out[i] = static_cast<float>(v[i]);
}
}  // namespace

const sim::Truth& Sil::truth() {
  if (!truth_) {
    truth_.emplace();
    truth_->x = sim_.state();
    if (sensors_.params().imu_position.isZero())
      truth_->fm = sim_.evaluate();
    else  // the lever arm needs the angular acceleration: one evaluation gives both
      truth_->omega_dot = sim::derivative(ac_, truth_->x, sim_.surfaces(), sim_.wind(), &truth_->fm).segment<3>(sim::P);
    truth_->mass = ac_.mass;
    truth_->rho = ac_.rho;
    truth_->throttle = sim_.surfaces().delta_t;
  }
  return *truth_;
}

void Sil::put_sensors(std::int64_t t) {
  truth_.reset();
  const auto stamp = static_cast<std::uint64_t>(board_us(t));
  put_imu(t);
  if (mag_.poll(t) == Poll::sample) {
    const auto m = sensors_.mag(truth(), mag_.dt_since_last(t));
    mag_.last_sample = t;
    rosflight_firmware::MagStruct s{};
    s.header.timestamp = stamp;
    copy3(s.flux, m.field);  // T
    s.temperature = 288.15f;
    board_.put_mag(s);
  }
  if (baro_.poll(t) == Poll::sample) {
    const auto m = sensors_.baro(truth(), baro_.dt_since_last(t));
    baro_.last_sample = t;
    PressureStruct s{};
    s.header.timestamp = stamp;
    s.pressure = static_cast<float>(m.pressure);
    s.temperature = static_cast<float>(m.temperature);
    board_.put_baro(s);
  }
  if (diff_.poll(t) == Poll::sample) {
    sim::Truth seen = truth();
    if (t < emulator::ns(o_.world.pitot_cover)) {  // covered: still air at the probe
      seen.fm.air.v_air.setZero();
      seen.fm.air.Va = 0.0;
    }
    const auto m = sensors_.diff_pressure(seen, diff_.dt_since_last(t));
    diff_.last_sample = t;
    PressureStruct s{};
    s.header.timestamp = stamp;
    s.pressure = static_cast<float>(m.pressure);
    s.temperature = static_cast<float>(m.temperature);
    board_.put_diff_pressure(s);
  }
  put_gnss(t);
  put_rc(t);
}

void Sil::put_imu(std::int64_t t) {
  imu_sent_ = false;
  if (imu_.poll(t) != Poll::sample) return;
  const auto m = sensors_.imu(truth(), imu_.dt_since_last(t));
  imu_.last_sample = t;
  rosflight_firmware::ImuStruct s{};
  s.header.timestamp = static_cast<std::uint64_t>(board_us(t));
  copy3(s.accel, m.accel);  // m/s^2, specific force, FRD
  copy3(s.gyro, m.gyro);    // rad/s
  s.temperature = static_cast<float>(m.temperature);
  board_.put_imu(s);
  imu_sent_ = true;
}

/// A fix valid at t reaches the board gnss_latency later; its header stamp is then ("time of
/// data read complete", board.h), pps the board time of the top of its UTC second.
void Sil::put_gnss(std::int64_t t) {
  if (gnss_.poll(t) == Poll::sample) {
    const auto m = sensors_.gnss(truth(), gnss_.dt_since_last(t));
    gnss_.last_sample = t;
    GnssStruct s{};
    const std::int64_t unix_ns = emulator::kUnixEpoch + t;
    s.unix_seconds = unix_ns / 1'000'000'000;
    s.unix_nanos = static_cast<std::int32_t>(unix_ns % 1'000'000'000);
    s.pps = static_cast<std::uint64_t>(board_us(t) - s.unix_nanos / 1000);  // the top of the fix's UTC second
    s.fix_type = static_cast<std::uint8_t>(m.fix ? rosflight_firmware::GNSSFixType::GNSS_FIX_TYPE_3D_FIX
                                                 : rosflight_firmware::GNSSFixType::GNSS_FIX_TYPE_NO_FIX);
    s.num_sat = static_cast<std::uint8_t>(m.num_sats);
    s.lat = m.lat;
    s.lon = m.lon;
    s.height_msl = static_cast<float>(m.alt);
    s.vel_n = static_cast<float>(m.vel_ned.x());
    s.vel_e = static_cast<float>(m.vel_ned.y());
    s.vel_d = static_cast<float>(m.vel_ned.z());
    s.h_acc = static_cast<float>(m.h_acc);
    s.v_acc = static_cast<float>(m.v_acc);
    s.speed_accy = static_cast<float>(m.s_acc);
    gnss_pending_.emplace_back(t + gnss_latency_, s);
  }
  if (!gnss_pending_.empty() && gnss_pending_.front().first <= t) {
    GnssStruct s = gnss_pending_.front().second;
    s.header.timestamp = static_cast<std::uint64_t>(board_us(t));
    board_.put_gnss(s);
    gnss_pending_.pop_front();
  }
}

/// The receiver's frame every 20 ms (the script's transmitter; `lost`: the SBUS failsafe flag).
void Sil::put_rc(std::int64_t t) {
  if (!rc_script_.receiver() || rc_.poll(t) != Poll::sample) return;
  rc_.last_sample = t;
  const firmware::RcFrame f = emulator::RcScript::frame(rc_script_.at(t));
  rosflight_firmware::RcStruct s{};
  s.header.timestamp = static_cast<std::uint64_t>(board_us(t));
  s.nChan = static_cast<std::uint8_t>(f.chan.size());
  for (std::size_t i = 0; i < f.chan.size(); ++i) s.chan[i] = f.chan[i];
  s.frameLost = false;
  s.failsafeActivated = f.lost;
  board_.put_rc(s);
}

/// Each output holds its value between PWM pulses (its pwm_init rate); servos: PWM fraction
/// 0..1 = -throw..+throw in the uavbook's signs; the motor: throttle 0..1. Outputs never
/// initialised or disabled stay at 0: servos at an end stop, motor off, as on the board.
void Sil::apply_outputs(std::int64_t t) {
  const auto& pwm = board_.pwm();
  const auto& rate = board_.pwm_rate();
  for (std::size_t k = 0; k < 4; ++k) {
    const auto o = static_cast<std::size_t>(outputs_[k]);
    if (t < next_pulse_[k]) continue;
    held_[k] = board_.pwm_enabled() ? pwm[o] : 0.0f;
    next_pulse_[k] = rate[o] > 0 ? next_pulse_[k] + emulator::ns(1.0 / rate[o]) : t + dt_;
    if (next_pulse_[k] <= t) next_pulse_[k] = t + dt_;
  }
  auto servo = [&](std::size_t k) { return (2.0 * held_[k] - 1.0) * throw_[k]; };
  sim_.set_command({servo(1), servo(0), servo(2), std::clamp(static_cast<double>(held_[3]), 0.0, 1.0)});
}

}  // namespace tern::fcu::sil
