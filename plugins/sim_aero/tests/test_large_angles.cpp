// Tests of the model against the book at beta = 0 (the uavbook's equations written out here
// independently of model.cpp), and of where it leaves the book (model.hpp, "Large angles"):
// a crosswind, a tailwind, a stopped propeller.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "tern/aircraft.hpp"
#include "tern/math.hpp"
#include "tern/aero/model.hpp"

using tern::Aircraft;
using tern::kPi;
using tern::load_aircraft;
using namespace tern::sim;

namespace {
const std::string kAircraft = TERN_AIRCRAFT_DIR;

struct Book {
  Eigen::Vector3d f, m;  // aerodynamic + thrust force and moment, body, N and N m
};

// Propeller thrust and torque at airspeed Va (the uavbook's propulsion supplement, eqs. 4.17-4.20).
Eigen::Vector2d book_propeller(const Aircraft& ac, double Va, double delta_t) {
  const auto& p = ac.prop;
  const double rho = ac.rho, D = p.D_prop;
  const double a = rho * std::pow(D, 5) * p.C_Q_0 / (4 * kPi * kPi);
  const double b = rho * std::pow(D, 4) * p.C_Q_1 * Va / (2 * kPi) + p.K_Q * p.K_Q / p.R_motor;
  const double c = rho * std::pow(D, 3) * p.C_Q_2 * Va * Va - p.K_Q * p.V_max * delta_t / p.R_motor + p.K_Q * p.i0;
  const double Omega = (-b + std::sqrt(b * b - 4 * a * c)) / (2 * a);
  const double n = Omega / (2 * kPi), J = Va / (n * D);
  const double C_T = p.C_T_2 * J * J + p.C_T_1 * J + p.C_T_0, C_Q = p.C_Q_2 * J * J + p.C_Q_1 * J + p.C_Q_0;
  return {rho * n * n * std::pow(D, 4) * C_T, rho * n * n * std::pow(D, 5) * C_Q};
}

// The book's forces and moments (sec. 4.2-4.3) for body air velocity (u, 0, w), rates pqr.
Book book_forces(const Aircraft& ac, double u, double w, const Eigen::Vector3d& pqr, const Deltas& d) {
  const auto& A = ac.aero;
  const double Va = std::hypot(u, w), alpha = std::atan2(w, u), qbar = 0.5 * ac.rho * Va * Va;
  const double p = pqr.x(), q = pqr.y(), r = pqr.z();
  double sigma = 0.0;  // the book's blend; aircraft without it (ROSflight's) have linear lift
  if (ac.stall_blend) {
    const double e1 = std::exp(-ac.M * (alpha - ac.alpha0)), e2 = std::exp(ac.M * (alpha + ac.alpha0));
    sigma = (1 + e1 + e2) / ((1 + e1) * (1 + e2));
  }
  const double sa = std::sin(alpha), ca = std::cos(alpha);
  const double C_L = (1 - sigma) * (A.C_L_0 + A.C_L_alpha * alpha) + sigma * 2 * (alpha >= 0 ? 1 : -1) * sa * sa * ca;
  const double C_D = A.C_D_p + std::pow(A.C_L_0 + A.C_L_alpha * alpha, 2) / (kPi * ac.e * ac.AR());
  const double cq = ac.c * q / (2 * Va), bp = ac.b * p / (2 * Va), br = ac.b * r / (2 * Va);
  const double F_lift = qbar * ac.S * (C_L + A.C_L_q * cq + A.C_L_delta_e * d.delta_e);
  const double F_drag = qbar * ac.S * (C_D + A.C_D_q * cq + A.C_D_delta_e * d.delta_e);
  const Eigen::Vector2d prop = book_propeller(ac, Va, d.delta_t);
  Book out;
  out.f.x() = -ca * F_drag + sa * F_lift + prop.x();
  out.f.z() = -sa * F_drag - ca * F_lift;
  out.f.y() = qbar * ac.S * (A.C_Y_0 + A.C_Y_p * bp + A.C_Y_r * br + A.C_Y_delta_a * d.delta_a + A.C_Y_delta_r * d.delta_r);
  out.m.x() =
      qbar * ac.S * ac.b * (A.C_ell_0 + A.C_ell_p * bp + A.C_ell_r * br + A.C_ell_delta_a * d.delta_a + A.C_ell_delta_r * d.delta_r) -
      prop.y();
  out.m.y() = qbar * ac.S * ac.c * (A.C_m_0 + A.C_m_alpha * alpha + A.C_m_q * cq + A.C_m_delta_e * d.delta_e);
  out.m.z() = qbar * ac.S * ac.b * (A.C_n_0 + A.C_n_p * bp + A.C_n_r * br + A.C_n_delta_a * d.delta_a + A.C_n_delta_r * d.delta_r);
  return out;
}

// The model's aerodynamic force and moment with the aircraft high above the ground, level, no
// wind, body velocity (u, v, w).
ForcesMoments model_forces(const Aircraft& ac, const Eigen::Vector3d& uvw, const Eigen::Vector3d& pqr, const Deltas& d,
                           const Wind& wind = {}) {
  return forces_moments(ac, make_state({0, 0, -100}, uvw, 0, 0, 0, pqr), d, wind);
}
}  // namespace

