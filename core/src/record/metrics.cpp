#include "record/metrics.hpp"

#include <cmath>

#include "record/common_frame.hpp"
#include "tern/math.hpp"

namespace tern::core {

namespace {}

void FlightMetrics::configure() {
  declare(state_, "state", "estimated state");
  declare(truth_, "truth", "true state (simulation)", Need::optional);
  declare(gnss_, "gnss", "GNSS fixes (the raw-GNSS baseline of the estimation figures)", Need::optional);
  declare(command_, "controller_command", "commanded altitude, course, airspeed", Need::optional);
  declare(internals_, "controller_internals", "commanded roll and pitch", Need::optional);
  declare(path_, "current_path", "commanded path segment", Need::optional);
  declare(phase_, "flight_phase", "flight phase (only cruise counts)", Need::optional);
  declare(period_, "period", 0.01, ParamSpec("s", 0.0, 10.0, "sample the errors at most this often"));
  declare(start_after_, "start_after", 60.0,
          ParamSpec("s", 0.0, 1e9, "when the mission never completes a loop, the window starts at this flight time"));
  declare(cruise_only_, "cruise_only", true, ParamSpec("", 0, 0, "count only samples in the cruise phase"));
}

void FlightMetrics::reset() {
  est_ = {};
  gnss_err_ = {};
  trk_ = {};
  passages_.clear();
  loops_ = 0;
  max_cross_ = max_alt_ = 0;
  first_index_ = last_index_ = -1;
  last_sample_ = -1;
  window_start_ = -1;
}

void FlightMetrics::step(Nanos now) {
  // waypoint passages and loops
  if (path_.has_value()) {
    const int idx = path_->waypoint_index;
    if (idx != last_index_) {
      if (last_index_ >= 0) passages_.push_back({now, last_index_});
      if (first_index_ < 0 && idx >= 0) first_index_ = idx;
      if (last_index_ >= 0 && idx >= 0 && idx == first_index_ && last_index_ != first_index_) {
        ++loops_;
        if (loops_ == 1 && window_start_ < 0) window_start_ = now;
      }
      last_index_ = idx;
    }
  }
  if (window_start_ < 0 && loops_ == 0 && now >= from_seconds(start_after_()) && first_index_ < 0) window_start_ = now;
  if (window_start_ < 0 || now < window_start_) return;
  if (last_sample_ >= 0 && now - last_sample_ < from_seconds(period_())) return;
  if (cruise_only_() && phase_.connected() && phase_->phase != msg::Phase::cruise) return;
  const msg::State& s = state_.get();
  if (!s.valid) return;
  last_sample_ = now;
  if (truth_.has_value()) add_estimation_errors(s, truth_.get());
  if (path_.has_value()) {
    const msg::CurrentPath& cp = path_.get();
    const Eigen::Vector2d p(s.p_n, s.p_e);
    Eigen::Vector2d closest = p;
    if (cp.path_type == msg::CurrentPath::line) {
      const Eigen::Vector2d r(cp.r.x(), cp.r.y());
      Eigen::Vector2d q(cp.q.x(), cp.q.y());
      if (q.norm() > 1e-9) {
        q.normalize();
        closest = r + q * (p - r).dot(q);
      }
    } else {
      const Eigen::Vector2d c(cp.c.x(), cp.c.y());
      const Eigen::Vector2d d = p - c;
      if (d.norm() > 1e-9) closest = c + cp.rho * d.normalized();
    }
    trk_[t_north].add(p.x() - closest.x());
    trk_[t_east].add(p.y() - closest.y());
    if (std::isfinite((p - closest).norm())) max_cross_ = std::max(max_cross_, (p - closest).norm());
  }
  if (command_.has_value()) {
    trk_[t_alt].add(command_->h_c - (-s.p_d));
    if (std::isfinite(command_->h_c + s.p_d)) max_alt_ = std::max(max_alt_, std::fabs(command_->h_c + s.p_d));
    trk_[t_course].add(wrap_pi(command_->chi_c - s.chi) * kDegPerRad);
    trk_[t_airspeed].add(command_->Va_c - s.Va);
  }
  if (internals_.has_value()) {
    trk_[t_roll].add(wrap_pi(internals_->phi_c - s.phi) * kDegPerRad);
    trk_[t_pitch].add(wrap_pi(internals_->theta_c - s.theta) * kDegPerRad);
  }
}

// Estimate vs truth in the truth's frame (common_frame.hpp), and beside it the latest GNSS fix
// vs the same truth sample: the raw-GNSS baseline computed the same way.
void FlightMetrics::add_estimation_errors(const msg::State& s, const msg::State& t) {
  const Eigen::Vector3d p = estimate_in_truth_frame(s, t);
  est_[e_north].add(p.x() - t.p_n);
  est_[e_east].add(p.y() - t.p_e);
  est_[e_alt].add(t.p_d - p.z());
  est_[e_roll].add(wrap_pi(s.phi - t.phi) * kDegPerRad);
  est_[e_pitch].add(wrap_pi(s.theta - t.theta) * kDegPerRad);
  est_[e_heading].add(wrap_pi(s.psi - t.psi) * kDegPerRad);
  est_[e_course].add(wrap_pi(s.chi - t.chi) * kDegPerRad);
  est_[e_airspeed].add(s.Va - t.Va);
  est_[e_wind_n].add(s.w_n - t.w_n);
  est_[e_wind_e].add(s.w_e - t.w_e);
  if (gnss_.has_value()) {
    const Eigen::Vector3d g = fix_in_truth_frame(gnss_.get(), t);
    gnss_err_[0].add(g.x() - t.p_n);
    gnss_err_[1].add(g.y() - t.p_e);
    gnss_err_[2].add(t.p_d - g.z());
  }
}

std::vector<std::pair<std::string, double>> FlightMetrics::summary() const {
  std::vector<std::pair<std::string, double>> out;
  out.emplace_back("loops", loops_);
  out.emplace_back("waypoints_reached", static_cast<double>(passages_.size()));
  out.emplace_back("max_cross_track_m", max_cross_);
  out.emplace_back("max_altitude_error_m", max_alt_);
  out.emplace_back("window_start_s", window_start_ < 0 ? std::nan("") : to_seconds(window_start_));
  if (truth_.connected())
    for (int i = 0; i < kEst; ++i) out.emplace_back(std::string("est_rmse_") + kEstNames[i], est_[i].value());
  if (truth_.connected() && gnss_.connected())
    for (int i = 0; i < kGnss; ++i) out.emplace_back(std::string("gnss_rmse_") + kEstNames[i], gnss_err_[i].value());
  for (int i = 0; i < kTrk; ++i) out.emplace_back(std::string("track_rmse_") + kTrkNames[i], trk_[i].value());
  return out;
}

}  // namespace tern::core
