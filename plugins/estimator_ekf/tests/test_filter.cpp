// EKF core: Jacobians against finite differences, block propagation against F P F^T + Q,
// the Joseph-form update and the chi-square gate.
#include <doctest/doctest.h>

#include <limits>
#include <random>
#include <utility>

#include "tern/estimator_ekf/filter.hpp"
#include "tern/estimator_ekf/measurements.hpp"
#include "tern/math.hpp"

using namespace tern::ekf;

namespace {

NominalState sample_state() {
  NominalState x;
  x.p = Vec3(120.0, -40.0, -85.0);
  x.v = Vec3(14.0, 9.0, -1.5);
  x.q = tern::quaternion_from_euler(0.4, -0.2, 2.5);
  x.b_g = Vec3(0.01, -0.02, 0.005);
  x.b_a = Vec3(0.1, 0.05, -0.2);
  x.wind = Eigen::Vector2d(3.0, -4.0);
  x.b_baro = 1.5;
  x.e_gnss = Vec3(0.5, -1.0, 2.0);
  x.S_g << 0.01, -0.02, 0.015, 0.012, -0.008, 0.02, -0.017, 0.009, 0.005;
  x.b_m = Vec3(0.03, -0.05, 0.04);
  x.k_sp = 0.04;
  x.wind_d = 0.7;
  return x;
}

/// x1 [-] x0: the error state that takes x0 to x1.
ErrVec boxminus(const NominalState& x1, const NominalState& x0) {
  ErrVec d;
  d.segment<3>(idx::p) = x1.p - x0.p;
  d.segment<3>(idx::v) = x1.v - x0.v;
  const Eigen::AngleAxisd aa(x0.q.conjugate() * x1.q);
  d.segment<3>(idx::th) = aa.angle() * aa.axis();
  d.segment<3>(idx::bg) = x1.b_g - x0.b_g;
  d.segment<3>(idx::ba) = x1.b_a - x0.b_a;
  d.segment<2>(idx::w) = x1.wind - x0.wind;
  d(idx::bb) = x1.b_baro - x0.b_baro;
  d.segment<3>(idx::eg) = x1.e_gnss - x0.e_gnss;
  for (int i = 0; i < 3; ++i) d.segment<3>(idx::sg + 3 * i) = (x1.S_g - x0.S_g).row(i).transpose();
  d.segment<3>(idx::bm) = x1.b_m - x0.b_m;
  d(idx::sp) = x1.k_sp - x0.k_sp;
  d(idx::wd) = x1.wind_d - x0.wind_d;
  return d;
}

/// The Anaconda's lift model (configs/aircraft/anaconda.yaml): rho S / (2 m) with rho 1.2682,
/// S 0.52, m 4.5; c 0.235; C_L_0 0.506, C_L_alpha 5.61, C_L_q 7.95, C_L_delta_e 0.13.
NormalForce anaconda_normal_force() {
  NormalForce m;
  m.k = 1.2682 * 0.52 / (2.0 * 4.5);
  m.C_L_0 = 0.506;
  m.C_L_alpha = 5.61;
  m.C_L_q = 7.95;
  m.C_L_delta_e = 0.13;
  m.chord = 0.235;
  m.delta_e = -0.04;
  m.q = 0.12;
  return m;
}

template <class Model>
void check_jacobian(const Model& m, const NominalState& x) {
  const auto H = m.jacobian(x);
  const double eps = 1e-6;
  for (int i = 0; i < kErrDim; ++i) {
    ErrVec d = ErrVec::Zero();
    d(i) = eps;
    const auto num = ((m.h(boxplus(x, d)) - m.h(boxplus(x, -d))) / (2 * eps)).eval();
    for (int r = 0; r < Model::kDim; ++r) {
      INFO("row " << r << " column " << i);
      CHECK(H(r, i) == doctest::Approx(num(r)).epsilon(1e-5).scale(1.0));
    }
  }
}

Cov random_spd(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n;
  Cov A;
  for (int i = 0; i < kErrDim; ++i)
    for (int j = 0; j < kErrDim; ++j) A(i, j) = n(rng);
  return A * A.transpose() * 0.1 + Cov::Identity() * 0.01;
}

}  // namespace

