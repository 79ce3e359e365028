// Path geometry, Beard & McLain, *Small Unmanned Aircraft*, ch. 11. See geometry.hpp.
#include "tern/path/geometry.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "tern/math.hpp"

namespace tern::path {

namespace {
using tern::kPi;
constexpr double kInf = std::numeric_limits<double>::infinity();

bool finite(const Vec3& v) { return v.allFinite(); }

Vec3 horizontal_unit(const Vec3& from, const Vec3& to, const char* what) {
  Vec3 d(to.x() - from.x(), to.y() - from.y(), 0.0);
  const double n = d.norm();
  if (!(n > 1e-9)) throw std::invalid_argument(std::string("path geometry: ") + what + " has zero horizontal length");
  return d / n;
}

/// Horizontal angle of a vector, atan2(e, n).
double angle_of(const Vec3& v) { return std::atan2(v.y(), v.x()); }

/// Turn angle for the Dubins arcs: mod 2 pi, with a full turn within roundoff counted as 0.
double arc(double x) {
  const double a = tern::wrap_2pi(x);
  return a > 2.0 * kPi - 1e-9 ? 0.0 : a;
}

/// Point at distance R from centre c in direction of course angle a (d of c).
Vec3 on_circle(const Vec3& c, double R, double a) { return {c.x() + R * std::cos(a), c.y() + R * std::sin(a), c.z()}; }
}  // namespace

bool in_half_plane(const Vec3& p, const Vec3& z, const Vec3& n) { return (p.x() - z.x()) * n.x() + (p.y() - z.y()) * n.y() >= 0.0; }

Vec3 line_switch_normal(const Vec3& q_in, const Vec3& q_out) {
  Vec3 s(q_in.x() + q_out.x(), q_in.y() + q_out.y(), 0.0);
  const double n = s.norm();
  if (n < 1e-6) return Vec3(q_in.x(), q_in.y(), 0.0).normalized();
  return s / n;
}

Fillet compute_fillet(const Vec3& w_prev, const Vec3& w, const Vec3& w_next, double R) {
  if (!(R > 0.0) || !std::isfinite(R)) throw std::invalid_argument("fillet: radius R must be > 0, got " + std::to_string(R));
  if (!finite(w_prev) || !finite(w) || !finite(w_next)) throw std::invalid_argument("fillet: waypoint is not finite");
  Fillet f;
  f.q_in = horizontal_unit(w_prev, w, "fillet: incoming leg");
  f.q_out = horizontal_unit(w, w_next, "fillet: outgoing leg");
  const double cos_v = std::clamp(-f.q_in.dot(f.q_out), -1.0, 1.0);
  f.varrho = std::acos(cos_v);
  const double turn = kPi - f.varrho;
  f.z1 = w;
  f.z2 = w;
  f.c = w;
  const double cross = f.q_in.x() * f.q_out.y() - f.q_in.y() * f.q_out.x();
  f.lambda = cross >= 0.0 ? 1 : -1;
  if (turn < kStraightTurn) {
    f.kind = Fillet::Kind::straight;
    return f;
  }
  const double half = f.varrho / 2.0;
  const double tan_half = std::tan(half);
  const double L_in = horizontal_distance(w_prev, w), L_out = horizontal_distance(w, w_next);
  f.offset = tan_half > 0.0 ? R / tan_half : kInf;
  if (!(f.offset <= std::min(L_in, L_out))) {
    f.kind = Fillet::Kind::too_sharp;
    return f;
  }
  f.kind = Fillet::Kind::fillet;
  Vec3 n = f.q_in - f.q_out;
  n.z() = 0.0;
  n.normalize();
  f.c = w - (R / std::sin(half)) * n;
  f.c.z() = w.z();
  f.z1 = w - f.offset * f.q_in;
  f.z1.z() = w.z();
  f.z2 = w + f.offset * f.q_out;
  f.z2.z() = w.z();
  return f;
}

double wind_turn_radius(double Va, const Vec3& wind, double chi0, double sweep, double phi, double g) {
  if (!(Va > 0.0) || !std::isfinite(Va) || !wind.head<2>().allFinite() || !std::isfinite(chi0) || !std::isfinite(sweep) || !(phi > 0.0) ||
      !(phi < kPi / 2.0) || !(g > 0.0))
    return 0.0;
  const double span = std::min(std::fabs(sweep), 2.0 * kPi);
  const int n = std::max(2, static_cast<int>(std::ceil(span / (kPi / 90.0))) + 1);  // every 2 deg or finer
  const double dir = sweep >= 0.0 ? 1.0 : -1.0;
  double R = 0.0;
  // the samples, and the downwind course when the turn sweeps it (where the radius peaks)
  const bool windy = wind.head<2>().norm() > 0.0;
  const double downwind = windy ? tern::wrap_2pi(dir * (std::atan2(wind.y(), wind.x()) - chi0)) : 0.0;
  for (int i = 0; i <= n; ++i) {
    if (i == n && !(windy && downwind <= span)) break;
    const double chi = i < n ? chi0 + dir * span * static_cast<double>(i) / static_cast<double>(n - 1) : chi0 + dir * downwind;
    const double c = std::cos(chi), s = std::sin(chi);
    const double w_along = wind.x() * c + wind.y() * s;
    const double w_cross = -wind.x() * s + wind.y() * c;
    const double sin_crab = std::clamp(w_cross / Va, -0.99, 0.99);
    const double cos_crab = std::sqrt(1.0 - sin_crab * sin_crab);
    const double Vg = w_along + Va * cos_crab;
    if (!(Vg > 0.0)) continue;
    R = std::max(R, Vg * Vg / (g * std::tan(phi) * cos_crab));
  }
  return R;
}

std::string_view dubins_type_name(DubinsType t) {
  switch (t) {
    case DubinsType::RSR: return "RSR";
    case DubinsType::RSL: return "RSL";
    case DubinsType::LSR: return "LSR";
    case DubinsType::LSL: return "LSL";
  }
  return "?";
}

DubinsPath dubins_path(const Vec3& ps, double chi_s, const Vec3& pe, double chi_e, double R) {
  if (!(R > 0.0) || !std::isfinite(R)) throw std::invalid_argument("dubins: radius R must be > 0, got " + std::to_string(R));
  if (!finite(ps) || !finite(pe) || !std::isfinite(chi_s) || !std::isfinite(chi_e))
    throw std::invalid_argument("dubins: start or end configuration is not finite");
  DubinsPath P;
  P.R = R;
  P.ps = ps;
  P.pe = pe;
  P.chi_s = chi_s;
  P.chi_e = chi_e;
  P.close = horizontal_distance(ps, pe) < 2.0 * R;
  // Circle centres (Alg. 7): right of the course is course + pi/2 in NED.
  const Vec3 crs = on_circle(ps, R, chi_s + kPi / 2), cls = on_circle(ps, R, chi_s - kPi / 2);
  const Vec3 cre = on_circle(pe, R, chi_e + kPi / 2), cle = on_circle(pe, R, chi_e - kPi / 2);
  // A point of a clockwise circle where the course is psi lies at angle psi - pi/2 from the
  // centre; on a counter-clockwise circle at psi + pi/2. The straight segment's course psi:
  //   RSR, LSL: direction of ce - cs;  RSL: theta + asin(2R/l);  LSR: theta - asin(2R/l).
  std::array<double, 4> psi{};
  auto& L = P.lengths;
  {  // RSR
    const Vec3 d = cre - crs;
    const double l = d.head<2>().norm();
    psi[0] = l > 1e-9 ? angle_of(d) : chi_s;
    L[0] = R * arc(psi[0] - chi_s) + l + R * arc(chi_e - psi[0]);
  }
  {  // RSL
    const Vec3 d = cle - crs;
    const double l = d.head<2>().norm();
    if (l >= 2.0 * R) {
      psi[1] = angle_of(d) + std::asin(std::min(1.0, 2.0 * R / l));
      L[1] = R * arc(psi[1] - chi_s) + std::sqrt(std::max(0.0, l * l - 4.0 * R * R)) + R * arc(psi[1] - chi_e);
    } else {
      L[1] = kInf;
    }
  }
  {  // LSR
    const Vec3 d = cre - cls;
    const double l = d.head<2>().norm();
    if (l >= 2.0 * R) {
      psi[2] = angle_of(d) - std::asin(std::min(1.0, 2.0 * R / l));
      L[2] = R * arc(chi_s - psi[2]) + std::sqrt(std::max(0.0, l * l - 4.0 * R * R)) + R * arc(chi_e - psi[2]);
    } else {
      L[2] = kInf;
    }
  }
  {  // LSL
    const Vec3 d = cle - cls;
    const double l = d.head<2>().norm();
    psi[3] = l > 1e-9 ? angle_of(d) : chi_s;
    L[3] = R * arc(chi_s - psi[3]) + l + R * arc(psi[3] - chi_e);
  }
  int best = 0;
  for (int k = 1; k < 4; ++k)
    if (L[k] < L[best]) best = k;
  P.type = static_cast<DubinsType>(best);
  P.length = L[best];
  const bool right_s = best == 0 || best == 1, right_e = best == 0 || best == 2;
  P.cs = right_s ? crs : cls;
  P.ce = right_e ? cre : cle;
  P.lambda_s = right_s ? 1 : -1;
  P.lambda_e = right_e ? 1 : -1;
  P.q1 = course_vector(psi[best]);
  P.z1 = on_circle(P.cs, R, psi[best] + (right_s ? -kPi / 2 : kPi / 2));
  P.z2 = on_circle(P.ce, R, psi[best] + (right_e ? -kPi / 2 : kPi / 2));
  P.z3 = pe;
  P.q3 = course_vector(chi_e);
  P.arc_s = right_s ? arc(psi[best] - chi_s) : arc(chi_s - psi[best]);
  P.arc_e = right_e ? arc(chi_e - psi[best]) : arc(psi[best] - chi_e);
  return P;
}

}  // namespace tern::path
