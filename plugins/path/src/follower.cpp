// Vector-field path following, Beard & McLain, ch. 10. See follower.hpp.
#include "tern/path/follower.hpp"

#include <algorithm>
#include <cmath>

#include "tern/math.hpp"

namespace tern::path {

using tern::kPi;
using tern::unwrap_near;

double cross_track_error(const Vec3& r, const Vec3& q, const Vec3& p) {
  const double chi_q = std::atan2(q.y(), q.x());
  return -std::sin(chi_q) * (p.x() - r.x()) + std::cos(chi_q) * (p.y() - r.y());
}

FollowerCommand follow(const PathSegment& path, const FollowerInput& in, const FollowerGains& g) {
  FollowerCommand out;
  out.Va_c = path.Va_d;
  const double chi = std::isfinite(in.chi) ? in.chi : 0.0;
  if (path.type == PathSegment::Type::line) {
    const double q_ne = std::hypot(path.q.x(), path.q.y());
    if (!(q_ne > 1e-9)) {
      out.chi_c = chi;
      out.h_c = -path.r.z();
      return out;
    }
    const double chi_q = unwrap_near(std::atan2(path.q.y(), path.q.x()), chi);
    const Vec3 e_p = in.p - path.r;
    const double e_py = -std::sin(chi_q) * e_p.x() + std::cos(chi_q) * e_p.y();
    out.chi_c = chi_q - g.chi_inf * (2.0 / kPi) * std::atan(g.k_path * e_py);
    // Altitude along the line (eq. 10.5): the part of e_p in the vertical plane containing q.
    const double qn = path.q.x() / q_ne, qe = path.q.y() / q_ne;
    const double along = e_p.x() * qn + e_p.y() * qe;  // = |s_ne| signed along the line
    out.h_c = -path.r.z() - along * path.q.z() / q_ne;
    if (path.landing) {
      out.landing = true;
      out.h_td = -path.r.z();
      out.h_c = std::max(out.h_c, out.h_td);
    }
    out.phi_ff = 0.0;
    out.chi_c = unwrap_near(out.chi_c, chi);
    return out;
  }
  // Orbit (Alg. 4).
  const double rho = path.rho > 0.0 ? path.rho : 1.0;
  const double dn = in.p.x() - path.c.x(), de = in.p.y() - path.c.y();
  const double d = std::hypot(dn, de);
  const double varphi = unwrap_near(d > 1e-9 ? std::atan2(de, dn) : chi - path.lambda * kPi / 2.0, chi);
  const double lam = path.lambda >= 0 ? 1.0 : -1.0;
  out.chi_c = varphi + lam * (kPi / 2.0 + std::atan(g.k_orbit * (d - rho) / rho));
  out.h_c = -path.c.z();
  if (std::fabs(d - rho) < 0.5 * rho) {
    const double V = (std::isfinite(in.Vg) && in.Vg > 0.0) ? in.Vg : (std::isfinite(in.Va) ? in.Va : 0.0);
    const double crab = std::isfinite(in.psi) ? std::cos(chi - in.psi) : 1.0;
    out.phi_ff = lam * std::atan(V * V / (g.gravity * rho * std::max(crab, 0.5)));
  }
  // Keep chi_c within pi of chi (the course loop's error is then chi_c - chi).
  out.chi_c = unwrap_near(out.chi_c, chi);
  return out;
}

}  // namespace tern::path
