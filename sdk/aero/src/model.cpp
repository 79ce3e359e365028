// The uavbook model: air data, forces and moments, equations of motion, RK4 (see model.hpp).
#include "tern/aero/model.hpp"

#include <algorithm>
#include <cmath>
#include "tern/math.hpp"

namespace tern::sim {
namespace {
using tern::kPi;

double safe_exp(double x) { return std::exp(std::min(x, 700.0)); }
}  // namespace

Eigen::Quaterniond attitude(const StateVector& x) { return Eigen::Quaterniond(x[E0], x[E1], x[E2], x[E3]).normalized(); }

namespace {
Eigen::Vector3d air_velocity(const StateVector& x, const Wind& wind, const Eigen::Matrix3d& Rot) {
  return Eigen::Vector3d(x[U], x[V], x[W]) - (Rot.transpose() * wind.steady_ned + wind.gust_body);
}

AirData air_data_rot(const StateVector& x, const Wind& wind, const Eigen::Matrix3d& Rot) {
  AirData a;
  a.v_air = air_velocity(x, wind, Rot);
  a.Va = a.v_air.norm();
  a.V_xz = Eigen::Vector3d(a.v_air.x(), 0.0, a.v_air.z()).norm();  // == Va, bit for bit, when v_r = 0
  a.alpha = std::atan2(a.v_air.z(), a.v_air.x());
  if (a.V_xz > 0.0) {
    a.sin_alpha = a.v_air.z() / a.V_xz;
    a.cos_alpha = a.v_air.x() / a.V_xz;
  } else {  // atan2's signed zeros (alpha 0 or pi)
    a.sin_alpha = std::sin(a.alpha);
    a.cos_alpha = std::cos(a.alpha);
  }
  if (a.Va > 1e-9) {
    a.sin_beta = std::clamp(a.v_air.y() / a.Va, -1.0, 1.0);
    a.beta = std::asin(a.sin_beta);
    a.cos_beta = a.V_xz / a.Va;
  }
  return a;
}
}  // namespace

AirData air_data(const StateVector& x, const Wind& wind) { return air_data_rot(x, wind, attitude(x).toRotationMatrix()); }

double airspeed(const StateVector& x, const Wind& wind) { return air_velocity(x, wind, attitude(x).toRotationMatrix()).norm(); }

PropulsionOutput propulsion(const Aircraft& ac, double V, double delta_t) {
  const auto& p = ac.prop;
  const double rho = ac.rho, D = p.D_prop;
  const double D2 = D * D, D3 = D2 * D, D4 = D3 * D, D5 = D4 * D;
  const double V_in = p.V_max * delta_t;
  const double V2 = V * std::fabs(V);  // the book's Va^2, signed: the flow's push follows its direction
  // Omega is the positive root of a Omega^2 + b Omega + c = 0 (torque balance motor/propeller).
  const double a = rho * D5 * p.C_Q_0 / (4.0 * kPi * kPi);
  const double b = rho * D4 * p.C_Q_1 * V / (2.0 * kPi) + p.K_Q * p.K_Q / p.R_motor;
  const double c = rho * D3 * p.C_Q_2 * V2 - p.K_Q * V_in / p.R_motor + p.K_Q * p.i0;
  const double disc = b * b - 4.0 * a * c;
  double Omega = disc > 0.0 ? (-b + std::sqrt(disc)) / (2.0 * a) : 0.0;
  Omega = std::max(Omega, 0.0);  // the motor does not drive the propeller backwards
  PropulsionOutput out;
  out.Omega = Omega;
  // T_p = rho (Omega/2pi)^2 D^4 C_T(J), J = 2 pi V/(Omega D), written without dividing by Omega.
  out.T_p = rho * D4 * p.C_T_0 * Omega * Omega / (4.0 * kPi * kPi) + rho * D3 * p.C_T_1 * V * Omega / (2.0 * kPi) + rho * D2 * p.C_T_2 * V2;
  out.Q_p = rho * D5 * p.C_Q_0 * Omega * Omega / (4.0 * kPi * kPi) + rho * D4 * p.C_Q_1 * V * Omega / (2.0 * kPi) + rho * D3 * p.C_Q_2 * V2;
  return out;
}

double propeller_inflow(const AirData& air, double sigma) { return (1.0 - sigma) * air.V_xz + sigma * air.v_air.x(); }

namespace {
// The blending function of an aircraft with exp(M a0) computed once: sigma(x) = (1 + e1 + e2) /
// ((1 + e1)(1 + e2)), e1 = exp(-M (x - a0)) = e0 / exp(M x), e2 = exp(M (x + a0)) = e0 exp(M x):
// one exp per angle (the angle of attack's and the sideslip's in every evaluation).
struct Blend {
  double M, a0, e0;
};

Blend blend_of(const Aircraft& ac) {
  const double a0 = ac.stall_blend ? ac.alpha0 : kLinearLiftLimit;
  return {ac.M, a0, safe_exp(ac.M * a0)};
}

double sigma_at(const Blend& b, double x) {
  double e1 = 0.0, e2 = 0.0;
  if (std::fabs(b.M * b.a0) + std::fabs(b.M * x) < 700.0) {
    const double ex = std::exp(b.M * x);
    e1 = b.e0 / ex;
    e2 = b.e0 * ex;
  } else {  // far beyond the blending angle (or an extreme M): each term capped
    e1 = safe_exp(-b.M * (x - b.a0));
    e2 = safe_exp(b.M * (x + b.a0));
  }
  return (1.0 + e1 + e2) / ((1.0 + e1) * (1.0 + e2));
}
}  // namespace

double blend_sigma(const Aircraft& ac, double alpha) { return sigma_at(blend_of(ac), alpha); }

namespace {
// sa, ca: sin(alpha), cos(alpha), computed once per evaluation by the caller
double lift_c(const Aircraft& ac, double alpha, double sigma, double sa, double ca) {
  const double sgn = alpha >= 0.0 ? 1.0 : -1.0;
  return (1.0 - sigma) * (ac.aero.C_L_0 + ac.aero.C_L_alpha * alpha) + sigma * (2.0 * sgn * sa * sa * ca);
}

double drag_c(const Aircraft& ac, double alpha, double sigma, double sin_alpha) {
  const double cl = ac.aero.C_L_0 + ac.aero.C_L_alpha * alpha;
  const double sa = std::fabs(sin_alpha);
  return ac.aero.C_D_p + (1.0 - sigma) * cl * cl / (kPi * ac.e * ac.AR()) + sigma * 2.0 * sa * sa * sa;
}
}  // namespace

double lift_coefficient(const Aircraft& ac, double alpha) {
  return lift_c(ac, alpha, blend_sigma(ac, alpha), std::sin(alpha), std::cos(alpha));
}
double drag_coefficient(const Aircraft& ac, double alpha) { return drag_c(ac, alpha, blend_sigma(ac, alpha), std::sin(alpha)); }

namespace {
// Spring-damper wheels with rolling and side friction; ground plane p_d = 0.
void ground_contact(const Aircraft& ac, const StateVector& x, const Eigen::Matrix3d& Rot, const Deltas& d, ForcesMoments& fm) {
  const auto& g = ac.gear;
  const Eigen::Vector3d p(x[PN], x[PE], x[PD]);
  // in the air (no wheel below the ground: each `continue`s below) there is nothing to work out
  if (std::none_of(g.points.begin(), g.points.end(), [&](const Eigen::Vector3d& r) { return (p + Rot * r).z() > 0.0; })) return;
  const double n = static_cast<double>(g.points.size());
  const double k = ac.mass * kGravity / (n * g.static_deflection);
  const double c = 2.0 * g.damping_ratio * std::sqrt(k * ac.mass / n);
  const Eigen::Vector3d v(x[U], x[V], x[W]);
  const Eigen::Vector3d w(x[P], x[Q], x[R]);
  // Wheel rolling direction: body x projected on the ground plane.
  Eigen::Vector2d xh(Rot(0, 0), Rot(1, 0));
  const double xn = xh.norm();
  xh = xn > 1e-6 ? Eigen::Vector2d(xh / xn) : Eigen::Vector2d(1.0, 0.0);
  const Eigen::Vector2d yh(-xh.y(), xh.x());
  // a steered wheel rolls along body x turned by the steering angle (positive: to the right);
  // its direction is worked out with the first wheel on the ground (none in the air)
  bool steer_known = false;
  Eigen::Vector2d xs = xh, ys = yh;
  for (const auto& r : g.points) {
    const Eigen::Vector3d pi = p + Rot * r;
    const double depth = pi.z();  // > 0: below the ground
    if (depth <= 0.0) continue;
    const Eigen::Vector3d vi = Rot * (v + w.cross(r));  // NED velocity of the wheel
    const double N = std::max(0.0, k * depth + c * vi.z());
    if (N <= 0.0) continue;
    ++fm.wheels_on_ground;
    const Eigen::Vector2d vh(vi.x(), vi.y());
    const bool steered = g.nose_steering != 0.0 && r.x() > 0.0;
    if (steered && !steer_known) {
      const double steer = -g.nose_steering * d.delta_r;
      xs = std::cos(steer) * xh + std::sin(steer) * yh;
      ys = Eigen::Vector2d(-xs.y(), xs.x());
      steer_known = true;
    }
    const Eigen::Vector2d& ax = steered ? xs : xh;
    const Eigen::Vector2d& ay = steered ? ys : yh;
    const double v_long = vh.dot(ax), v_lat = vh.dot(ay);
    // wheels behind the CG brake (a tricycle's mains, a taildragger's... mains ahead: not braked)
    const double mu_long = g.mu_roll + (r.x() <= 0.0 ? g.mu_brake * std::clamp(d.brake, 0.0, 1.0) : 0.0);
    const double f_long = -mu_long * N * std::clamp(v_long / g.v_slip, -1.0, 1.0);
    const double f_lat = -g.mu_lateral * N * std::clamp(v_lat / g.v_slip, -1.0, 1.0);
    const Eigen::Vector2d fh = f_long * ax + f_lat * ay;
    const Eigen::Vector3d f_body = Rot.transpose() * Eigen::Vector3d(fh.x(), fh.y(), -N);
    fm.f_ground += f_body;
    fm.m_ground += r.cross(f_body);
  }
}
}  // namespace

namespace {
// Lift, drag and pitching moment (book sec. 4.2) on the flow in the body x-z plane: its dynamic
// pressure qbar cos^2(beta) and speed V_xz = Va cos(beta) (model.hpp, "Large angles").
void longitudinal(const Aircraft& ac, const StateVector& x, const Deltas& d, double sigma, ForcesMoments& fm) {
  const auto& A = ac.aero;
  const double V = fm.air.V_xz, alpha = fm.air.alpha, q = x[Q];
  // qbar S, and qbar S c/(2 V) written without dividing by V (finite at V = 0).
  const double qS = 0.5 * ac.rho * V * V * ac.S;
  const double qSc = 0.25 * ac.rho * V * ac.S * ac.c;
  const double ca = fm.air.cos_alpha, sa = fm.air.sin_alpha;
  // Beyond the blending angle C_m_alpha alpha fades to C_m_alpha sin(alpha), and the incidence
  // terms (C_m_0, the elevator's) to their value times cos(alpha): they reverse with the flow.
  const double alpha_m = (1.0 - sigma) * alpha + sigma * sa;
  const double incidence = (1.0 - sigma) + sigma * ca;
  const double F_lift = qS * (lift_c(ac, alpha, sigma, sa, ca) + A.C_L_delta_e * d.delta_e * incidence) + qSc * A.C_L_q * q;
  const double F_drag = qS * (drag_c(ac, alpha, sigma, sa) + A.C_D_delta_e * d.delta_e) + qSc * A.C_D_q * q;
  fm.f_aero.x() = -ca * F_drag + sa * F_lift;
  fm.f_aero.z() = -sa * F_drag - ca * F_lift;
  const double C_m = (A.C_m_0 + A.C_m_delta_e * d.delta_e) * incidence + A.C_m_alpha * alpha_m;
  fm.m_aero.y() = ac.c * (qS * C_m + qSc * A.C_m_q * q);
}

// Side force, rolling and yawing moments (book sec. 4.3) on the full dynamic pressure; the
// sideslip terms leave the book's linear beta beyond the blending angle (model.hpp).
void lateral(const Aircraft& ac, const Blend& blend, const StateVector& x, const Deltas& d, ForcesMoments& fm) {
  const auto& A = ac.aero;
  const double Va = fm.air.Va, beta = fm.air.beta, p = x[P], r = x[R];
  // qbar S, and qbar S b/(2 Va) written without dividing by Va (finite at Va = 0).
  const double qS = 0.5 * ac.rho * Va * Va * ac.S;
  const double qSb = 0.25 * ac.rho * Va * ac.S * ac.b;
  const double sb = sigma_at(blend, beta), sin_b = fm.air.sin_beta;
  const double beta_y = (1.0 - sb) * beta + sb * sin_b;                    // side force, yaw
  const double beta_l = (1.0 - sb) * beta + sb * sin_b * fm.air.cos_beta;  // roll
  fm.f_aero.y() =
      qS * (A.C_Y_0 + A.C_Y_beta * beta_y + A.C_Y_delta_a * d.delta_a + A.C_Y_delta_r * d.delta_r) + qSb * (A.C_Y_p * p + A.C_Y_r * r);
  fm.m_aero.x() = ac.b * (qS * (A.C_ell_0 + A.C_ell_beta * beta_l + A.C_ell_delta_a * d.delta_a + A.C_ell_delta_r * d.delta_r) +
                          qSb * (A.C_ell_p * p + A.C_ell_r * r));
  fm.m_aero.z() = ac.b * (qS * (A.C_n_0 + A.C_n_beta * beta_y + A.C_n_delta_a * d.delta_a + A.C_n_delta_r * d.delta_r) +
                          qSb * (A.C_n_p * p + A.C_n_r * r));
}

ForcesMoments forces_moments_rot(const Aircraft& ac, const Blend& blend, const StateVector& x, const Deltas& d, const Wind& wind,
                                 const Eigen::Matrix3d& Rot) {
  ForcesMoments fm;
  fm.air = air_data_rot(x, wind, Rot);
  const double sigma = sigma_at(blend, fm.air.alpha);
  longitudinal(ac, x, d, sigma, fm);
  lateral(ac, blend, x, d, fm);
  fm.prop = propulsion(ac, propeller_inflow(fm.air, sigma), d.delta_t);
  fm.f_aero.x() += fm.prop.T_p;
  fm.m_aero.x() -= fm.prop.Q_p;
  fm.f_gravity = Rot.transpose() * Eigen::Vector3d(0.0, 0.0, ac.mass * kGravity);
  ground_contact(ac, x, Rot, d, fm);
  fm.force = fm.f_aero + fm.f_gravity + fm.f_ground;
  fm.moment = fm.m_aero + fm.m_ground;
  return fm;
}
}  // namespace

ForcesMoments forces_moments(const Aircraft& ac, const StateVector& x, const Deltas& d, const Wind& wind) {
  return forces_moments_rot(ac, blend_of(ac), x, d, wind, attitude(x).toRotationMatrix());
}

namespace {
// What every evaluation of an integration step shares: computed once per step.
struct StepConstants {
  Blend blend;
  InertiaGammas gamma;
};

StepConstants constants_of(const Aircraft& ac) { return {blend_of(ac), inertia_gammas(ac)}; }

StateVector derivative_b(const Aircraft& ac, const StepConstants& k, const StateVector& x, const Deltas& d, const Wind& w,
                         ForcesMoments* out) {
  const Eigen::Matrix3d Rot = attitude(x).toRotationMatrix();
  const ForcesMoments fm = forces_moments_rot(ac, k.blend, x, d, w, Rot);
  const Eigen::Vector3d v(x[U], x[V], x[W]);
  const double p = x[P], q = x[Q], r = x[R];
  StateVector dx;
  dx.segment<3>(PN) = Rot * v;
  // Book eq. 3.15: body acceleration.
  dx[U] = r * x[V] - q * x[W] + fm.force.x() / ac.mass;
  dx[V] = p * x[W] - r * x[U] + fm.force.y() / ac.mass;
  dx[W] = q * x[U] - p * x[V] + fm.force.z() / ac.mass;
  // Appendix B: quaternion kinematics (e0 scalar).
  const double e0 = x[E0], e1 = x[E1], e2 = x[E2], e3 = x[E3];
  dx[E0] = 0.5 * (-p * e1 - q * e2 - r * e3);
  dx[E1] = 0.5 * (p * e0 + r * e2 - q * e3);
  dx[E2] = 0.5 * (q * e0 - r * e1 + p * e3);
  dx[E3] = 0.5 * (r * e0 + q * e1 - p * e2);
  // Book eq. 3.17 with the Gamma coefficients of eq. 3.13.
  const auto [G1, G2, G3, G4, G5, G6, G7, G8] = k.gamma;
  const double l = fm.moment.x(), m = fm.moment.y(), n = fm.moment.z();
  dx[P] = G1 * p * q - G2 * q * r + G3 * l + G4 * n;
  dx[Q] = G5 * p * r - G6 * (p * p - r * r) + m / ac.Jy;
  dx[R] = G7 * p * q - G1 * q * r + G4 * l + G8 * n;
  if (out != nullptr) *out = fm;
  return dx;
}
}  // namespace

StateVector derivative(const Aircraft& ac, const StateVector& x, const Deltas& d, const Wind& w, ForcesMoments* out) {
  return derivative_b(ac, constants_of(ac), x, d, w, out);
}

StateVector rk4_step(const Aircraft& ac, const StateVector& x, const Deltas& d, const Wind& w, double dt) {
  const StepConstants c = constants_of(ac);
  const StateVector k1 = derivative_b(ac, c, x, d, w, nullptr);
  const StateVector k2 = derivative_b(ac, c, x + 0.5 * dt * k1, d, w, nullptr);
  const StateVector k3 = derivative_b(ac, c, x + 0.5 * dt * k2, d, w, nullptr);
  const StateVector k4 = derivative_b(ac, c, x + dt * k3, d, w, nullptr);
  StateVector xn = x + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  xn.segment<4>(E0).normalize();
  return xn;
}

StateVector make_state(const Eigen::Vector3d& p_ned, const Eigen::Vector3d& v_body, double phi, double theta, double psi,
                       const Eigen::Vector3d& pqr) {
  StateVector x;
  x.segment<3>(PN) = p_ned;
  x.segment<3>(U) = v_body;
  const double c0 = std::cos(psi / 2), s0 = std::sin(psi / 2);
  const double c1 = std::cos(theta / 2), s1 = std::sin(theta / 2);
  const double c2 = std::cos(phi / 2), s2 = std::sin(phi / 2);
  x[E0] = c0 * c1 * c2 + s0 * s1 * s2;
  x[E1] = c0 * c1 * s2 - s0 * s1 * c2;
  x[E2] = c0 * s1 * c2 + s0 * c1 * s2;
  x[E3] = s0 * c1 * c2 - c0 * s1 * s2;
  x.segment<3>(P) = pqr;
  return x;
}

bool all_finite(const StateVector& x) { return x.allFinite(); }

double rest_height(const Aircraft& ac) {
  double z = 0.0;
  for (const auto& r : ac.gear.points) z = std::max(z, r.z());
  return z - ac.gear.static_deflection;
}

}  // namespace tern::sim

namespace tern::sim {
StateVector rest_state(const Aircraft& ac, double p_n, double p_e, double psi) {
  StateVector x = make_state({p_n, p_e, -rest_height(ac)}, Eigen::Vector3d::Zero(), 0, 0, psi);
  for (int i = 0; i < 2000; ++i) x = rk4_step(ac, x, Deltas{}, Wind{}, 0.0025);  // 5 s
  x[PN] = p_n;  // exactly where asked (the settling moves it by micrometres)
  x[PE] = p_e;
  x.segment<3>(U).setZero();
  x.segment<3>(P).setZero();
  return x;
}
}  // namespace tern::sim
