// core/apps/sysid/aero_samples.cpp: forces and moments as coefficients (aero_samples.hpp).
#include "sysid/aero_samples.hpp"

#include <algorithm>
#include <cmath>

#include "tern/aero/model.hpp"

namespace tern::core::sysid {

namespace {

std::vector<std::size_t> airborne(const FlightSeries& s, const AirborneFilter& f) {
  const std::vector<unsigned char> up = airborne_mask(s, f.ground).up;
  std::vector<double> va;
  for (std::size_t k = 0; k < s.size(); ++k)
    if (up[k] && std::isfinite(s.Va[k])) va.push_back(s.Va[k]);
  const double min_Va = f.min_Va_ratio * median(va);
  std::vector<std::size_t> keep;
  for (std::size_t k = 0; k < s.size(); ++k)
    if (up[k] && s.Va[k] > min_Va && std::abs(s.alpha[k]) < f.max_flow_angle && std::abs(s.beta[k]) < f.max_flow_angle) keep.push_back(k);
  return keep;
}

}  // namespace

AeroSamples aero_samples(const FlightSeries& s, const Aircraft& ac, const AirborneFilter& filter, double pitot_scale) {
  AeroSamples a;
  for (const std::size_t k : airborne(s, filter)) {
    const double qbar = std::isfinite(s.qbar[k]) ? pitot_scale * pitot_scale * s.qbar[k] : 0.5 * ac.rho * s.Va[k] * s.Va[k];
    const double Va = std::sqrt(2.0 * std::max(qbar, 0.0) / ac.rho), alpha = s.alpha[k], beta = s.beta[k];
    const double V_xz = Va * std::cos(beta);
    const double qS = qbar * ac.S, qS_xz = qS * std::cos(beta) * std::cos(beta);
    const sim::PropulsionOutput prop = sim::propulsion(ac, V_xz, s.delta_t[k]);
    const double Fx = ac.mass * s.a_x[k] - prop.T_p, Fy = ac.mass * s.a_y[k], Fz = ac.mass * s.a_z[k];
    const double p = s.p[k], q = s.q[k], r = s.r[k];
    const double l = ac.Jx * s.p_dot[k] - ac.Jxz * s.r_dot[k] + (ac.Jz - ac.Jy) * q * r - ac.Jxz * p * q + prop.Q_p;
    const double m = ac.Jy * s.q_dot[k] + (ac.Jx - ac.Jz) * p * r + ac.Jxz * (p * p - r * r);
    const double n = ac.Jz * s.r_dot[k] - ac.Jxz * s.p_dot[k] + (ac.Jy - ac.Jx) * p * q + ac.Jxz * q * r;
    a.t.push_back(s.t[k]);
    a.C_L.push_back((std::sin(alpha) * Fx - std::cos(alpha) * Fz) / qS_xz);
    a.C_D.push_back(-(std::cos(alpha) * Fx + std::sin(alpha) * Fz) / qS_xz);
    a.C_X.push_back(Fx / qS_xz), a.C_Z.push_back(Fz / qS_xz);
    a.C_Y.push_back(Fy / qS);
    a.C_ell.push_back(l / (qS * ac.b));
    a.C_ell_prop.push_back(prop.Q_p / (qS * ac.b));
    a.C_m.push_back(m / (qS_xz * ac.c));
    a.C_n.push_back(n / (qS * ac.b));
    a.alpha.push_back(alpha), a.beta.push_back(beta);
    a.p_hat.push_back(ac.b * p / (2.0 * Va)), a.q_hat.push_back(ac.c * q / (2.0 * V_xz)), a.r_hat.push_back(ac.b * r / (2.0 * Va));
    a.delta_a.push_back(s.delta_a[k]), a.delta_e.push_back(s.delta_e[k]), a.delta_r.push_back(s.delta_r[k]);
    a.delta_t.push_back(s.delta_t[k]);
    if (!s.exc_delta_a.empty()) {
      a.exc_delta_a.push_back(s.exc_delta_a[k]), a.exc_delta_e.push_back(s.exc_delta_e[k]);
      a.exc_delta_r.push_back(s.exc_delta_r[k]), a.exc_delta_t.push_back(s.exc_delta_t[k]);
    }
    a.Va.push_back(Va), a.p.push_back(p), a.q.push_back(q), a.r.push_back(r);
    a.source.push_back(k);
  }
  return a;
}

}  // namespace tern::core::sysid
