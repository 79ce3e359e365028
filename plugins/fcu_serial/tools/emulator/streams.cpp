// emulator/streams.cpp: what the emulated FCU sends in one loop (see emulator.hpp), with the
// firmware file each message follows.
#include <cmath>

#include "emulator.hpp"
#include "util.hpp"
#include "tern/atmosphere.hpp"

namespace tern::fcu::emulator {

namespace {
using Poll = sim::SensorSchedule::Poll;
}  // namespace

void Emulator::step_sensors(std::int64_t t) {
  truth_.reset();
  imu_delivered_ = false;
  const std::int64_t ft = fcu_time();
  if (imu_.poll(t) == Poll::sample) step_imu(truth(), t);
  if (mag_.poll(t) == Poll::sample) {
    const auto m = sensors_.mag(truth(), mag_.dt_since_last(t));
    mag_.last_sample = t;
    mavlink::SmallMag s;  // CommManager::send_mag
    s.xmag = static_cast<float>(m.field.x());
    s.ymag = static_cast<float>(m.field.y());
    s.zmag = static_cast<float>(m.field.z());
    send(s);
  }
  if (baro_.poll(t) == Poll::sample) {
    const auto m = sensors_.baro(truth(), baro_.dt_since_last(t));
    baro_.last_sample = t;
    fcu_->fw().baro(static_cast<float>(m.pressure), ft);
    mavlink::SmallBaro s;  // CommManager::send_baro: the raw pressure, its altitude (correct_baro: turbomath::alt)
    s.pressure = static_cast<float>(m.pressure);
    s.temperature = static_cast<float>(m.temperature);
    s.altitude = firmware::pressure_altitude(s.pressure);
    send(s);
  }
  if (diff_.poll(t) == Poll::sample) {
    auto m = sensors_.diff_pressure(truth(), diff_.dt_since_last(t));
    diff_.last_sample = t;
    if (t < static_cast<std::int64_t>(o_.pitot_cover * 1e9)) {  // covered: the sensor's offset and noise only
      const double u = truth().fm.air.v_air.x();
      m.pressure -= 0.5 * truth().rho * u * u;
    }
    const float p = fcu_->fw().diff_pressure(static_cast<float>(m.pressure), ft);
    mavlink::DiffPressure s;  // CommManager::send_diff_pressure after correct_diff_pressure
    s.diff_pressure = p;
    s.temperature = static_cast<float>(m.temperature);
    s.velocity = static_cast<float>(tern::rosflight::indicated_airspeed(p));
    send(s);
  }
  if (gnss_.poll(t) == Poll::sample) {
    const auto m = sensors_.gnss(truth(), gnss_.dt_since_last(t));
    gnss_.last_sample = t;
    mavlink::RosflightGnss s;  // MavlinkAdapter::send_gnss
    const std::int64_t unix_ns = kUnixEpoch + t;
    s.seconds = unix_ns / 1'000'000'000;
    s.nanos = static_cast<std::int32_t>(unix_ns % 1'000'000'000);
    s.fix_type = m.fix ? 3 : 0;
    s.num_sat = static_cast<std::uint8_t>(m.num_sats);
    s.lat = m.lat;
    s.lon = m.lon;
    s.height = static_cast<float>(m.alt);
    s.vel_n = static_cast<float>(m.vel_ned.x());
    s.vel_e = static_cast<float>(m.vel_ned.y());
    s.vel_d = static_cast<float>(m.vel_ned.z());
    s.h_acc = static_cast<float>(m.h_acc);
    s.v_acc = static_cast<float>(m.v_acc);
    s.s_acc = static_cast<float>(m.s_acc);
    s.rosflight_timestamp = static_cast<std::uint64_t>(ft / 1000);
    send(s);
  }
  step_rc(t);
  step_streams(t);
}

/// Sensors::run (calibration, bias correction), then the loop body (command_manager, mixer);
/// CommManager::stream: SMALL_IMU and ATTITUDE_QUATERNION on every sample, OUTPUT_RAW on every
/// 8th (stamp: clock_millis, values: Mixer::raw_outputs).
void Emulator::step_imu(const sim::Truth& truth, std::int64_t t) {
  const std::int64_t ft = fcu_time();
  const auto m = sensors_.imu(truth, imu_.dt_since_last(t));
  imu_.last_sample = t;
  std::array<float, 3> a{static_cast<float>(m.accel.x()), static_cast<float>(m.accel.y()), static_cast<float>(m.accel.z())};
  std::array<float, 3> g{static_cast<float>(m.gyro.x()), static_cast<float>(m.gyro.y()), static_cast<float>(m.gyro.z())};
  fcu_->fw().imu(a, g, ft);
  mavlink::SmallImu s;
  s.time_boot_us = static_cast<std::uint64_t>(ft / 1000);
  s.xacc = a[0];
  s.yacc = a[1];
  s.zacc = a[2];
  s.xgyro = g[0];
  s.ygyro = g[1];
  s.zgyro = g[2];
  s.temperature = static_cast<float>(m.temperature);
  imu_at_ = send(s);
  imu_delivered_ = true;                                     // unless corrupt_frames() damages it
  const Eigen::Quaterniond q = sim::attitude(sim_.state());  // the true attitude (a real FCU: its estimate)
  mavlink::AttitudeQuaternion att;
  att.time_boot_ms = static_cast<std::uint32_t>(ft / 1'000'000);
  att.q1 = static_cast<float>(q.w());
  att.q2 = static_cast<float>(q.x());
  att.q3 = static_cast<float>(q.y());
  att.q4 = static_cast<float>(q.z());
  att.rollspeed = static_cast<float>(sim_.state()[sim::P]);
  att.pitchspeed = static_cast<float>(sim_.state()[sim::Q]);
  att.yawspeed = static_cast<float>(sim_.state()[sim::R]);
  send(att);
  if (imu_count_++ % 8 == 0) {
    mavlink::RosflightOutputRaw r;
    r.stamp = static_cast<std::uint64_t>(ft / 1'000'000);
    const auto& raw = fcu_->fw().raw_outputs();
    for (std::size_t i = 0; i < raw.size(); ++i) r.values[i] = raw[i];
    send(r);
  }
}

/// A receiver frame every 20 ms: RC_CHANNELS as CommManager::send_rc_raw and
/// MavlinkAdapter::send_rc_raw pack it (chancount 0, channels 1..8 = chan * 1000 + 1000 us
/// converted to uint16_t, i.e. truncated: 1350 us, the float 0.35f, reads back 1349; 9..18 = 0,
/// rssi 0), then RC::run and CommandManager::run (ROSflight::run).
void Emulator::step_rc(std::int64_t t) {
  if (!rc_script_.receiver() || rc_.poll(t) != Poll::sample) return;
  rc_.last_sample = t;
  const firmware::RcFrame f = RcScript::frame(rc_script_.at(t));
  mavlink::RcChannels rc;
  rc.time_boot_ms = static_cast<std::uint32_t>(fcu_time() / 1'000'000);
  rc.chancount = 0;
  std::uint16_t* ch[8] = {&rc.chan1_raw, &rc.chan2_raw, &rc.chan3_raw, &rc.chan4_raw,
                          &rc.chan5_raw, &rc.chan6_raw, &rc.chan7_raw, &rc.chan8_raw};
  for (std::size_t i = 0; i < 8; ++i) *ch[i] = static_cast<std::uint16_t>(f.chan[i] * 1000.0 + 1000);
  rc.rssi = 0;
  send(rc);
  fcu_->fw().rc(f, fcu_time());
}

/// CommManager::send_1hz_heartbeat (HEARTBEAT 1 Hz, ROSFLIGHT_STATUS 10 Hz), then the rest of
/// CommManager::stream (parameter echoes and lists, held log lines, status on a change).
void Emulator::step_streams(std::int64_t t) {
  if (heartbeat_.poll(t) == Poll::sample) {
    heartbeat_.last_sample = t;
    send(fcu_->heartbeat());
  }
  if (status_.poll(t) == Poll::sample) {
    status_.last_sample = t;
    send(fcu_->status());
  }
  fcu_->stream(fcu_time(), out_);
}

}  // namespace tern::fcu::emulator
