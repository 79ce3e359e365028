// The phase machine's landing decisions. See landing_checks.hpp.
#include "safety/landing_checks.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace tern::core {

double height_above_touchdown(const msg::State& s, const msg::CurrentPath& path) { return path.r.z() - s.p_d; }

double along_touchdown(const msg::State& s, const msg::CurrentPath& path) {
  const double qn = std::hypot(path.q.x(), path.q.y());
  if (!(qn > 1e-9)) return 0.0;
  return ((s.p_n - path.r.x()) * path.q.x() + (s.p_e - path.r.y()) * path.q.y()) / qn;
}

double runway_height(const msg::State& s, const msg::CurrentPath& path, const msg::Range* range, Nanos now) {
  const double h = range != nullptr ? range->height_at(now, s.phi, s.theta) : std::nan("");
  return std::isfinite(h) ? h : height_above_touchdown(s, path);
}

std::string unstabilised(const msg::State& s, const msg::CurrentPath& path, double Va_c, const LandingLimits& l) {
  const double qn = std::hypot(path.q.x(), path.q.y());
  if (!(qn > 1e-9)) return "the glide path has no horizontal direction";
  const double cn = path.q.x() / qn, ce = path.q.y() / qn;
  const double dn = s.p_n - path.r.x(), de = s.p_e - path.r.y();
  const double cross = -ce * dn + cn * de;
  const double along = std::min(cn * dn + ce * de, 0.0);
  const double glide_h = -path.r.z() - along * path.q.z() / qn;
  const double glide_err = -s.p_d - glide_h;
  if (std::fabs(cross) > l.max_cross_track) return fmt::format("cross-track {:.1f} m > {:.1f} m", cross, l.max_cross_track);
  if (std::fabs(glide_err) > l.max_glide_error)
    return fmt::format("{:.1f} m {} the glide path > {:.1f} m", std::fabs(glide_err), glide_err > 0 ? "above" : "below", l.max_glide_error);
  if (s.Va < Va_c - l.max_airspeed_deficit)
    return fmt::format("airspeed {:.1f} m/s < {:.1f} m/s (Va_c {:.1f} - {:.1f})", s.Va, Va_c - l.max_airspeed_deficit, Va_c,
                       l.max_airspeed_deficit);
  return "";
}

}  // namespace tern::core
