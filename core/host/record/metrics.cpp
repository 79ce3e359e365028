#include "record/metrics.hpp"

#include <cmath>

#include "tern/common_frame.hpp"
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
  declare(phase_, "flight_phase", "flight phase (only cruise counts; the landing's touchdown)", Need::optional);
  declare(waypoints_, "waypoints", "the mission: a land item's touchdown point (the landing's touchdown figures)", Need::optional);
  declare(period_, "period", 0.01, ParamSpec("s", 0.0, 10.0, "sample the errors at most this often"));
  declare(start_after_, "start_after", 60.0,
          ParamSpec("s", 0.0, 1e9, "when the mission never completes a loop, the window starts at this flight time"));
  declare(cruise_only_, "cruise_only", true, ParamSpec("", 0, 0, "count only samples in the cruise phase"));
}

void FlightMetrics::reset() { f_ = Flight{}; }

void FlightMetrics::step(Nanos now) {
  if (truth_.has_value() && phase_.has_value())
    f_.landing.observe(now, phase_->phase, truth_.get(), waypoints_.has_value() ? &waypoints_.get() : nullptr);
  // waypoint passages and loops
  if (path_.has_value()) {
    const int idx = path_->waypoint_index;
    if (idx != f_.last_index) {
      if (f_.last_index >= 0) f_.passages.push_back({now, f_.last_index});
      if (f_.first_index < 0 && idx >= 0) f_.first_index = idx;
      if (f_.last_index >= 0 && idx >= 0 && idx == f_.first_index && f_.last_index != f_.first_index) {
        ++f_.loops;
        if (f_.loops == 1 && f_.window_start < 0) f_.window_start = now;
      }
      f_.last_index = idx;
    }
  }
  if (f_.window_start < 0 && f_.loops == 0 && now >= from_seconds(start_after_()) && f_.first_index < 0) f_.window_start = now;
  if (f_.window_start < 0 || now < f_.window_start) return;
  if (f_.last_sample >= 0 && now - f_.last_sample < from_seconds(period_())) return;
  if (cruise_only_() && phase_.connected() && phase_->phase != msg::Phase::cruise) return;
  const msg::State& s = state_.get();
  if (!s.valid) return;
  f_.last_sample = now;
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
    f_.trk[t_north].add(p.x() - closest.x());
    f_.trk[t_east].add(p.y() - closest.y());
    if (std::isfinite((p - closest).norm())) f_.max_cross = std::max(f_.max_cross, (p - closest).norm());
  }
  if (command_.has_value()) {
    f_.trk[t_alt].add(command_->h_c - (-s.p_d));
    if (std::isfinite(command_->h_c + s.p_d)) f_.max_alt = std::max(f_.max_alt, std::fabs(command_->h_c + s.p_d));
    f_.trk[t_course].add(wrap_pi(command_->chi_c - s.chi) * kDegPerRad);
    f_.trk[t_airspeed].add(command_->Va_c - s.Va);
  }
  if (internals_.has_value()) {
    f_.trk[t_roll].add(wrap_pi(internals_->phi_c - s.phi) * kDegPerRad);
    f_.trk[t_pitch].add(wrap_pi(internals_->theta_c - s.theta) * kDegPerRad);
  }
}

// Estimate vs truth in the truth's frame (common_frame.hpp), and beside it the latest GNSS fix
// vs the same truth sample: the raw-GNSS baseline computed the same way.
void FlightMetrics::add_estimation_errors(const msg::State& s, const msg::State& t) {
  const Eigen::Vector3d p = estimate_in_truth_frame(s, t);
  f_.est[e_north].add(p.x() - t.p_n);
  f_.est[e_east].add(p.y() - t.p_e);
  f_.est[e_alt].add(t.p_d - p.z());
  f_.est[e_roll].add(wrap_pi(s.phi - t.phi) * kDegPerRad);
  f_.est[e_pitch].add(wrap_pi(s.theta - t.theta) * kDegPerRad);
  f_.est[e_heading].add(wrap_pi(s.psi - t.psi) * kDegPerRad);
  f_.est[e_course].add(wrap_pi(s.chi - t.chi) * kDegPerRad);
  f_.est[e_airspeed].add(s.Va - t.Va);
  f_.est[e_wind_n].add(s.w_n - t.w_n);
  f_.est[e_wind_e].add(s.w_e - t.w_e);
  if (gnss_.has_value()) {
    const Eigen::Vector3d g = fix_in_truth_frame(gnss_.get(), t);
    f_.gnss_err[0].add(g.x() - t.p_n);
    f_.gnss_err[1].add(g.y() - t.p_e);
    f_.gnss_err[2].add(t.p_d - g.z());
  }
}

std::vector<std::pair<std::string, double>> FlightMetrics::summary() const {
  std::vector<std::pair<std::string, double>> out;
  out.emplace_back("loops", f_.loops);
  out.emplace_back("waypoints_reached", static_cast<double>(f_.passages.size()));
  out.emplace_back("max_cross_track_m", f_.max_cross);
  out.emplace_back("max_altitude_error_m", f_.max_alt);
  out.emplace_back("window_start_s", f_.window_start < 0 ? std::nan("") : to_seconds(f_.window_start));
  if (truth_.connected())
    for (int i = 0; i < kEst; ++i) out.emplace_back(std::string("est_rmse_") + kEstNames[i], f_.est[i].value());
  if (truth_.connected() && gnss_.connected())
    for (int i = 0; i < kGnss; ++i) out.emplace_back(std::string("gnss_rmse_") + kEstNames[i], f_.gnss_err[i].value());
  for (int i = 0; i < kTrk; ++i) out.emplace_back(std::string("track_rmse_") + kTrkNames[i], f_.trk[i].value());
  return out;
}

}  // namespace tern::core
