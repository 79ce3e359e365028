// The touchdown on the truth. See landing_report.hpp.
#include "record/landing_report.hpp"

#include <algorithm>

#include "tern/math.hpp"

namespace tern::core {

namespace {

bool from_the_flare(msg::Phase p) { return p == msg::Phase::flare || p == msg::Phase::rollout || p == msg::Phase::stopped; }
}  // namespace

void LandingReport::observe(Nanos now, msg::Phase phase, const msg::State& truth, const msg::WaypointList* wps) {
  const Eigen::Vector3d p(truth.p_n, truth.p_e, truth.p_d);
  if (!p.allFinite()) return;
  if (phase == msg::Phase::preflight || !home_) home_ = p;  // the last sample at rest (or the first)
  if (!have_target_ && wps != nullptr) {
    for (std::uint32_t i = 0; i < std::min<std::uint32_t>(wps->count, msg::WaypointList::kCapacity); ++i) {
      const msg::Waypoint& w = wps->items[i];
      if (w.type != msg::Waypoint::land || w.lla) continue;
      target_ = home_->head<2>() + w.w.head<2>();
      heading_ = w.chi_d;
      have_target_ = true;
    }
  }
  if (!td_) {  // the sink rates within the window before now
    sinks_.emplace_back(now, truth.v_d);
    while (now - sinks_.front().first > from_seconds(kSinkWindow)) sinks_.pop_front();
  }
  const Eigen::Vector2d u(std::cos(heading_), std::sin(heading_));
  if (!td_ && from_the_flare(phase) && -p.z() <= -home_->z() + kContactMargin) {
    Touchdown t;
    t.t_s = to_seconds(now);
    td_point_ = p.head<2>();
    if (have_target_) {
      const Eigen::Vector2d d = td_point_ - target_;
      t.along_m = d.dot(u);
      t.across_m = -u.y() * d.x() + u.x() * d.y();
    }
    t.sink_rate_mps = truth.v_d;
    for (const auto& [at, v_d] : sinks_) t.sink_rate_mps = std::max(t.sink_rate_mps, v_d);
    t.airspeed_mps = truth.Va;
    t.ground_speed_mps = std::hypot(truth.v_n, truth.v_e);
    t.roll_deg = truth.phi * kDegPerRad;
    t.pitch_deg = truth.theta * kDegPerRad;
    td_ = t;
  }
  if (td_ && !td_->stopped) {
    td_->rollout_m = (p.head<2>() - td_point_).norm();
    td_->stopped = std::hypot(truth.v_n, truth.v_e) < kStoppedSpeed;
  }
}

}  // namespace tern::core
