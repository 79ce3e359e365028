#include "vector_field.hpp"

#include <cmath>
#include <limits>
#include "tern/math.hpp"

namespace tern_@NAME@ {
using tern::kPi;
using tern::kGravity;
using tern::unwrap_near;  // angle a shifted by a multiple of 2 pi to within pi of ref (sec. 10.2)

double cross_track_error(const Eigen::Vector3d& r, const Eigen::Vector3d& q, const Eigen::Vector3d& p) {
  const double chi_q = std::atan2(q.y(), q.x());
  return -std::sin(chi_q) * (p.x() - r.x()) + std::cos(chi_q) * (p.y() - r.y());
}

Guidance follow_line(const Eigen::Vector3d& r, const Eigen::Vector3d& q, const Eigen::Vector3d& p,
                     double chi, const FollowerGains& g) {
  const double q_h = std::hypot(q.x(), q.y());
  if (!(q_h > 0.0) || !q.allFinite() || !r.allFinite() || !p.allFinite() || !std::isfinite(chi)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan, 0.0};
  }
  const double chi_q = unwrap_near(std::atan2(q.y(), q.x()), chi);
  const double e_py = cross_track_error(r, q, p);
  Guidance out;
  out.chi_c = chi_q - g.chi_inf * 2.0 / kPi * std::atan(g.k_path * e_py);
  // eq. 10.5: the path error projected onto the vertical plane that holds the line
  const Eigen::Vector3d e_p = p - r;
  const Eigen::Vector3d n = Eigen::Vector3d(q.y(), -q.x(), 0.0) / q_h;  // q x k, normalised
  const Eigen::Vector3d s = e_p - e_p.dot(n) * n;
  out.h_c = -r.z() - std::hypot(s.x(), s.y()) * q.z() / q_h;
  return out;
}

Guidance follow_orbit(const Eigen::Vector3d& c, double rho, int lambda, const Eigen::Vector3d& p,
                      double chi, double Va, const FollowerGains& g) {
  const double sign = lambda >= 0 ? 1.0 : -1.0;
  const double d = std::hypot(p.x() - c.x(), p.y() - c.y());
  const double varphi = unwrap_near(std::atan2(p.y() - c.y(), p.x() - c.x()), chi);
  Guidance out;
  out.chi_c = varphi + sign * (kPi / 2.0 + std::atan(g.k_orbit * (d - rho) / rho));
  out.h_c = -c.z();
  if (std::fabs(d - rho) < rho) out.phi_ff = sign * std::atan(Va * Va / (kGravity * rho));
  return out;
}

}  // namespace tern_@NAME@
