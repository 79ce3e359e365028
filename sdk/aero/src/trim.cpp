// Trim by Newton's method on the uavbook model (see trim.hpp).
#include "tern/aero/trim.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>
#include "tern/math.hpp"

namespace tern::sim {
namespace {

using Vec7 = Eigen::Matrix<double, 7, 1>;

/// Whether the rudder moves nothing (a flying wing's file: its three rudder derivatives 0).
bool rudderless(const Aircraft& ac) { return ac.aero.C_Y_delta_r == 0.0 && ac.aero.C_ell_delta_r == 0.0 && ac.aero.C_n_delta_r == 0.0; }

struct Problem {
  const Aircraft& ac;
  TrimRequest req;
  double psi_dot;
  bool beta_free;  ///< z[5] is beta (the rudder held at 0), else delta_r (beta 0)

  double beta(const Vec7& z) const { return beta_free ? z[5] : 0.0; }
  StateVector state(const Vec7& z) const {
    const double alpha = z[0], phi = z[1], theta = z[2], b = beta(z);
    const Eigen::Vector3d v(req.Va * std::cos(alpha) * std::cos(b), req.Va * std::sin(b), req.Va * std::sin(alpha) * std::cos(b));
    const Eigen::Vector3d pqr(-psi_dot * std::sin(theta), psi_dot * std::sin(phi) * std::cos(theta),
                              psi_dot * std::cos(phi) * std::cos(theta));
    return make_state(Eigen::Vector3d(0, 0, -req.altitude), v, phi, theta, req.psi, pqr);
  }
  Deltas deltas(const Vec7& z) const {
    Deltas d;
    d.delta_e = z[3];
    d.delta_a = z[4];
    d.delta_r = beta_free ? 0.0 : z[5];
    d.delta_t = z[6];
    return d;
  }
  Vec7 residual(const Vec7& z) const {
    const StateVector x = state(z);
    const StateVector dx = derivative(ac, x, deltas(z), Wind{});
    Vec7 r;
    r << dx[U], dx[V], dx[W], dx[P], dx[Q], dx[R], -dx[PD] - req.Va * std::sin(req.gamma);
    return r;
  }
};

std::string describe(const TrimRequest& r) {
  std::ostringstream s;
  s << "trim at Va = " << r.Va << " m/s, gamma = " << r.gamma << " rad, R = " << r.R << " m";
  return s.str();
}

}  // namespace

TrimResult compute_trim(const Aircraft& ac, const TrimRequest& req) {
  const std::string what = describe(req);
  if (!(req.Va > 0) || !std::isfinite(req.Va)) throw std::runtime_error(what + ": Va must be > 0");
  if (!std::isfinite(req.gamma) || std::fabs(req.gamma) >= 1.5) throw std::runtime_error(what + ": |gamma| must be < 1.5 rad");
  if (std::isnan(req.R) || std::fabs(req.R) < 1.0) throw std::runtime_error(what + ": |R| must be >= 1 m (inf for straight flight)");
  if (!std::isfinite(req.altitude) || !std::isfinite(req.psi)) throw std::runtime_error(what + ": altitude and psi must be finite");
  Problem pb{ac, req, std::isinf(req.R) ? 0.0 : req.Va * std::cos(req.gamma) / req.R, rudderless(ac)};

  // Initial guess: lift = weight, pitch-moment balance, coordinated bank.
  const double qS = 0.5 * ac.rho * req.Va * req.Va * ac.S;
  const double phi0 = std::atan(pb.psi_dot * req.Va / kGravity);
  const double CL = ac.mass * kGravity * std::cos(req.gamma) / (qS * std::cos(phi0));
  double alpha0 = (CL - ac.aero.C_L_0) / ac.aero.C_L_alpha;
  if (!std::isfinite(alpha0)) alpha0 = 0.05;
  alpha0 = std::clamp(alpha0, -0.2, 0.3);
  Vec7 z;
  z << alpha0, phi0, alpha0 + req.gamma,
      ac.aero.C_m_delta_e != 0 ? -(ac.aero.C_m_0 + ac.aero.C_m_alpha * alpha0) / ac.aero.C_m_delta_e : 0.0, 0.0, 0.0, 0.5;
  Vec7 r = pb.residual(z);
  int it = 0;
  for (; it < 100 && r.norm() > 1e-11; ++it) {
    Eigen::Matrix<double, 7, 7> J;
    for (int j = 0; j < 7; ++j) {
      const double h = 1e-6;
      Vec7 zp = z, zm = z;
      zp[j] += h;
      zm[j] -= h;
      J.col(j) = (pb.residual(zp) - pb.residual(zm)) / (2 * h);
    }
    const Vec7 step = J.colPivHouseholderQr().solve(-r);
    if (!step.allFinite()) break;
    double lambda = 1.0;
    bool improved = false;
    for (int k = 0; k < 30; ++k, lambda *= 0.5) {
      const Vec7 zn = z + lambda * step;
      const Vec7 rn = pb.residual(zn);
      if (rn.allFinite() && rn.norm() < r.norm()) {
        z = zn;
        r = rn;
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  if (!(r.norm() < 1e-8)) {
    std::ostringstream s;
    s << what << ": no trim found (residual " << r.norm() << " after " << it << " iterations)";
    throw std::runtime_error(s.str());
  }
  TrimResult out;
  out.x = pb.state(z);
  out.delta = pb.deltas(z);
  out.alpha = z[0];
  out.phi = z[1];
  out.theta = z[2];
  out.beta = pb.beta(z);
  out.residual = r.norm();
  out.iterations = it;
  auto limit = [&](double v, double lim, const char* name) {
    if (std::fabs(v) > lim) {
      std::ostringstream s;
      s << what << ": needs " << name << " = " << v << " rad, beyond its limit " << lim << " rad";
      throw std::runtime_error(s.str());
    }
  };
  if (out.delta.delta_t < 0.0 || out.delta.delta_t > 1.0) {
    std::ostringstream s;
    s << what << ": needs delta_t = " << out.delta.delta_t << ", outside [0, 1]";
    throw std::runtime_error(s.str());
  }
  limit(out.delta.delta_e, ac.max_delta_e, "delta_e");
  limit(out.delta.delta_a, ac.max_delta_a, "delta_a");
  limit(out.delta.delta_r, ac.max_delta_r, "delta_r");
  return out;
}

}  // namespace tern::sim
