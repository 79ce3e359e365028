// plugin_step.cpp: fcu_serial's step: waiting for the FCU's IMU sample of `now` (clock fcu),
// or following the host clock while the FCU is silent, then publishing what is due, stamped by
// FcuClock (tern_fcu_serial/fcu_clock.hpp). See fcu_serial_plugin.hpp.
#include <algorithm>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "fcu_serial_plugin.hpp"
#include "tern/atmosphere.hpp"

namespace tern::fcu_serial {

namespace {
fcu::HostTime host_now() { return {fcu::steady_ns()}; }
constexpr tern::Nanos kRcCheckAfter = 1'000'000'000;  // the start-up RC check: 1 s of flight
/// SMALL_IMU's temperature is the board's ImuStruct::temperature, sent as it is by
/// CommManager::send_imu (rosflight_firmware src/comm_manager.cpp, via Sensors::get_imu()). This
/// firmware's include/interface/board.h declares it in K; a board that fills it in deg C (the
/// firmware's own test/test_board.cpp imu_read writes 25.0) reads below this, and is converted.
constexpr float kCelsiusBelow = 150.0f;
}  // namespace

void FcuSerial::step(tern::Nanos now) {
  if (!link_) throw std::runtime_error("fcu_serial: step() before start()");
  for (auto& e : link_->take_events()) log().warn("{}", e);
  clock_.first_step(host_now(), fcu::FlightTime{now});
  if (lockstep_() && s_.owed_command) {
    send_command();  // the command for the IMU period that ends at `now` (before waiting for it)
    s_.owed_command = false;
  }
  pull();
  if (policy_ == fcu::ClockPolicy::fcu) {
    if (s_.link_lost || s_.imu_stalled)
      follow_host(now);
    else
      wait_for(now);
  }
  process(now);
  warn_without_rc(now);
  s_.last_step_now = now;
  check_link(host_now());
  send_due(now);
}

void FcuSerial::pull() {
  const std::size_t before = s_.pending.size();
  link_->drain(s_.pending);
  for (std::size_t i = before; i < s_.pending.size(); ++i) {
    const fcu::Received& r = s_.pending[i];
    s_.last_rx.ns = std::max(s_.last_rx.ns, r.rx_ns);
    if (r.frame.msgid == mav::SmallImu::kId) {
      s_.imu_stalled = false;
      s_.newest_imu = fcu::FcuTime{static_cast<std::int64_t>(mav::SmallImu::unpack(r.frame.payload.data()).time_boot_us) * 1000};
    }
  }
}

bool FcuSerial::has_imu_pending() const {
  return std::any_of(s_.pending.begin(), s_.pending.end(), [](const fcu::Received& r) { return r.frame.msgid == mav::SmallImu::kId; });
}

/// Clock fcu: waits until the IMU sample of time `now` has arrived, at most wait_timeout (then
/// flight time follows the host clock until a sample comes; a silent link is check_link's).
void FcuSerial::wait_for(tern::Nanos now) {
  std::int64_t deadline = fcu::steady_ns() + tern::from_seconds(wait_timeout_());
  for (;;) {
    if (s_.newest_imu && clock_.reached(*s_.newest_imu, fcu::FlightTime{now})) return;
    if (deadline - fcu::steady_ns() <= 0 && lockstep_() && lockstep_resend(now))
      deadline = fcu::steady_ns() + tern::from_seconds(wait_timeout_());
    const std::int64_t left = deadline - fcu::steady_ns();
    if (left <= 0) {
      s_.imu_stalled = true;
      clock_.follow_host(host_now(), fcu::FlightTime{now});
      if (fcu::steady_ns() - s_.last_rx.ns < tern::from_seconds(link_timeout_()))
        log().warn("t={:.3f} s: no IMU sample from the FCU for {:.2f} s while other data arrives; flight time follows the host clock",
                   tern::to_seconds(now), wait_timeout_());
      return;
    }
    link_->wait(left);
    pull();
  }
}

/// Lockstep: the FCU waits for one command per IMU sample it delivered. Sends the last one
/// again (ours may have been lost); with nothing at all for link_timeout the link is gone: the
/// flight ends in one line rather than fly commands on a frozen state.
bool FcuSerial::lockstep_resend(tern::Nanos now) {
  const std::int64_t silent = fcu::steady_ns() - s_.last_rx.ns;
  if (silent > tern::from_seconds(link_timeout_()))
    throw std::runtime_error(
        fmt::format("lockstep: nothing from the FCU for {:.2f} s at t={:.3f} s (link_timeout): "
                    "the emulator stopped, or is not running with --lockstep",
                    tern::to_seconds(silent), tern::to_seconds(now)));
  send_command();
  ++s_.lockstep_resends;
  return true;
}

/// The FCU is silent: flight time follows the host clock until it speaks again (so the host
/// neither races ahead nor floods the link with commands).
void FcuSerial::follow_host(tern::Nanos now) {
  for (std::int64_t left; (left = clock_.host_deadline(fcu::FlightTime{now}).ns - fcu::steady_ns()) > 0;) {
    if (s_.link_lost ? !s_.pending.empty() : !s_.imu_stalled) break;  // data again / an IMU sample again
    link_->wait(left);
    pull();
  }
}

void FcuSerial::process(tern::Nanos now) {
  Due due;
  while (!s_.pending.empty()) {
    const fcu::Received& r = s_.pending.front();
    const auto m = mav::decode(r.frame);
    if (m) {
      if (const auto* s = std::get_if<mav::SmallImu>(&*m)) {
        if (!take_imu(*s, r, now, due)) break;  // a later sample: the next step publishes it
      } else {
        const fcu::FlightTime stream = clock_.untimed(fcu::HostTime{r.rx_ns});
        if (policy_ == fcu::ClockPolicy::wall && stream.ns > now) break;
        handle_other(*m, r, stream, due);
      }
    }
    s_.pending.pop_front();
  }
  publish(due);
  if (due.imu && lockstep_()) s_.owed_command = true;
}

/// One SMALL_IMU: a reboot or a gap is one line (counted); false if it belongs to a later step.
bool FcuSerial::take_imu(const mav::SmallImu& s, const fcu::Received& r, tern::Nanos now, Due& due) {
  const fcu::FcuTime t{static_cast<std::int64_t>(s.time_boot_us) * 1000};
  const fcu::FcuClock::Imu i = clock_.imu(t, fcu::HostTime{r.rx_ns}, fcu::FlightTime{now});
  if (i.rebooted) {
    ++s_.reboots;
    log().warn("FCU rebooted: its clock went back from {:.3f} s to {:.3f} s; time re-anchored", i.before.ns * 1e-9, t.ns * 1e-9);
  }
  if (i.stamp.ns > now) return false;
  if (const auto gap = clock_.accept_imu(t, i.stamp)) {
    ++s_.link_losses;
    log().warn("t={:.3f} s: no IMU sample for {:.2f} s of FCU time (link silent or frames lost); resumed", tern::to_seconds(now),
               *gap * 1e-9);
  }
  msg::Imu out;
  out.stamp = i.stamp.ns;
  out.accel = Eigen::Vector3d(s.xacc, s.yacc, s.zacc);
  out.gyro = Eigen::Vector3d(s.xgyro, s.ygyro, s.zgyro);
  out.temperature = s.temperature < kCelsiusBelow ? s.temperature + tern::kZeroCelsius : s.temperature;  // deg C or K
  if (due.imu) ++s_.imu_superseded;
  due.imu = out;
  return true;
}

void FcuSerial::publish(const Due& due) {
  if (due.imu) imu_out_.publish(*due.imu);
  if (due.mag) mag_out_.publish(*due.mag);
  if (due.baro) baro_out_.publish(*due.baro);
  if (due.diff) diff_out_.publish(*due.diff);
  if (due.gnss) gnss_out_.publish(*due.gnss);
  if (due.rc) rc_out_.publish(*due.rc);
  if (due.status && s_.status) status_out_.publish(*s_.status);
}

/// The start-up RC check: without RC frames the firmware never mixes.
void FcuSerial::warn_without_rc(tern::Nanos now) {
  if (!s_.first_step_now) s_.first_step_now = now;
  if (s_.rc_seen || s_.rc_warned || now - *s_.first_step_now < kRcCheckAfter) return;
  s_.rc_warned = true;
  log().warn(
      "no RC_CHANNELS from the FCU in the first second: without a receiver the firmware never mixes "
      "(command_manager.cpp CommandManager::run mixes on a new RC frame), so the outputs will not move");
}

}  // namespace tern::fcu_serial