TEST_CASE("measurement Jacobians match finite differences") {
  const NominalState x = sample_state();
  SUBCASE("gnss position") { check_jacobian(GnssPosition{}, x); }
  SUBCASE("gnss velocity") { check_jacobian(GnssVelocity{}, x); }
  SUBCASE("gnss position, antenna lever arm") {
    GnssPosition m;
    m.antenna = Vec3(-0.3, 0.1, -0.2);
    check_jacobian(m, x);
  }
  SUBCASE("gnss velocity, antenna lever arm in a turn") {
    GnssVelocity m;
    m.antenna = Vec3(-0.3, 0.1, -0.2);
    m.gyro = Vec3(0.4, -0.3, 0.9);
    check_jacobian(m, x);
  }
  SUBCASE("magnetometer") { check_jacobian(Magnetometer{}, x); }
  SUBCASE("barometer") {
    BaroAltitude baro;
    baro.dynamic_pressure = 180.0;
    baro.q_datum = 20.0;
    check_jacobian(baro, x);
  }
  SUBCASE("magnetic heading") { check_jacobian(MagHeading{}, x); }
  SUBCASE("pitot airspeed") { check_jacobian(PitotAirspeed{}, x); }
  SUBCASE("zero sideslip") { check_jacobian(ZeroSideslip{}, x); }
  SUBCASE("side force") {
    SideForce m;  // the Anaconda's: rho S / (2 m) with rho 1.2682, S 0.52, m 4.5
    m.k = 1.2682 * 0.52 / (2.0 * 4.5);
    m.C_Y_0 = 0.01;
    m.C_Y_beta = -0.98;
    m.C_Y_delta_a = 0.075;
    m.C_Y_delta_r = 0.19;
    m.delta_a = 0.05;
    m.delta_r = -0.08;
    check_jacobian(m, x);
  }
  SUBCASE("normal force") { check_jacobian(anaconda_normal_force(), x); }
  SUBCASE("normal force, level-calibrated accelerometer") {
    NormalForce m = anaconda_normal_force();
    m.level_G(0, 1) = 1.0 / 9.81;
    m.level_G(1, 0) = -1.0 / 9.81;
    check_jacobian(m, x);
  }
}

TEST_CASE("normal force: h is the lift over the mass along -z, plus the accelerometer bias") {
  NormalForce m = anaconda_normal_force();
  m.delta_e = m.q = 0.0;
  NominalState x;  // level, heading north, 17 m/s, the air coming 1 m/s from below (an updraft)
  x.v = Vec3(17.0, 0.0, 0.0);
  x.wind_d = -1.0;
  // w_r = +1 m/s: alpha = atan(1 / 17)
  const double Va = std::hypot(17.0, 1.0), alpha = std::atan2(1.0, 17.0);
  const double lift = 0.5 * 1.2682 * Va * Va * 0.52 * (0.506 + 5.61 * alpha) / 4.5;
  CHECK(m.h(x)(0) == doctest::Approx(-lift).epsilon(0.01));
  x.b_a = Vec3(0.0, 0.0, 0.3);
  CHECK(m.h(x)(0) == doctest::Approx(-lift + 0.3).epsilon(0.01));
  CHECK(m.applicable(x, NormalForce::Vec(0.0)));
  x.v = Vec3(5.0, 0.0, 0.0);  // below the minimum airspeed: the wheels may carry the weight
  CHECK_FALSE(m.applicable(x, NormalForce::Vec(0.0)));
  m.k = 0.0;  // no aircraft model: never applicable
  x.v = Vec3(17.0, 0.0, 0.0);
  CHECK_FALSE(m.applicable(x, NormalForce::Vec(0.0)));
}

