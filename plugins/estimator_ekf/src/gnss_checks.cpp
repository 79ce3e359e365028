// GnssChecks: the GNSS start-up checks (see gnss_checks.hpp).
#include "tern/estimator_ekf/gnss_checks.hpp"

#include <algorithm>
#include <cmath>

#include <cstdio>
#include <utility>

namespace tern::ekf {

namespace {
/// A reported accuracy above its limit; 0 or non-finite is "not reported" and passes.
bool above(double reported, double limit) { return std::isfinite(reported) && reported > 0.0 && reported > limit; }

/// The dilution the PDOP check judges: PDOP from both (PX4), HDOP where only it is reported
/// (ArduPilot), 0 when neither is.
double reported_dop(const msg::Gnss& f) {
  const bool h = std::isfinite(f.hdop) && f.hdop > 0.0, v = std::isfinite(f.vdop) && f.vdop > 0.0;
  return h && v ? std::hypot(f.hdop, f.vdop) : h ? f.hdop : 0.0;
}
}  // namespace

std::string gnss_check_names(std::uint32_t bits) {
  static constexpr std::pair<std::uint32_t, const char*> kNames[] = {{gnss_check::fix, "fix type"},
                                                                     {gnss_check::nsats, "satellites"},
                                                                     {gnss_check::pdop, "dilution of precision"},
                                                                     {gnss_check::eph, "h_acc"},
                                                                     {gnss_check::epv, "v_acc"},
                                                                     {gnss_check::sacc, "s_acc"},
                                                                     {gnss_check::hdrift, "horizontal drift"},
                                                                     {gnss_check::vdrift, "vertical drift"},
                                                                     {gnss_check::hspeed, "horizontal speed"},
                                                                     {gnss_check::vspeed, "vertical speed"}};
  std::string s;
  for (const auto& [bit, name] : kNames) {
    if ((bits & bit) == 0) continue;
    if (!s.empty()) s += ", ";
    s += name;
  }
  return s;
}

bool GnssChecks::update(const msg::Gnss& fix, bool usable, Motion motion) {
  if (passed_) return true;
  if (first_stamp_ < 0) {
    first_stamp_ = fix.stamp;
    last_fail_ = fix.stamp;  // the first fix counts as a failure: hold_time from it at least
  }
  last_ = fix;
  if (usable) {
    run_drift(fix, motion);
  } else {
    reset_drift();  // a fix gap: the next displacement is not a drift over one interval
  }
  const auto mask = static_cast<std::uint32_t>(c_.mask);
  // In the air a receiver cannot settle as on the ground (its antenna turns from part of the sky
  // in every bank): the in-flight limits apply, as after the checks have passed (PX4
  // runSimplifiedChecks).
  const std::uint32_t quality = motion == Motion::in_air ? flight_failures(fix, usable) : fix_failures(fix, usable);
  failing_ = (quality | drift_failing_) & (mask | gnss_check::fix);
  if (failing_ != 0) {
    last_fail_ = fix.stamp;
  } else if (to_seconds(fix.stamp - last_fail_) >= c_.hold_time) {
    passed_ = true;
    passed_stamp_ = fix.stamp;
  }
  return passed_;
}

std::uint32_t GnssChecks::fix_failures(const msg::Gnss& f, bool usable) const {
  std::uint32_t fail = 0;
  if (!usable) fail |= gnss_check::fix;
  if (usable && f.num_sats > 0 && f.num_sats < c_.min_sats) fail |= gnss_check::nsats;
  if (above(reported_dop(f), c_.max_pdop)) fail |= gnss_check::pdop;
  if (above(f.h_acc, c_.max_h_acc)) fail |= gnss_check::eph;
  if (above(f.v_acc, c_.max_v_acc)) fail |= gnss_check::epv;
  if (above(f.s_acc, c_.max_s_acc)) fail |= gnss_check::sacc;
  return fail;
}

std::uint32_t GnssChecks::flight_failures(const msg::Gnss& f, bool usable) const {
  std::uint32_t fail = usable ? 0u : gnss_check::fix;
  if (above(f.h_acc, c_.flight_max_h_acc)) fail |= gnss_check::eph;
  if (above(f.v_acc, c_.flight_max_v_acc)) fail |= gnss_check::epv;
  if (above(f.s_acc, c_.flight_max_s_acc)) fail |= gnss_check::sacc;
  return fail;
}

void GnssChecks::run_drift(const msg::Gnss& f, Motion motion) {
  if (motion == Motion::in_air) {  // PX4: passed in flight
    drift_failing_ = 0;
    h_drift_ = v_drift_ = h_speed_ = v_speed_ = 0.0;
    reset_drift();
    return;
  }
  if (motion == Motion::moving) {  // PX4: the verdicts from before the movement are kept
    reset_drift();
    return;
  }
  if (!frame_) frame_.emplace(f.lat, f.lon, f.alt);
  const Eigen::Vector3d ned = frame_->to_ned(f.lat, f.lon, f.alt);
  if (!ned.allFinite() || !f.vel.allFinite()) return;
  if (prev_stamp_ >= 0) {
    const double dt = std::clamp(to_seconds(f.stamp - prev_stamp_), 1e-3, c_.drift_time_constant);
    const double k = dt / c_.drift_time_constant;
    const Eigen::Vector3d limit(c_.max_h_drift, c_.max_h_drift, c_.max_v_drift);
    // the position rate: filtered, then the state clamped (anti-windup on the state, not the input)
    rate_filt_ = (k * (ned - prev_ned_) / dt + (1.0 - k) * rate_filt_).cwiseMax(-10.0 * limit).cwiseMin(10.0 * limit);
    // the reported velocity: the input clamped, then filtered
    const Eigen::Vector3d v = f.vel.cwiseMax(-10.0 * limit).cwiseMin(10.0 * limit);
    vel_filt_ = k * v + (1.0 - k) * vel_filt_;
    h_drift_ = rate_filt_.head<2>().norm();
    v_drift_ = std::fabs(rate_filt_.z());
    h_speed_ = vel_filt_.head<2>().norm();
    v_speed_ = std::fabs(vel_filt_.z());
    drift_failing_ = (h_drift_ > c_.max_h_drift ? gnss_check::hdrift : 0u) | (v_drift_ > c_.max_v_drift ? gnss_check::vdrift : 0u) |
                     (h_speed_ > c_.max_h_drift ? gnss_check::hspeed : 0u) | (v_speed_ > c_.max_v_drift ? gnss_check::vspeed : 0u);
  }
  prev_ned_ = ned;
  prev_stamp_ = f.stamp;
}

void GnssChecks::reset_drift() {
  prev_stamp_ = -1;
  rate_filt_.setZero();
  vel_filt_.setZero();
}

std::string GnssChecks::describe_failing() const {
  std::string s;
  const auto add = [&](std::uint32_t bit, const char* format, double value, double limit) {
    if ((failing_ & bit) == 0) return;
    char buf[64];
    std::snprintf(buf, sizeof buf, format, value, limit);
    if (!s.empty()) s += ", ";
    s += buf;
  };
  add(gnss_check::fix, "fix type %.0f below the minimum", static_cast<double>(last_.fix_type), 0.0);
  add(gnss_check::nsats, "%.0f satellites < %.0f", last_.num_sats, c_.min_sats);
  add(gnss_check::pdop, last_.vdop > 0.0 ? "PDOP %.2f > %.2f" : "HDOP %.2f > %.2f", reported_dop(last_), c_.max_pdop);
  add(gnss_check::eph, "h_acc %.2f m > %.2f", last_.h_acc, c_.max_h_acc);
  add(gnss_check::epv, "v_acc %.2f m > %.2f", last_.v_acc, c_.max_v_acc);
  add(gnss_check::sacc, "s_acc %.2f m/s > %.2f", last_.s_acc, c_.max_s_acc);
  add(gnss_check::hdrift, "horizontal drift %.2f m/s > %.2f", h_drift_, c_.max_h_drift);
  add(gnss_check::vdrift, "vertical drift %.2f m/s > %.2f", v_drift_, c_.max_v_drift);
  add(gnss_check::hspeed, "horizontal speed %.2f m/s > %.2f", h_speed_, c_.max_h_drift);
  add(gnss_check::vspeed, "vertical speed %.2f m/s > %.2f", v_speed_, c_.max_v_drift);
  return s;
}

}  // namespace tern::ekf
