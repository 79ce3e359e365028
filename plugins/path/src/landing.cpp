// The straight-in approach of a land item. See tern/path/landing.hpp.
#include "tern/path/landing.hpp"

#include <algorithm>
#include <cmath>

namespace tern::path {

Approach plan_approach(const Vec3& touchdown, double heading, const LandSpec& spec, double entry_d, double aim_offset) {
  Approach a;
  a.touchdown = touchdown;
  a.heading = heading;
  const double min_height = kMinEntryHeights * spec.decision_height;
  double height = touchdown.z() - entry_d;  // entry altitude above the touchdown point
  if (height < min_height) {
    height = min_height;
    a.raised = true;
  }
  const double t = std::tan(spec.glide_slope);
  a.length = height / t;
  const Vec3 h_dir(std::cos(heading), std::sin(heading), 0.0);
  a.aim_offset = std::clamp(aim_offset, -0.5 * a.length, 0.5 * a.length);
  a.aim = touchdown - a.aim_offset * h_dir;
  a.entry = a.aim - a.length * h_dir;
  a.entry.z() = touchdown.z() - height;
  a.q = Vec3(h_dir.x(), h_dir.y(), t).normalized();
  return a;
}

double runway_ground_speed(double Va, const Vec3& wind, double heading) {
  const double along = wind.x() * std::cos(heading) + wind.y() * std::sin(heading);
  const double cross = -wind.x() * std::sin(heading) + wind.y() * std::cos(heading);
  if (std::fabs(cross) >= Va) return 0.0;
  return std::max(std::sqrt(Va * Va - cross * cross) + along, 0.0);
}

double aim_offset(double Vg, double flare_time, const LandSpec& spec) {
  if (flare_time <= 0.0) return 0.0;
  return std::max(Vg, 0.0) * flare_time - spec.flare_height / std::tan(spec.glide_slope);
}

double along_runway(const Approach& a, const Vec3& p) {
  return (p.x() - a.touchdown.x()) * std::cos(a.heading) + (p.y() - a.touchdown.y()) * std::sin(a.heading);
}

double glide_path_altitude(const Approach& a, const Vec3& p) {
  const double s = std::clamp(along_runway(a, p) + a.aim_offset, -a.length, 0.0);
  return -a.touchdown.z() - s * a.q.z() / std::hypot(a.q.x(), a.q.y());
}

}  // namespace tern::path