TEST_CASE("side force: h is the lateral aerodynamic force over the mass, plus the accelerometer bias") {
  SideForce m;
  m.k = 1.2682 * 0.52 / (2.0 * 4.5);
  m.C_Y_beta = -0.98;
  NominalState x;  // level, heading north, 17 m/s air-relative with 1 m/s from the right
  x.v = Vec3(17.0, 0.0, 0.0);
  x.wind = Eigen::Vector2d(0.0, -1.0);  // blowing to the west: the air comes at the aircraft from its right
  // v_r = +1 m/s (air velocity relative to the body, body y): beta = asin(1 / Va) > 0
  const double Va = std::hypot(17.0, 1.0), beta = std::asin(1.0 / Va);
  const double exact = 0.5 * 1.2682 * Va * Va * 0.52 * -0.98 * beta / 4.5;
  CHECK(m.h(x)(0) == doctest::Approx(exact).epsilon(0.01));
  x.b_a = Vec3(0.0, 0.2, 0.0);
  CHECK(m.h(x)(0) == doctest::Approx(exact + 0.2).epsilon(0.01));
  m.k = 0.0;  // no aircraft model: never applicable
  CHECK_FALSE(m.applicable(x, SideForce::Vec(0.0)));
}

TEST_CASE("transition matrix matches finite differences of the nominal propagation") {
  const NominalState x = sample_state();
  const Vec3 accel(1.5, -0.8, -11.0), gyro(0.3, -0.2, 0.25);
  const double dt = 0.0025, g = 9.81;
  ProcessNoise k;
  k.gnss_error_k = 0.01;
  const Cov F = Filter::transition(x, accel, gyro, dt, k);
  const NominalState x1 = Filter::propagate_nominal(x, accel, gyro, dt, g, k);
  const double eps = 1e-6;
  for (int i = 0; i < kErrDim; ++i) {
    ErrVec d = ErrVec::Zero();
    d(i) = eps;
    const ErrVec num = (boxminus(Filter::propagate_nominal(boxplus(x, d), accel, gyro, dt, g, k), x1) -
                        boxminus(Filter::propagate_nominal(boxplus(x, -d), accel, gyro, dt, g, k), x1)) /
                       (2 * eps);
    for (int r = 0; r < kErrDim; ++r) {
      INFO("row " << r << " column " << i);
      // F is first order in dt: the neglected terms are O(dt^2 |a|) ~ 1e-4.
      CHECK(std::fabs(F(r, i) - num(r)) <= 2e-4 * std::max(1.0, std::fabs(num(r))));
    }
  }
}

TEST_CASE("the gyro sensitivity error: the body rate it gives and the attitude uncertainty it adds in proportion to the rate") {
  NominalState x;
  x.b_g = Vec3(0.01, 0.0, 0.0);
  x.S_g(1, 2) = 0.02;  // 2 % of the z rate read on y
  CHECK((x.rate(Vec3(0.01, 0.02, 1.0)) - Vec3(0.0, 0.0, 1.0)).norm() == doctest::Approx(0.0));
  // A yaw rate of 1 rad/s held 1 s with S_g(1, 2) 0.02 rad uncertain: 0.02 rad of pitch sigma.
  Filter f;
  Cov P0 = Cov::Identity() * 1e-12;
  P0(idx::sg + 5, idx::sg + 5) = 0.02 * 0.02;
  f.initialize(NominalState{}, P0);
  ProcessNoise qn;
  qn.gyro = 0.0;
  qn.gyro_bias_walk = qn.gyro_scale_walk = 0.0;
  for (int k = 0; k < 400; ++k) f.propagate(Vec3(0.0, 0.0, -9.81), Vec3(0.0, 0.0, 1.0), 0.0025, qn, 9.81);
  // The attitude error rotates with the body (Exp(-w dt)): its variance moves between x and y.
  const double tilt = std::sqrt(f.P()(idx::th, idx::th) + f.P()(idx::th + 1, idx::th + 1));
  CHECK(tilt == doctest::Approx(0.02).epsilon(0.01));
  CHECK(f.P()(idx::th + 2, idx::th + 2) < 1e-10);
  // still: nothing grows
  Filter g;
  g.initialize(NominalState{}, P0);
  for (int k = 0; k < 400; ++k) g.propagate(Vec3(0.0, 0.0, -9.81), Vec3::Zero(), 0.0025, qn, 9.81);
  CHECK(g.P()(idx::th + 1, idx::th + 1) < 1e-10);
}

