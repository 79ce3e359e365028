// linearize.cpp: uavbook ch. 5 linear models about a trim (see tern/aero/linear_model.hpp).
#include "tern/aero/linear_model.hpp"

#include <algorithm>
#include <cmath>

#include "tern/aero/model.hpp"
#include "tern/math.hpp"

namespace tern::aero {

LinearModel linearize(const tern::Aircraft& ac, const sim::TrimRequest& req) {
  LinearModel lm;
  lm.Va = req.Va;
  lm.trim = sim::compute_trim(ac, req);
  const sim::TrimResult& tr = lm.trim;
  const sim::StateVector& xs = tr.x;
  const double phi0 = tr.phi, theta0 = tr.theta, psi0 = req.psi, h0 = -xs[sim::PD];
  const sim::Wind calm;
  // full reduced state z = [u v w p q r phi theta psi h], inputs [de da dr dt]
  using Z = Eigen::Matrix<double, 10, 1>;
  using In = Eigen::Vector4d;
  Z z0;
  z0 << xs[sim::U], xs[sim::V], xs[sim::W], xs[sim::P], xs[sim::Q], xs[sim::R], phi0, theta0, psi0, h0;
  const In in0(tr.delta.delta_e, tr.delta.delta_a, tr.delta.delta_r, tr.delta.delta_t);
  auto f = [&](const Z& z, const In& in) {
    const sim::StateVector x = sim::make_state({0, 0, -z[9]}, {z[0], z[1], z[2]}, z[6], z[7], z[8], {z[3], z[4], z[5]});
    sim::Deltas d;
    d.delta_e = in[0];
    d.delta_a = in[1];
    d.delta_r = in[2];
    d.delta_t = in[3];
    const sim::StateVector dx = sim::derivative(ac, x, d, calm);
    const double sp = std::sin(z[6]), cp = std::cos(z[6]), tt = std::tan(z[7]), ct = std::cos(z[7]);
    Z dz;
    dz << dx[sim::U], dx[sim::V], dx[sim::W], dx[sim::P], dx[sim::Q], dx[sim::R],
        z[3] + z[4] * sp * tt + z[5] * cp * tt,  // book eq. 3.3
        z[4] * cp - z[5] * sp, (z[4] * sp + z[5] * cp) / ct, -dx[sim::PD];
    return dz;
  };
  Eigen::Matrix<double, 10, 10> A;
  Eigen::Matrix<double, 10, 4> B;
  for (int j = 0; j < 10; ++j) {
    const double h = 1e-5 * std::max(1.0, std::abs(z0[j]));
    Z zp = z0, zm = z0;
    zp[j] += h;
    zm[j] -= h;
    A.col(j) = (f(zp, in0) - f(zm, in0)) / (2 * h);
  }
  for (int j = 0; j < 4; ++j) {
    const double h = 1e-6;
    In ip = in0, im = in0;
    ip[j] += h;
    im[j] -= h;
    B.col(j) = (f(z0, ip) - f(z0, im)) / (2 * h);
  }
  const int lon[5] = {0, 2, 4, 7, 9}, lat[5] = {1, 3, 5, 6, 8};
  const int ulon[2] = {0, 3}, ulat[2] = {1, 2};
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      lm.A_lon(i, j) = A(lon[i], lon[j]);
      lm.A_lat(i, j) = A(lat[i], lat[j]);
    }
    for (int j = 0; j < 2; ++j) {
      lm.B_lon(i, j) = B(lon[i], ulon[j]);
      lm.B_lat(i, j) = B(lat[i], ulat[j]);
    }
  }
  // transfer-function coefficients (book sec. 5.4, a_V1/a_V2 with the propeller model)
  const auto& a = ac.aero;
  const double Va = req.Va, rho = ac.rho, S = ac.S, b = ac.b, c = ac.c, m = ac.mass;
  const double Gam = ac.Jx * ac.Jz - ac.Jxz * ac.Jxz;
  const double G3 = ac.Jz / Gam, G4 = ac.Jxz / Gam;
  const double Cpp = G3 * a.C_ell_p + G4 * a.C_n_p;
  const double Cpda = G3 * a.C_ell_delta_a + G4 * a.C_n_delta_a;
  auto& k = lm.tf;
  k["a_phi1"] = -0.5 * rho * Va * Va * S * b * Cpp * b / (2 * Va);
  k["a_phi2"] = 0.5 * rho * Va * Va * S * b * Cpda;
  const double qc = rho * Va * Va * c * S / (2 * ac.Jy);
  k["a_theta1"] = -qc * a.C_m_q * c / (2 * Va);
  k["a_theta2"] = -qc * a.C_m_alpha;
  k["a_theta3"] = qc * a.C_m_delta_e;
  const double dt = tr.delta.delta_t, hv = 1e-4;
  const double dT_dVa = (sim::propulsion(ac, Va + hv, dt).T_p - sim::propulsion(ac, Va - hv, dt).T_p) / (2 * hv);
  const double dT_ddt = (sim::propulsion(ac, Va, dt + hv).T_p - sim::propulsion(ac, Va, dt - hv).T_p) / (2 * hv);
  k["a_V1"] = rho * Va * S / m * (sim::drag_coefficient(ac, tr.alpha) + a.C_D_delta_e * tr.delta.delta_e) - dT_dVa / m;
  k["a_V2"] = dT_ddt / m;
  k["a_V3"] = tern::kGravity * std::cos(tr.theta - tr.alpha);
  k["a_beta1"] = -rho * Va * S / (2 * m) * a.C_Y_beta;
  k["a_beta2"] = rho * Va * S / (2 * m) * a.C_Y_delta_r;
  return lm;
}

}  // namespace tern::aero
