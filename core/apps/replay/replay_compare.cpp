// The replay report's comparisons: the estimate against the reference estimator (reference
// interpolated at the state's times) and against the raw GNSS fixes (the state interpolated at
// each fix's time of validity), and the wind estimate. One frame: the estimate's NED about
// state.csv's origin, the comparator's lat/lon/alt converted with tern::GeoOrigin.
#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "replay/replay_report_parts.hpp"

namespace tern::core::replay_report {

namespace {

/// The reference's fields, each interpolated between its own samples.
struct ReferenceColumns {
  Series phi, theta, psi, lat, lon, alt, v_n, v_e, v_d, w_n, w_e;
  explicit ReferenceColumns(const CsvTable& r)
      : phi(r, "phi"),
        theta(r, "theta"),
        psi(r, "psi"),
        lat(r, "lat"),
        lon(r, "lon"),
        alt(r, "alt"),
        v_n(r, "v_n"),
        v_e(r, "v_e"),
        v_d(r, "v_d"),
        w_n(r, "w_n"),
        w_e(r, "w_e") {}
  static double at(const Series& s, double tq, bool angle = false) { return interpolate(s.t, s.v, tq, kMaxGap, angle); }
};

struct ReferenceSums {
  ErrorSum roll, pitch, yaw, course, pos_h, pos_v, vel_h, vel_v;
};

void add_reference_sample(const CsvTable& s, const ReferenceColumns& ref, std::size_t k, OriginCache& origins, ReferenceSums& e) {
  const double t = s.at("time")[k];
  e.roll.add(wrap_pi(s.at("phi")[k] - ref.at(ref.phi, t, true)) * kDegPerRad);
  e.pitch.add(wrap_pi(s.at("theta")[k] - ref.at(ref.theta, t, true)) * kDegPerRad);
  e.yaw.add(wrap_pi(s.at("psi")[k] - ref.at(ref.psi, t, true)) * kDegPerRad);
  const double vn = ref.at(ref.v_n, t), ve = ref.at(ref.v_e, t), vd = ref.at(ref.v_d, t);
  const double svn = s.at("v_n")[k], sve = s.at("v_e")[k];
  if (std::hypot(vn, ve) >= kMinCourseSpeed) e.course.add(wrap_pi(std::atan2(sve, svn) - std::atan2(ve, vn)) * kDegPerRad);
  e.vel_h.add(std::hypot(svn - vn, sve - ve));
  e.vel_v.add(s.at("v_d")[k] - vd);
  const double lat = ref.at(ref.lat, t), lon = ref.at(ref.lon, t), alt = ref.at(ref.alt, t);
  const GeoOrigin* o = origins.at(k);
  if (o != nullptr && std::isfinite(lat) && std::isfinite(lon) && std::isfinite(alt)) {
    const Eigen::Vector3d p = o->to_ned(lat, lon, alt);
    e.pos_h.add(std::hypot(s.at("p_n")[k] - p.x(), s.at("p_e")[k] - p.y()));
    e.pos_v.add(s.at("p_d")[k] - p.z());
  }
}

}  // namespace

ReferenceComparison compare_reference(const RunTables& run, const ReplayWindow& w) {
  ReferenceComparison c;
  if (!run.reference) {
    c.absent = "absent (no topics/reference.csv)";
    return c;
  }
  const CsvTable& s = run.state;
  const auto [first, last] = index_range(s.at("time"), w.start_s, w.end_s);
  OriginCache origins(s);
  ReferenceSums e;
  const ReferenceColumns ref(*run.reference);
  for (std::size_t k = first; k < last; ++k)
    if (s.at("valid")[k] > 0.5) add_reference_sample(s, ref, k, origins, e);
  const std::string at = "valid state samples in the window, the reference interpolated linearly at their stamp (gaps <= 1 s)";
  c.roll = e.roll.figure("deg", "roll: " + at);
  c.pitch = e.pitch.figure("deg", "pitch: " + at);
  c.yaw = e.yaw.figure("deg", "yaw: " + at + ", wrapped");
  c.course = e.course.figure("deg", "course atan2(v_e, v_n): " + at + ", where the reference's horizontal speed >= 5 m/s");
  c.position_h = e.pos_h.figure("m", "horizontal position: " + at + ", reference lat/lon/alt in the estimate's NED (state origin)");
  c.position_v = e.pos_v.figure("m", "down position: " + at + ", reference alt in the estimate's NED (state origin)");
  c.velocity_h = e.vel_h.figure("m/s", "horizontal velocity |(dv_n, dv_e)|: " + at);
  c.velocity_v = e.vel_v.figure("m/s", "down velocity: " + at);
  return c;
}

WindReport wind_report(const RunTables& run, const ReplayWindow& w) {
  WindReport r;
  const CsvTable& s = run.state;
  if (!s.has("w_n") || !s.has("w_e")) {
    r.absent = "absent (state.csv has no w_n, w_e)";
    return r;
  }
  const auto [first, last] = index_range(s.at("time"), w.start_s, w.end_s);
  const auto &wn = s.at("w_n"), &we = s.at("w_e"), &valid = s.at("valid"), &t = s.at("time");
  std::optional<ReferenceColumns> ref;
  if (run.reference) ref.emplace(*run.reference);
  if (ref && (ref->w_n.t.empty() || ref->w_e.t.empty())) ref.reset();  // no wind in it
  double sum = 0.0, max = 0.0;
  ErrorSum e;
  for (std::size_t k = first; k < last; ++k) {
    const double speed = std::hypot(wn[k], we[k]);
    if (!(valid[k] > 0.5) || std::isnan(speed)) continue;
    sum += speed;
    max = std::max(max, speed);
    ++r.samples;
    if (ref) e.add(std::hypot(wn[k] - ReferenceColumns::at(ref->w_n, t[k]), we[k] - ReferenceColumns::at(ref->w_e, t[k])));
  }
  if (r.samples > 0) {
    r.mean_speed = sum / static_cast<double>(r.samples);
    r.max_speed = max;
  }
  r.vs_reference =
      ref ? e.figure("m/s", "|(w_n, w_e) - reference|: valid state samples in the window, the reference interpolated at their stamp")
          : e.figure("m/s", "absent (no wind in topics/reference.csv)");
  return r;
}

}  // namespace tern::core::replay_report