TEST_CASE("the accelerometer scale error adds velocity noise in proportion to the load beyond level 1 g") {
  ProcessNoise qn;
  qn.accel_scale = 0.02;
  qn.maneuver_time = 1.0;
  const double dt = 0.0025;
  const double level = Filter::process_noise_diagonal(qn, dt, 0.0)(idx::v);
  const double two_g = Filter::process_noise_diagonal(qn, dt, 9.81)(idx::v);
  CHECK(level == doctest::Approx(qn.accel * qn.accel * dt * dt));
  // one extra g held 1 s with a 2 % error: 0.196 m/s of velocity uncertainty after 1 s.
  CHECK((two_g - level) / dt == doctest::Approx(0.02 * 0.02 * 9.81 * 9.81));
  CHECK(Filter::process_noise_diagonal(qn, dt, 9.81)(idx::th) == Filter::process_noise_diagonal(qn, dt, 0.0)(idx::th));
  // propagate() measures the load from the bias-corrected specific force (down velocity: no
  // attitude coupling for a force along z, the bias block adds dt^2 P_ba)
  Filter f;
  NominalState x;
  x.b_a = Vec3(0.0, 0.0, 0.5);
  f.initialize(x, Cov::Identity() * 1e-4);
  f.propagate(Vec3(0.0, 0.0, -2 * 9.81 + 0.5), Vec3::Zero(), dt, qn, 9.81);
  CHECK(f.P()(idx::v + 2, idx::v + 2) == doctest::Approx(1e-4 + dt * dt * 1e-4 + two_g).epsilon(1e-12));
}

TEST_CASE("block-wise propagation equals F P F^T + Q and keeps P symmetric") {
  Filter f;
  const NominalState x = sample_state();
  const Cov P0 = random_spd(3);
  f.initialize(x, P0);
  const Vec3 accel(1.5, -0.8, -11.0), gyro(0.3, -0.2, 0.25);
  ProcessNoise qn;
  qn.position = 0.01;
  const double dt = 0.0025;
  f.propagate(accel, gyro, dt, qn, 9.81);
  const Cov F = Filter::transition(x, accel, gyro, dt, qn);
  Cov expected = F * P0 * F.transpose();
  expected.diagonal() += Filter::process_noise_diagonal(qn, dt, (accel - x.b_a - Vec3(0, 0, -9.81)).norm());
  CHECK((f.P() - expected).cwiseAbs().maxCoeff() < 1e-12 * expected.cwiseAbs().maxCoeff());
  CHECK((f.P() - f.P().transpose()).cwiseAbs().maxCoeff() == 0.0);
  const NominalState xn = Filter::propagate_nominal(x, accel, gyro, dt, 9.81, qn);
  CHECK((f.x().p - xn.p).norm() == 0.0);
}

TEST_CASE("covariance period: the samples' transitions in one step, to second order in the period") {
  // Four 400-Hz samples in a turn with a pull-up: one covariance step (period 10 ms) against a
  // step per sample (period 0). The nominal state is the same; the covariance differs by the
  // blocks the period leaves out (second order in T, filter.hpp).
  const NominalState x = sample_state();
  const Cov P0 = random_spd(5);
  ProcessNoise qn;
  qn.position = 0.01;
  Filter each, period;
  each.initialize(x, P0);
  period.initialize(x, P0);
  period.set_covariance_period(0.01);
  const Vec3 gyro(0.8, -0.3, 0.5);
  for (int k = 0; k < 4; ++k) {
    const Vec3 accel(1.5, -0.8 + 0.1 * k, -14.0);
    CHECK(each.propagate(accel, gyro, 0.0025, qn, 9.81));
    CHECK(period.propagate(accel, gyro, 0.0025, qn, 9.81) == (k == 3));  // stepped with the fourth
  }
  CHECK((period.x().q.coeffs() - each.x().q.coeffs()).norm() == 0.0);
  const double scale = each.P().cwiseAbs().maxCoeff();
  // the p and v rows and columns by the blocks left out: Phi_p,theta ~ 0.5 T^2 R [a]x, 7e-4 here
  CHECK((period.P() - each.P()).cwiseAbs().maxCoeff() < 5e-4 * scale);
  CHECK((period.P() - period.P().transpose()).cwiseAbs().maxCoeff() == 0.0);
  // Phi_theta,X is kept exactly: the attitude's covariances with everything but p and v agree to rounding
  const int n = kErrDim - idx::th;
  CHECK((period.P().block<3, n>(idx::th, idx::th) - each.P().block<3, n>(idx::th, idx::th)).cwiseAbs().maxCoeff() < 1e-12 * scale);
  // an update steps the pending samples first: after one sample it sees what period 0 sees
  Filter one, pending;
  one.initialize(x, P0);
  pending.initialize(x, P0);
  pending.set_covariance_period(0.01);
  CHECK(one.propagate(Vec3(0.0, 0.0, -9.81), gyro, 0.0025, qn, 9.81));
  CHECK_FALSE(pending.propagate(Vec3(0.0, 0.0, -9.81), gyro, 0.0025, qn, 9.81));
  CHECK((pending.P() - P0).cwiseAbs().maxCoeff() == 0.0);  // not stepped yet
  BaroAltitude a, b;
  a.gate = b.gate = 0.0;
  CHECK(one.update(a, BaroAltitude::Vec(0.3)) == UpdateResult::accepted);
  CHECK(pending.update(b, BaroAltitude::Vec(0.3)) == UpdateResult::accepted);
  CHECK((pending.P() - one.P()).cwiseAbs().maxCoeff() < 1e-12 * one.P().cwiseAbs().maxCoeff());
}

