// The replay report's GNSS comparison: the estimate interpolated at each fix's time of validity
// (the receiver's epoch `time_of_validity`, or stamp - the estimator's gnss_delay when it is 0),
// against the fix: horizontal position, horizontal velocity, course; and the share of fixes the
// estimator accepted (its own counters).
#include <cmath>

#include <fmt/format.h>

#include "replay/replay_report_parts.hpp"

namespace tern::core::replay_report {

namespace {

struct GnssSums {
  ErrorSum pos_h, vel_h, course;
};

/// The estimator's parameter prefix ("ekf.") from its counters, else "".
std::string param_prefix(const EstimatorCounters& c) { return c.instance.empty() ? "" : c.instance + "."; }

/// One fix at its time of validity tov (s) against the state there; false if the state is not
/// valid on both sides of tov (or not in one frame).
bool add_fix(const CsvTable& s, OriginCache& origins, double tov, double lat, double lon, double alt, double vn, double ve, GnssSums& e) {
  const auto b = bracket(s.at("time"), tov, kMaxGap);
  if (!b) return false;
  const std::size_t k1 = b->f == 0.0 ? b->k : b->k + 1;
  const auto& valid = s.at("valid");
  if (!(valid[b->k] > 0.5 && valid[k1] > 0.5) || !origins.same(b->k, k1)) return false;
  const double svn = lerp(s.at("v_n"), *b), sve = lerp(s.at("v_e"), *b);
  e.vel_h.add(std::hypot(svn - vn, sve - ve));
  if (std::hypot(vn, ve) >= kMinCourseSpeed) e.course.add(wrap_pi(std::atan2(sve, svn) - std::atan2(ve, vn)) * kDegPerRad);
  if (const GeoOrigin* o = origins.at(b->k); o != nullptr && origins.at(k1) != nullptr) {
    const Eigen::Vector3d p = o->to_ned(lat, lon, alt);
    e.pos_h.add(std::hypot(lerp(s.at("p_n"), *b) - p.x(), lerp(s.at("p_e"), *b) - p.y()));
  }
  return true;
}

double share_accepted(const EstimatorCounters& c, const std::string& model) {
  for (const auto& m : c.models)
    if (m.model == model && m.accepted + m.rejected > 0) return m.accepted / (m.accepted + m.rejected);
  return NAN;
}

}  // namespace

FixTimes fix_times(const RunTables& run, const EstimatorCounters& c, const ReplayWindow& w) {
  const CsvTable& f = *run.gnss;
  FixTimes out;
  out.param = param_prefix(c) + "gnss_delay";
  out.delay = run.params.number_at(out.param, w.start_s).value_or(0.0);
  const auto &stamp = f.at("stamp"), &tov_ns = f.at("time_of_validity");
  for (std::size_t k = 0; k < f.rows; ++k) {
    out.epoch.push_back(tov_ns[k] != 0.0);
    out.tov.push_back((out.epoch.back() ? tov_ns[k] : stamp[k] - std::round(out.delay * 1e9)) / 1e9);  // in ns, then s: exact
  }
  return out;
}

GnssComparison compare_gnss(const RunTables& run, const EstimatorCounters& c, const ReplayWindow& w) {
  GnssComparison g;
  if (!run.gnss) {
    g.absent = "absent (no topics/gnss.csv)";
    return g;
  }
  const CsvTable& f = *run.gnss;
  const double min_fix = run.params.number_at(param_prefix(c) + "min_gnss_fix_type", w.start_s).value_or(3.0);
  const auto& fix = f.at("fix_type");
  const FixTimes times = fix_times(run, c, w);
  OriginCache origins(run.state);
  GnssSums e;
  std::size_t from_epoch = 0, from_delay = 0;
  g.fixes = f.rows;
  for (std::size_t k = 0; k < f.rows; ++k) {
    const double tov = times.tov[k];
    if (!(fix[k] >= min_fix) || tov < w.start_s || tov > w.end_s) continue;
    ++g.fixes_in_window;
    if (!add_fix(run.state, origins, tov, f.at("lat")[k], f.at("lon")[k], f.at("alt")[k], f.at("vel_n")[k], f.at("vel_e")[k], e)) continue;
    (times.epoch[k] ? from_epoch : from_delay)++;
  }
  g.time_rule = fmt::format("time_of_validity where non-zero ({} fixes), else stamp - {} {} s ({} fixes)", from_epoch, times.param,
                            times.delay, from_delay);
  const std::string at = fmt::format(
      "fixes (fix_type >= {}) with their time of validity in the window, the valid state interpolated there (at its stamp)", min_fix);
  g.position_h = e.pos_h.figure("m", "horizontal position, fix lat/lon in the estimate's NED (state origin): " + at);
  g.velocity_h = e.vel_h.figure("m/s", "horizontal velocity |(dv_n, dv_e)|: " + at);
  g.course = e.course.figure("deg", "course atan2(v_e, v_n): " + at + ", where the fix's horizontal speed >= 5 m/s");
  g.share_pos_accepted = share_accepted(c, "gnss_pos");
  g.share_vel_accepted = share_accepted(c, "gnss_vel");
  return g;
}

}  // namespace tern::core::replay_report
