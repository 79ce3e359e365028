// fcu_clock.cpp: see tern_fcu_serial/fcu_clock.hpp.
#include "tern_fcu_serial/fcu_clock.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace tern::fcu {

ClockPolicy parse_clock_policy(std::string_view s) {
  if (s == "fcu") return ClockPolicy::fcu;
  if (s == "wall") return ClockPolicy::wall;
  throw std::invalid_argument("clock '" + std::string(s) + "' is not fcu or wall");
}

void FcuClock::first_step(HostTime host, FlightTime now) {
  if (host_anchored_) return;
  host_anchored_ = true;
  host_origin_ = host;
  host_origin_flight_ = now;
}

void FcuClock::restart() {
  anchored_ = host_anchored_ = false;
  last_imu_.reset();
  last_stamp_ = stream_ = FlightTime{};
}

FlightTime FcuClock::of_fcu(FcuTime t, HostTime rx) const {
  if (policy_ == ClockPolicy::fcu) return {anchor_flight_.ns + (t.ns - anchor_fcu_.ns)};
  return of_host(timesync_.synced() ? HostTime{timesync_.to_companion(t.ns)} : rx);
}

FcuClock::Imu FcuClock::imu(FcuTime t, HostTime rx, FlightTime now) {
  Imu r;
  if (last_imu_ && t.ns <= last_imu_->ns - kRebootStep) {
    r.rebooted = true;
    r.before = *last_imu_;
    anchored_ = false;
    timesync_.clear();
    last_imu_ = t;  // the new epoch: a sample kept for a later step is not a second reboot
  }
  if (!anchored_ && policy_ == ClockPolicy::fcu) {
    anchored_ = true;
    anchor_fcu_ = t;
    anchor_flight_ = last_imu_ ? FlightTime{std::max(now.ns, last_stamp_.ns + 1)} : now;
  }
  r.stamp = of_fcu(t, rx);
  // stamps never go back (policy wall: the TIMESYNC estimate can move by a little)
  if (last_imu_ && r.stamp.ns <= last_stamp_.ns) r.stamp.ns = last_stamp_.ns + 1;
  return r;
}

std::optional<std::int64_t> FcuClock::accept_imu(FcuTime t, FlightTime stamp) {
  std::optional<std::int64_t> gap;
  if (last_imu_ && t.ns - last_imu_->ns > gap_) gap = t.ns - last_imu_->ns;
  last_imu_ = t;
  last_stamp_ = stream_ = stamp;
  return gap;
}

FlightTime FcuClock::untimed(HostTime rx) const { return policy_ == ClockPolicy::fcu ? stream_ : of_host(rx); }

FlightTime FcuClock::timed(FcuTime t, HostTime rx, FlightTime stream) const {
  if (t.ns <= 0 || (policy_ == ClockPolicy::fcu && !anchored_)) return stream;
  return {std::min(of_fcu(t, rx).ns, stream.ns)};
}

bool FcuClock::reached(FcuTime newest, FlightTime now) const {
  if (!anchored_) return true;                              // the first sample anchors at `now`
  if (last_imu_ && newest.ns < last_imu_->ns) return true;  // a reboot: imu() re-anchors
  return anchor_flight_.ns + (newest.ns - anchor_fcu_.ns) >= now.ns;
}

}  // namespace tern::fcu