TEST_CASE("covariance: exactly symmetric after updates, and after a reset's edit once stepped") {
  Filter f;
  Cov P0 = Cov::Identity();
  P0(idx::th, idx::v) = P0(idx::v, idx::th) = 0.3;
  f.initialize(sample_state(), P0);
  f.set_covariance_period(0.01);
  ProcessNoise qn;
  MagHeading h;  // 1 dof
  h.gate = 0.0;
  GnssVelocity gv;  // 3 dof
  gv.gate = 0.0;
  const auto exactly_symmetric = [&] { return (f.P() - f.P().transpose()).cwiseAbs().maxCoeff() == 0.0; };
  for (int k = 0; k < 8; ++k) f.propagate(Vec3(1.5, -0.8, -14.0), Vec3(0.8, -0.3, 0.5), 0.0025, qn, 9.81);
  CHECK(f.update(h, MagHeading::Vec(0.2)) == UpdateResult::accepted);
  CHECK(exactly_symmetric());
  CHECK(f.update(gv, Vec3(f.x().v + Vec3(0.3, -0.2, 0.1))) == UpdateResult::accepted);
  CHECK(exactly_symmetric());
  // a reset edits P through mutable_P(), one triangle off by more than an ulp
  f.mutable_P()(idx::bg, idx::bm) += 1e-9;  // states the step moves neither of
  CHECK_FALSE(exactly_symmetric());
  for (int k = 0; k < 4; ++k) f.propagate(Vec3(1.5, -0.8, -14.0), Vec3(0.8, -0.3, 0.5), 0.0025, qn, 9.81);
  CHECK(exactly_symmetric());  // the step symmetrised it first
}

TEST_CASE("update: Joseph form, variance shrinks, gate rejects and counts outliers") {
  Filter f;
  NominalState x = sample_state();
  Cov P = Cov::Identity();
  f.initialize(x, P);
  GnssVelocity m;
  m.sigma_h = 1.0;
  m.sigma_v = 1.0;
  const Vec3 z = x.v + Vec3(0.5, -0.5, 0.2);
  CHECK(f.update(m, z) == UpdateResult::accepted);
  // Scalar case: posterior variance 1*1/(1+1) = 0.5, state moves half-way.
  CHECK(f.P()(idx::v, idx::v) == doctest::Approx(0.5));
  CHECK(f.x().v.x() == doctest::Approx(x.v.x() + 0.25));
  CHECK(Eigen::LLT<Cov>(f.P()).info() == Eigen::Success);
  CHECK((f.P() - f.P().transpose()).norm() == 0.0);
  // A 100 m outlier: NIS = 100^2 / 1.5 >> 16.3.
  const NominalState before = f.x();
  CHECK(f.update(m, Vec3(f.x().v + Vec3(100.0, 0.0, 0.0))) == UpdateResult::rejected);
  CHECK(m.stats.rejected == 1);
  CHECK(m.stats.accepted == 1);
  CHECK(m.stats.last_nis > 1000.0);
  CHECK((f.x().v - before.v).norm() == 0.0);
  // Non-finite measurement: refused before anything is computed.
  CHECK(f.update(m, Vec3(NAN, 0.0, 0.0)) == UpdateResult::invalid);
  CHECK(m.stats.invalid == 1);
  CHECK(f.x().all_finite());
  // Gate 0 disables gating.
  m.gate = 0.0;
  CHECK(f.update(m, Vec3(f.x().v + Vec3(100.0, 0.0, 0.0))) == UpdateResult::accepted);
}