TEST_CASE("model: at beta = 0 the forces and moments are the book's equations") {
  Deltas d;
  d.delta_e = -0.08;
  d.delta_a = 0.05;
  d.delta_r = -0.03;
  d.delta_t = 0.6;
  const Eigen::Vector3d pqr(0.3, -0.2, 0.1);
  // the Aerosonde (the book's aircraft, its blended lift): to rounding (its blending tails are
  // below 1e-8 here); the Anaconda (linear lift, as ROSflight): to 1e-5, the tails of the blend
  // model.cpp applies at 0.35 rad for flow from behind (sigma(0.1) = 4e-6)
  for (const auto& [file, tol] : {std::pair{"aerosonde.yaml", 1e-9}, std::pair{"anaconda.yaml", 1e-5}}) {
    const Aircraft ac = load_aircraft(kAircraft + "/" + file);
    for (const double alpha : {-0.1, 0.0, 0.04, 0.1}) {
      CAPTURE(file);
      CAPTURE(alpha);
      const double Va = 17.0;
      const Book book = book_forces(ac, Va * std::cos(alpha), Va * std::sin(alpha), pqr, d);
      const ForcesMoments fm = model_forces(ac, {Va * std::cos(alpha), 0.0, Va * std::sin(alpha)}, pqr, d);
      for (int i = 0; i < 3; ++i) {
        CAPTURE(i);
        CHECK(std::fabs(fm.f_aero[i] - book.f[i]) <= tol * (std::fabs(book.f[i]) + 1.0));
        CHECK(std::fabs(fm.m_aero[i] - book.m[i]) <= tol * (std::fabs(book.m[i]) + 1.0));
      }
    }
  }
}

TEST_CASE("model: a pure crosswind at rest gives side force, no lift; the dihedral effect fades with it") {
  const Aircraft ac = load_aircraft(kAircraft + "/anaconda.yaml");
  Wind wind;
  wind.steady_ned = {0.0, -7.0, 0.0};  // the aircraft heads north, the air blows from the east: v_r = +7
  const ForcesMoments fm = model_forces(ac, {0, 0, 0}, {0, 0, 0}, Deltas{}, wind);
  CHECK(fm.air.beta == doctest::Approx(kPi / 2));
  CHECK(std::fabs(fm.f_aero.z()) < 1e-9);  // the book's model: 26 N up (59 % of the weight) at alpha 117 deg
  CHECK(std::fabs(fm.f_aero.x()) < 1e-9);  // no drag along x, no axial force on the propeller
  CHECK(std::fabs(fm.m_aero.y()) < 1e-9);
  CHECK(std::fabs(fm.m_aero.x()) < 1e-9);  // C_ell_beta sin(beta) cos(beta)
  const double qS = 0.5 * ac.rho * 49.0 * ac.S;
  CHECK(fm.f_aero.y() == doctest::Approx(qS * ac.aero.C_Y_beta));         // pushed downwind (C_Y_beta < 0)
  CHECK(fm.m_aero.z() == doctest::Approx(qS * ac.b * ac.aero.C_n_beta));  // the nose turns into the wind
  // at 10 deg of sideslip, within the blending angle, the book's linear derivatives
  const double b10 = 10.0 * kPi / 180.0;
  const ForcesMoments f10 = model_forces(ac, {17.0 * std::cos(b10), 17.0 * std::sin(b10), 0.0}, {0, 0, 0}, Deltas{});
  const double qS10 = 0.5 * ac.rho * 17.0 * 17.0 * ac.S;
  CHECK(f10.m_aero.x() + f10.prop.Q_p ==
        doctest::Approx(qS10 * ac.b * ac.aero.C_ell_beta * b10).epsilon(1e-3));  // less the windmilling torque
  // ... and the lift of the flow in the x-z plane, qbar cos^2(beta)
  CHECK(-f10.f_aero.z() == doctest::Approx(qS10 * std::pow(std::cos(b10), 2) * ac.aero.C_L_0).epsilon(0.02));
}

