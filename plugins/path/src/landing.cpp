// The straight-in approach of a land item. See tern/path/landing.hpp.
#include "tern/path/landing.hpp"

#include <algorithm>
#include <cmath>

namespace tern::path {

Approach plan_approach(const Vec3& touchdown, double heading, const LandSpec& spec, double entry_d) {
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
  a.entry = touchdown - a.length * h_dir;
  a.entry.z() = touchdown.z() - height;
  a.q = Vec3(h_dir.x(), h_dir.y(), t).normalized();
  return a;
}

double along_runway(const Approach& a, const Vec3& p) {
  return (p.x() - a.touchdown.x()) * std::cos(a.heading) + (p.y() - a.touchdown.y()) * std::sin(a.heading);
}

double glide_path_altitude(const Approach& a, const Vec3& p) {
  const double s = std::clamp(along_runway(a, p), -a.length, 0.0);
  return -a.touchdown.z() - s * a.q.z() / std::hypot(a.q.x(), a.q.y());
}

}  // namespace tern::path
