// The replay report's attitude notes: when the estimate's roll or pitch is more than
// kAttitudeGapNote deg RMS from the reference's, which of the two the specific-force check
// (replay_specific_force.cpp: roll and pitch only, the yaw solved per epoch, so neither side's yaw
// error enters) finds consistent with the accelerometer and the GNSS; when its yaw
// is more than kYawGapNote from the reference's, which of the two headings the GNSS course
// contradicts beyond the crab angle the estimated wind allows. One of the two more than
// kRefereeMargin times the other's error is "the one off"; else neither can be called wrong.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "replay/replay_report_parts.hpp"

namespace tern::core::replay_report {

namespace {

/// The median interval of the IMU's samples (s), NaN without an imu table.
double imu_interval(const RunTables& run) {
  if (!run.imu || run.imu->rows < 2) return NAN;
  const auto& t = run.imu->at("time");
  std::vector<double> dt;
  for (std::size_t k = 1; k < t.size(); ++k) dt.push_back(t[k] - t[k - 1]);
  return median(dt);
}

/// Which of two errors against an independent check is the one off (deg RMS each).
std::string verdict(double estimate_rms, double reference_rms, double gap_rms) {
  if (reference_rms > kRefereeMargin * estimate_rms)
    return ": the reference is the one the sensors contradict, so the gap is the reference's, not an estimation error";
  if (estimate_rms > kRefereeMargin * reference_rms)
    return ": the estimate is the one the sensors contradict: look at the estimator (a defect to find)";
  return fmt::format(
      ": both are as consistent with the sensors (within {:.0f} %){}, so this flight cannot say which is nearer the truth",
      100.0 * (kRefereeMargin - 1.0),
      gap_rms <= kRefereeMargin * std::max(estimate_rms, reference_rms) ? " and the gap is within that check's own scatter" : "");
}

std::optional<ReportNote> tilt_note(const RunTables& run, const char* axis, const ErrorFigure& gap, const ErrorFigure& est,
                                    const ErrorFigure& ref) {
  if (!(gap.rms > kAttitudeGapNote) || est.samples == 0 || ref.samples == 0) return std::nullopt;
  std::string text = fmt::format(
      "{} is {:.1f} deg RMS from the reference's; against the specific force (accelerometer vs GNSS acceleration - g, the yaw solved "
      "per epoch, neither's own: {} epochs where the {} is observable) the reference's {} needs {:.1f} deg RMS (mean {:+.1f}), the "
      "estimate's {:.1f} (mean {:+.1f}){}",
      axis, gap.rms, ref.samples, axis, axis, ref.rms, ref.mean, est.rms, est.mean, verdict(est.rms, ref.rms, gap.rms));
  const double dt = imu_interval(run);
  if (dt > kSlowImuNote)
    text += fmt::format(
        "; the IMU is logged every {:.0f} ms ({:.0f} Hz): each sample is integrated over that whole interval, a coarse "
        "attitude for any estimator",
        dt * 1e3, 1.0 / dt);
  return ReportNote{{std::string("reference.") + axis}, text};
}

/// Yaw minus the GNSS course (deg) at each fix of the window at >= kMinCourseSpeed, the
/// estimate's and the reference's, and the fixes' ground speeds.
struct YawVsCourse {
  ErrorSum estimate, reference;
  std::vector<double> speed;
};

YawVsCourse yaw_vs_course(const RunTables& run, const ReplayReport& r) {
  YawVsCourse out;
  const CsvTable &s = run.state, &g = *run.gnss;
  const Series ref_psi(*run.reference, "psi");
  const FixTimes times = fix_times(run, r.counters, r.window);
  for (std::size_t k = 0; k < g.rows; ++k) {
    const double t = times.tov[k], vn = g.at("vel_n")[k], ve = g.at("vel_e")[k];
    if (!(g.at("fix_type")[k] >= 3.0) || t < r.window.start_s || t > r.window.end_s || !(std::hypot(vn, ve) >= kMinCourseSpeed)) continue;
    const auto b = bracket(s.at("time"), t, kMaxGap);
    if (!b || !(s.at("valid")[b->k] > 0.5)) continue;
    const double course = std::atan2(ve, vn);
    out.estimate.add(wrap_pi(lerp(s.at("psi"), *b, true) - course) * kDegPerRad);
    out.reference.add(wrap_pi(interpolate(ref_psi.t, ref_psi.v, t, kMaxGap, true) - course) * kDegPerRad);
    out.speed.push_back(std::hypot(vn, ve));
  }
  return out;
}

std::optional<ReportNote> yaw_note(const RunTables& run, const ReplayReport& r) {
  if (!(r.reference.yaw.rms > kYawGapNote) || !run.gnss) return std::nullopt;
  const YawVsCourse y = yaw_vs_course(run, r);
  const ErrorFigure est = y.estimate.figure("deg", ""), ref = y.reference.figure("deg", "");
  if (est.samples == 0 || ref.samples == 0) return std::nullopt;
  const double speed = median(y.speed);
  const double crab = std::isfinite(r.wind.mean_speed) ? std::asin(std::min(1.0, r.wind.mean_speed / speed)) * kDegPerRad : 0.0;
  std::string text = fmt::format(
      "yaw is {:.1f} deg RMS from the reference's; against the GNSS course ({} fixes at >= {:.0f} m/s in the window) the reference's yaw "
      "is {:.1f} deg RMS off (mean {:+.1f}), the estimate's {:.1f} (mean {:+.1f})",
      r.reference.yaw.rms, est.samples, kMinCourseSpeed, ref.rms, ref.mean, est.rms, est.mean);
  if (std::isfinite(r.wind.mean_speed))
    text += fmt::format(
        ", where the estimated wind ({:.1f} m/s mean at a median ground speed of {:.1f} m/s) accounts for about {:.0f} deg "
        "of crab",
        r.wind.mean_speed, speed, crab);
  if (ref.rms > kRefereeMargin * est.rms && ref.rms > crab)
    text += ": the reference's heading is the one off, not the estimate's";
  else if (est.rms > kRefereeMargin * ref.rms && est.rms > crab)
    text += ": the estimate's heading is the one off: look at the estimator (a defect to find)";
  else
    text += ": this flight cannot say which heading is nearer the truth";
  return ReportNote{{"reference.yaw"}, text};
}

}  // namespace

std::vector<ReportNote> attitude_notes(const RunTables& run, const ReplayReport& r) {
  std::vector<ReportNote> out;
  if (!r.reference.absent.empty()) return out;
  const auto& sf = r.specific_force;
  if (sf.absent.empty()) {
    if (auto n = tilt_note(run, "roll", r.reference.roll, sf.roll, sf.reference_roll)) out.push_back(std::move(*n));
    if (auto n = tilt_note(run, "pitch", r.reference.pitch, sf.pitch, sf.reference_pitch)) out.push_back(std::move(*n));
  }
  if (auto n = yaw_note(run, r)) out.push_back(std::move(*n));
  return out;
}

}  // namespace tern::core::replay_report