TEST_CASE("magnetic heading: the levelling's tilt error is heading noise, tan(I) times the roll error towards magnetic north") {
  MagHeading m;
  const double D = m.declination, I = m.inclination;
  // level, pointing at magnetic north: the field in body axes is (cos I, 0, sin I)
  const Vec3 field(std::cos(I), 0.0, std::sin(I));
  CHECK(MagHeading::heading_from_field(field, 0.0, 0.0, D) == doctest::Approx(D));
  const Mat3 P = Vec3(0.01 * 0.01, 0.01 * 0.01, 0.05 * 0.05).asDiagonal();  // yaw's own does not count
  CHECK(MagHeading::tilt_variance_of(field, 0.0, 0.0, P) == doctest::Approx(std::pow(std::tan(I) * 0.01, 2)).epsilon(1e-4));
  CHECK(MagHeading::tilt_variance_of(field, 0.0, 0.0, Mat3::Zero()) == 0.0);
  const NominalState x;
  m.tilt_variance = 0.0;
  const double r0 = m.noise(x)(0, 0);
  m.tilt_variance = 0.02;
  CHECK(m.noise(x)(0, 0) == doctest::Approx(r0 + 0.02));
}

TEST_CASE("limit_variance caps a variance, keeps the correlations and the positive definiteness") {
  Filter f;
  f.initialize(sample_state(), random_spd(11) * 30.0);
  const Cov P0 = f.P();
  const int i = idx::w;
  const double cap = 0.5 * P0(i, i);
  f.limit_variance(idx::w, 2, cap);
  const Cov& P = f.P();
  CHECK(P(i, i) == doctest::Approx(cap));
  CHECK(P(i + 1, i + 1) == doctest::Approx(std::min(P0(i + 1, i + 1), cap)));  // capped only if above
  const auto corr = [](const Cov& C, int a, int b) { return C(a, b) / std::sqrt(C(a, a) * C(b, b)); };
  CHECK(corr(P, i, idx::v) == doctest::Approx(corr(P0, i, idx::v)).epsilon(1e-12));
  CHECK(P(idx::v, idx::v) == P0(idx::v, idx::v));
  CHECK(Eigen::LLT<Cov>(P).info() == Eigen::Success);
  f.limit_variance(idx::w, 2, 1e9);  // below the cap: untouched
  CHECK(f.P() == P);
}

TEST_CASE("pitot airspeed: from a wind estimate far off, one update moves u_r towards the measurement, never past it") {
  // The pressure form 0.5 rho u_r^2 linearised at u_r = 3 m/s overshoots a 9-m/s measurement;
  // in airspeed the model is linear in u_r and a confident update lands on it.
  for (double u0 : {3.0, -9.0}) {
    NominalState x;
    x.q = Eigen::Quaterniond::Identity();
    x.v = Vec3(u0, 0.0, 0.0);  // no wind estimate: u_r = u0 (negative: the tailwind mirror)
    Cov P = Cov::Identity() * 1e-6;
    P.block<2, 2>(idx::w, idx::w) = Eigen::Matrix2d::Identity() * 100.0;
    Filter f;
    f.initialize(x, P);
    PitotAirspeed pitot;
    pitot.gate = 0.0;
    REQUIRE(f.update(pitot, PitotAirspeed::Vec(9.0)) == UpdateResult::accepted);
    const double u_r = f.x().air_velocity_body().x();
    INFO("u0 " << u0 << " -> u_r " << u_r);
    CHECK(u_r > 8.5);
    CHECK(u_r <= 9.0 + 1e-9);
  }
}

