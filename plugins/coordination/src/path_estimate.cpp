// Turn-then-line path length and the wind triangle; see tern/coordination/path_estimate.hpp.
#include "tern/coordination/path_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tern/math.hpp"

namespace tern::coord {

namespace {
/// Length of the path turning in direction `turn` (+1 right/clockwise, -1 left) then straight,
/// or infinity when the target is inside that turn circle.
double one_side(const Vec2& p, double chi, const Vec2& target, double R, int turn) {
  const Vec2 right(-std::sin(chi), std::cos(chi));
  const Vec2 c = p + turn * R * right;
  const Vec2 v = target - c;
  const double D = v.norm();
  if (D < R) return std::numeric_limits<double>::infinity();
  const double tangent = std::sqrt(D * D - R * R);
  // the course that leaves the circle tangentially towards the target
  const double chi_exit = std::atan2(v.y(), v.x()) + turn * std::asin(R / D);
  double arc = wrap_2pi(turn * (chi_exit - chi));
  if (arc > 2.0 * kPi - 1e-9) arc = 0.0;  // straight ahead, rounded to just under a full turn
  return R * arc + tangent;
}
}  // namespace

double turn_then_line_length(const Vec2& p, double chi, const Vec2& target, double R) {
  if ((target - p).norm() < 1e-9) return 0.0;
  return std::min(one_side(p, chi, target, R, 1), one_side(p, chi, target, R, -1));
}

double ground_speed(double Va, const Vec2& w, const Vec2& q, double floor) {
  const double wq = w.dot(q);
  const double disc = Va * Va - w.squaredNorm() + wq * wq;
  if (!(disc >= 0.0)) return std::isfinite(disc) ? floor : disc;
  return std::max(wq + std::sqrt(disc), floor);
}

double airspeed_for(double Vg, const Vec2& w, const Vec2& q) { return (Vg * q - w).norm(); }

Vec2 direction_to(const Vec2& p, const Vec2& target, double chi) {
  const Vec2 d = target - p;
  const double n = d.norm();
  if (n < 1e-9) return {std::cos(chi), std::sin(chi)};
  return d / n;
}

}  // namespace tern::coord