TEST_CASE("model: a stopped propeller's drag follows the flow along its axis") {
  const Aircraft ac = load_aircraft(kAircraft + "/anaconda.yaml");
  const double drag8 = ac.rho * ac.prop.D_prop * ac.prop.D_prop * ac.prop.C_T_2 * 64.0;  // < 0: the book's at 8 m/s
  // the motor off in an 8 m/s tailwind: the propeller is pushed forward (the book: pulled aft, 3.7 N)
  PropulsionOutput tail = propulsion(ac, -8.0, 0.0);
  CHECK(tail.Omega == 0.0);
  CHECK(tail.T_p == doctest::Approx(-drag8));
  CHECK(tail.T_p > 3.0);
  // from ahead, in flight: the book's polynomial
  CHECK(propulsion(ac, 8.0, 0.0).T_p < 0.0);
  // the inflow: the book's Va from ahead, u_r from behind, 0 across the disc
  Wind wind;
  wind.steady_ned = {8.0, 0.0, 0.0};  // tailwind
  const ForcesMoments fm = model_forces(ac, {0, 0, 0}, {0, 0, 0}, Deltas{}, wind);
  CHECK(propeller_inflow(fm.air, blend_sigma(ac, fm.air.alpha)) == doctest::Approx(-8.0));
  CHECK(fm.prop.T_p > 3.0);
  wind.steady_ned = {0.0, 8.0, 0.0};  // crosswind
  CHECK(std::fabs(model_forces(ac, {0, 0, 0}, {0, 0, 0}, Deltas{}, wind).prop.T_p) < 1e-9);
}

TEST_CASE("model: with the flow from behind C_m_0 reverses, as the tail's incidence does") {
  const Aircraft ac = load_aircraft(kAircraft + "/anaconda.yaml");
  REQUIRE(ac.aero.C_m_0 > 0.0);
  Wind wind;
  wind.steady_ned = {8.0, 0.0, 0.0};  // 8 m/s tailwind, level: alpha = 180 deg
  const ForcesMoments fm = model_forces(ac, {0, 0, 0}, {0, 0, 0}, Deltas{}, wind);
  REQUIRE(std::fabs(std::fabs(fm.air.alpha) - kPi) < 1e-9);
  const double qSc = 0.5 * ac.rho * 64.0 * ac.S * ac.c;
  CHECK(fm.m_aero.y() == doctest::Approx(-qSc * ac.aero.C_m_0).epsilon(1e-6));  // the book: +C_m_0, nose up
  // from ahead at alpha 0 it is the book's +C_m_0
  CHECK(model_forces(ac, {8.0, 0, 0}, {0, 0, 0}, Deltas{}).m_aero.y() == doctest::Approx(qSc * ac.aero.C_m_0).epsilon(1e-6));
}

TEST_CASE("model: the blending function is the book's sigma(alpha) over the whole circle, an extreme M included") {
  Aircraft ac = load_aircraft(kAircraft + "/aerosonde.yaml");
  // book eq. 4.10, each exponential on its own (capped where it would overflow)
  const auto book_sigma = [](double M, double a0, double a) {
    const double e1 = std::exp(std::min(-M * (a - a0), 700.0)), e2 = std::exp(std::min(M * (a + a0), 700.0));
    return (1.0 + e1 + e2) / ((1.0 + e1) * (1.0 + e2));
  };
  for (const double M : {ac.M, 500.0}) {
    ac.M = M;
    for (int i = -360; i <= 360; ++i) {
      const double a = kPi * i / 360.0;
      const double s = blend_sigma(ac, a), b = book_sigma(M, ac.alpha0, a);
      INFO("M " << M << ", alpha " << a);
      REQUIRE(std::isfinite(s));
      CHECK(s == doctest::Approx(b).epsilon(1e-12));
      CHECK(s >= 0.0);
      CHECK(s <= 1.0 + 1e-12);
    }
  }
}