TEST_CASE("pitot and sideslip apply only above the minimum airspeed") {
  Filter f;
  NominalState x = sample_state();
  f.initialize(x, Cov::Identity() * 0.01);
  PitotAirspeed pitot;
  pitot.min_airspeed = 8.0;
  CHECK(f.update(pitot, PitotAirspeed::Vec(pitot.airspeed(0.5 * 1.225 * 5.0 * 5.0))) == UpdateResult::skipped);
  CHECK(pitot.stats.skipped == 1);
  ZeroSideslip beta;
  x.v = x.wind_ned() + Vec3(1.0, 1.0, 0.0);  // 1.4 m/s airspeed
  f.initialize(x, Cov::Identity() * 0.01);
  CHECK(f.update(beta, ZeroSideslip::Vec(0.0)) == UpdateResult::skipped);
}

TEST_CASE("a delayed update with the state of its time equals the update made then") {
  // A GNSS position valid at t0 fused at t0 (then 25 ms of propagation and a barometer
  // update), or fused at t1 = t0 + 25 ms with the state of t0 and the corrections since:
  // the same estimate at t1. Taken as current instead, the fix pulls the position back by the
  // 0.4 m flown in those 25 ms.
  const ProcessNoise noise;
  ErrVec var;             // a converged filter's variances: little correlation yet
  var.setConstant(1e-4);  // the sensitivities
  var.head<21>() << 4, 4, 9, 0.04, 0.04, 0.04, 1e-4, 1e-4, 1e-3, 1e-6, 1e-6, 1e-6, 1e-3, 1e-3, 1e-3, 1, 1, 1, 2, 2, 4;
  const NominalState x0 = sample_state();
  const GnssPosition::Vec z = x0.p + x0.e_gnss + Vec3(3.0, -2.0, 1.0);
  const Vec3 accel(0.3, -0.1, -9.7), gyro(0.02, 0.05, -0.1);
  const auto propagate_and_baro = [&](Filter& f) {
    for (int i = 0; i < 10; ++i) f.propagate(accel, gyro, 0.0025, noise, 9.81);
    BaroAltitude baro;
    baro.gate = 0.0;
    baro.sigma = 2.0;
    f.update(baro, BaroAltitude::Vec(-x0.p.z() + 0.5));
  };
  GnssPosition gnss;
  gnss.gate = 0.0;

  Filter at_t0;
  at_t0.initialize(x0, Cov(var.asDiagonal()));
  REQUIRE(at_t0.update(gnss, z) == UpdateResult::accepted);
  propagate_and_baro(at_t0);

  Filter delayed;
  delayed.initialize(x0, Cov(var.asDiagonal()));
  const NominalState x_then = delayed.x();
  const ErrVec sum_then = delayed.correction_sum();
  propagate_and_baro(delayed);
  Filter naive = delayed;
  const ErrVec since = delayed.correction_sum() - sum_then;
  REQUIRE(delayed.update(gnss, z, &x_then, &since) == UpdateResult::accepted);
  naive.update(gnss, z);

  const double err_delayed = (delayed.x().p - at_t0.x().p).norm();
  const double err_naive = (naive.x().p - at_t0.x().p).norm();
  CHECK(err_delayed < 0.02);
  CHECK(err_naive > 0.2);
  CHECK((delayed.x().v - at_t0.x().v).norm() < 0.01);
}

TEST_CASE("covariance inflation adds independent variance: fusing p + e afterwards does not teach e") {
  Filter f;
  f.initialize(sample_state(), random_spd(5));
  const Cov P0 = f.P();
  f.inflate(idx::p, 3, 4.0);
  CHECK(f.P()(idx::p, idx::p) == doctest::Approx(4.0 * P0(idx::p, idx::p)));
  CHECK(f.P()(idx::p + 1, idx::p) == P0(idx::p + 1, idx::p));
  CHECK(f.P()(idx::p, idx::v) == P0(idx::p, idx::v));
  CHECK(f.P()(idx::v, idx::v) == P0(idx::v, idx::v));
  CHECK(Eigen::LLT<Cov>(f.P()).info() == Eigen::Success);
  // capped: no variance beyond the square of its axis's innovation, none lowered
  const Cov P1 = f.P();
  const double cap[3] = {2.0 * P1(idx::p, idx::p), 0.5 * P1(idx::p + 1, idx::p + 1), 1e9};
  f.inflate(idx::p, 3, 4.0, cap);
  CHECK(f.P()(idx::p, idx::p) == doctest::Approx(cap[0]));
  CHECK(f.P()(idx::p + 1, idx::p + 1) == P1(idx::p + 1, idx::p + 1));
  CHECK(f.P()(idx::p + 2, idx::p + 2) == doctest::Approx(4.0 * P1(idx::p + 2, idx::p + 2)));
  // GNSS-like structure: p = z0 - e, var(e) = 1, corr(p, e) = -0.999. Inflate p x25, then fuse
  // z = p + e (sigma 0.1): var(e) must stay near 1 (nothing measures e alone).
  Cov P = Cov::Identity() * 1e-2;
  P.block<3, 3>(idx::p, idx::p) = Mat3::Identity();
  P.block<3, 3>(idx::eg, idx::eg) = Mat3::Identity();
  P.block<3, 3>(idx::p, idx::eg) = P.block<3, 3>(idx::eg, idx::p) = -0.999 * Mat3::Identity();
  Filter g;
  g.initialize(sample_state(), P);
  g.inflate(idx::p, 3, 25.0);
  const Eigen::Matrix<double, 3, kErrDim> H = [] {
    Eigen::Matrix<double, 3, kErrDim> h = Eigen::Matrix<double, 3, kErrDim>::Zero();
    h.block<3, 3>(0, idx::p) = Mat3::Identity();
    h.block<3, 3>(0, idx::eg) = Mat3::Identity();
    return h;
  }();
  const Cov& Pi = g.P();
  const Eigen::Matrix3d S = H * Pi * H.transpose() + 0.01 * Mat3::Identity();
  const Cov post = Pi - Pi * H.transpose() * S.inverse() * H * Pi;
  CHECK(post(idx::eg, idx::eg) > 0.9);
}

TEST_CASE("the covariance kernels: the same numbers as Eigen's expressions, bit for bit, at every dimension") {
  // downdate() and P_times_Ht() run as plain loops, built also for AVX (filter.cpp): every element
  // must take the same operations in the same order as the expressions they replace, or a flight
  // would depend on the machine's vector width.
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01;
  Cov P;
  for (int j = 0; j < kErrDim; ++j)
    for (int i = 0; i < kErrDim; ++i) P(i, j) = n01(rng);
  Eigen::Matrix<double, kErrDim, 3> Wt;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < kErrDim; ++i) Wt(i, j) = n01(rng);
  for (int M = 1; M <= 3; ++M) {
    Cov expected = P;
    for (int j = 0; j < kErrDim; ++j)
      for (int m = 0; m < M; ++m) expected.col(j) -= Wt(j, m) * Wt.col(m);
    Cov got = P;
    downdate(got, Wt.data(), M);
    CHECK(got == expected);
  }
  Eigen::Matrix<double, 3, kErrDim> H = Eigen::Matrix<double, 3, kErrDim>::Zero();
  for (int k : {0, 4, 6, 7, 15, 20, 31, 34}) H.col(k) = Vec3(n01(rng), 0.0, n01(rng));  // zeros too, as a model's
  Eigen::Matrix<double, kErrDim, 3> expected = Eigen::Matrix<double, kErrDim, 3>::Zero();
  for (int k = 0; k < kErrDim; ++k)
    for (int m = 0; m < 3; ++m)
      if (H(m, k) != 0.0) expected.col(m) += H(m, k) * P.col(k);
  Eigen::Matrix<double, kErrDim, 3> got;
  P_times_Ht(P, H.data(), 3, got.data());
  CHECK(got == expected);
}

TEST_CASE("all_finite: a NaN, an infinity or an overflowing sum anywhere in P") {
  Cov P = Cov::Identity();
  CHECK(all_finite(P));
  for (const auto& [i, j] : {std::pair{0, 0}, std::pair{17, 3}, std::pair{34, 34}}) {
    Cov bad = P;
    bad(i, j) = std::numeric_limits<double>::quiet_NaN();
    CHECK_FALSE(all_finite(bad));
    bad(i, j) = -std::numeric_limits<double>::infinity();
    CHECK_FALSE(all_finite(bad));
  }
  Cov huge = P;
  huge(3, 5) = huge(5, 3) = std::numeric_limits<double>::max();
  CHECK_FALSE(all_finite(huge));  // finite elements whose sum is not: unhealthy too
}
