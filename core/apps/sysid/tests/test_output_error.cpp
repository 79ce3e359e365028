// The output-error refinement (sysid/output_error.hpp) on rates its own model generates from known
// coefficients, the Aerosonde's inertia and geometry: flow angles, airspeed and surfaces as
// multisines, the rates measured with coloured noise (first-order, 0.4 s correlation). Started from
// wrong values the fit must converge to the truth within its bounds, the coloured-residual bound
// must exceed the white one, and noise-free data must give the truth back exactly.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "sysid/output_error.hpp"
#include "tern/math.hpp"

namespace {

using tern::AeroCoefficients;
using tern::core::sysid::output_error;
using tern::core::sysid::OutputErrorFit;
using tern::core::sysid::OutputErrorOptions;
using tern::core::sysid::RateAxes;
using tern::core::sysid::RateData;

tern::Aircraft aerosonde() { return tern::load_aircraft(TERN_AIRCRAFT_DIR "/aerosonde.yaml"); }

/// A multisine of the harmonics k0, k0 + 3, ... of 1/20 Hz (disjoint sets for k0 = 1, 2, 3), rms ~ amplitude / 2.
double multisine(double t, int k0, double amplitude) {
  double s = 0.0;
  for (int k = k0; k <= 36; k += 3) s += std::sin(2.0 * tern::kPi * k * t / 20.0 + tern::kPi * k * k / 36.0);
  return amplitude * s / 4.0;
}

/// 200 s at 50 Hz: the rates the model gives with `truth` over one stretch, plus AR(1) noise of
/// standard deviation `noise` (rad/s), then cut into windows of 5 s.
RateData synthetic(const tern::Aircraft& ac, const AeroCoefficients& truth, RateAxes axes, double noise, unsigned seed) {
  RateData d;
  for (int k = 0; k < 10000; ++k) {
    const double t = 0.02 * k;
    d.t.push_back(t);
    d.Va.push_back(22.0 + 3.0 * std::sin(2.0 * tern::kPi * t / 70.0));
    d.alpha.push_back(0.04 + multisine(t, 1, 0.03));
    d.beta.push_back(multisine(t, 2, 0.03));
    d.delta_a.push_back(multisine(t, 3, 0.05));
    d.delta_e.push_back(-0.05 + multisine(t, 2, 0.06));
    d.delta_r.push_back(multisine(t, 1, 0.06));
    d.Q_p.push_back(0.0);
    d.p.push_back(0.0), d.q.push_back(0.0), d.r.push_back(0.0);
  }
  d.windows = {{0, d.size()}};
  const std::vector<Eigen::Vector3d> w = tern::core::sysid::simulate_rates(d, ac, truth, axes);
  std::mt19937 rng(seed);
  std::normal_distribution<double> white(0.0, 1.0);
  const double a = 0.95;  // 0.02 s / 0.4 s correlation time
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < d.size(); ++k) {
    n = a * n + noise * std::sqrt(1.0 - a * a) * Eigen::Vector3d(white(rng), white(rng), white(rng));
    d.p[k] = w[k].x() + n.x(), d.q[k] = w[k].y() + n.y(), d.r[k] = w[k].z() + n.z();
  }
  d.windows.clear();
  for (std::size_t b = 0; b < d.size(); b += 250) d.windows.emplace_back(b, std::min(b + 250, d.size()));
  return d;
}

const std::vector<std::string> kLateral = {"C_ell_0",  "C_ell_beta", "C_ell_p", "C_ell_r",     "C_ell_delta_a", "C_n_0",
                                           "C_n_beta", "C_n_p",      "C_n_r",   "C_n_delta_a", "C_n_delta_r"};
const std::vector<std::string> kPitch = {"C_m_0", "C_m_alpha", "C_m_q", "C_m_delta_e"};

/// The truth with the named coefficients scaled by `factor` (and a bias term, zero in the truth, moved).
AeroCoefficients scaled(const AeroCoefficients& truth, const std::vector<std::string>& names, double factor) {
  AeroCoefficients a = truth;
  for (const auto& n : names) a.*tern::core::sysid::moment_coefficient(n) *= factor;
  a.C_ell_0 += 0.002, a.C_n_0 -= 0.002, a.C_m_0 += 0.01;
  return a;
}

void check_recovered(const OutputErrorFit& f, const AeroCoefficients& truth, double max_relative) {
  for (std::size_t j = 0; j < f.names.size(); ++j) {
    const auto J = static_cast<Eigen::Index>(j);
    const double true_value = truth.*tern::core::sysid::moment_coefficient(f.names[j]);
    CAPTURE(f.names[j]);
    CAPTURE(f.theta[J]);
    CAPTURE(f.std_error[J]);
    CAPTURE(true_value);
    CHECK(std::abs(f.theta[J] - true_value) <= 3.0 * f.std_error[J]);
    CHECK(f.std_error[J] >= f.std_error_white[J]);
    if (std::abs(true_value) > 0.05) CHECK(std::abs(f.theta[J] - true_value) <= max_relative * std::abs(true_value));
  }
}

}  // namespace

TEST_CASE("output error: roll and yaw from a start off by 0.6, coloured noise, converge within the bounds") {
  const tern::Aircraft ac = aerosonde();
  const RateData d = synthetic(ac, ac.aero, RateAxes::lateral, 0.01, 7);
  const OutputErrorFit f = output_error(d, ac, scaled(ac.aero, kLateral, 0.6), RateAxes::lateral, kLateral, {});
  check_recovered(f, ac.aero, 0.05);
  CHECK(f.rms[0] < f.rms_start[0]);
  CHECK(f.rms[1] < f.rms_start[1]);
  // the residuals are the AR(1) noise (0.01 rad/s), not model error
  CHECK(f.rms[0] == doctest::Approx(0.01).epsilon(0.3));
  // 0.4 s of correlation: the white bound understates the scatter, the coloured one must not
  const Eigen::VectorXd ratio = f.std_error.cwiseQuotient(f.std_error_white);
  CHECK(ratio.maxCoeff() > 1.5);
}

TEST_CASE("output error: pitch from a start off by 1.5 converges within the bounds") {
  const tern::Aircraft ac = aerosonde();
  const RateData d = synthetic(ac, ac.aero, RateAxes::pitch, 0.005, 11);
  const OutputErrorFit f = output_error(d, ac, scaled(ac.aero, kPitch, 1.5), RateAxes::pitch, kPitch, {});
  check_recovered(f, ac.aero, 0.05);
  CHECK(f.relaxations >= 1);
  CHECK(f.residual_covariance(0, 0) == doctest::Approx(0.005 * 0.005).epsilon(0.5));
}

TEST_CASE("output error: noise-free rates give the truth back exactly") {
  const tern::Aircraft ac = aerosonde();
  const RateData d = synthetic(ac, ac.aero, RateAxes::lateral, 0.0, 1);
  AeroCoefficients start = ac.aero;
  start.C_ell_p *= 1.4, start.C_ell_delta_a *= 0.6, start.C_n_r *= 0.7, start.C_n_delta_r *= 1.5;
  const std::vector<std::string> some = {"C_ell_p", "C_ell_delta_a", "C_n_r", "C_n_delta_r"};
  const OutputErrorFit f = output_error(d, ac, start, RateAxes::lateral, some, {});
  for (std::size_t j = 0; j < some.size(); ++j) {
    CAPTURE(some[j]);
    CHECK(f.theta[static_cast<Eigen::Index>(j)] == doctest::Approx(ac.aero.*tern::core::sysid::moment_coefficient(some[j])).epsilon(1e-4));
  }
}

TEST_CASE("output error: names outside the axes' moments and empty windows are one clear error") {
  const tern::Aircraft ac = aerosonde();
  RateData d = synthetic(ac, ac.aero, RateAxes::pitch, 0.0, 1);
  CHECK_THROWS_WITH_AS(output_error(d, ac, ac.aero, RateAxes::pitch, {"C_L_alpha"}, {}), doctest::Contains("not a moment coefficient"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(output_error(d, ac, ac.aero, RateAxes::lateral, {"C_m_q"}, {}), doctest::Contains("lateral"), std::invalid_argument);
  d.windows = {{0, 2}};
  CHECK_THROWS_AS(output_error(d, ac, ac.aero, RateAxes::pitch, {"C_m_q"}, {}), std::invalid_argument);
}

TEST_CASE("output error: a command shifted by a fraction of a sample keeps its amplitude up to 0.4 of the Nyquist frequency") {
  // 50-Hz samples of 2.5-, 5- and 10-Hz sinusoids shifted by 0.35 of a sample (7 ms): within 0.4 %
  // of the sinusoid 7 ms late up to 5 Hz and 0.8 % at 10 Hz, away from the run's ends. Linear
  // interpolation between samples, the former shift, is 1.4, 5 and 17 % off (the amplitude
  // |0.65 + 0.35 e^(-j 2 pi f T)|).
  const double tau = 0.007;
  for (const double hz : {2.5, 5.0, 10.0}) {
    std::vector<double> t, x, out(400);
    for (int k = 0; k < 400; ++k) t.push_back(0.02 * k), x.push_back(std::sin(2.0 * tern::kPi * hz * t.back() + 0.3));
    tern::core::sysid::shift_run(t, x, tau, 0, t.size(), out);
    double worst = 0.0;
    for (std::size_t k = 10; k + 10 < t.size(); ++k)
      worst = std::max(worst, std::abs(out[k] - std::sin(2.0 * tern::kPi * hz * (t[k] - tau) + 0.3)));
    CAPTURE(hz);
    CHECK(worst < (hz < 6.0 ? 0.004 : 0.008));
    // a whole number of samples is an exact copy, a constant stays constant
    tern::core::sysid::shift_run(t, x, 0.04, 0, t.size(), out);
    CHECK(out[100] == doctest::Approx(x[98]).epsilon(1e-12));
  }
  std::vector<double> t = {0.0, 0.02, 0.04, 0.06, 0.08}, one(5, 1.0), out(5);
  tern::core::sysid::shift_run(t, one, 0.013, 0, 5, out);
  for (const double v : out) CHECK(v == doctest::Approx(1.0).epsilon(1e-12));
  // a run whose times stand still, a delay that is not a number: one clear error, not a wild index
  const std::vector<double> still(5, 1.0);
  CHECK_THROWS_AS(tern::core::sysid::shift_run(still, one, 0.013, 0, 5, out), std::invalid_argument);
  CHECK_THROWS_AS(tern::core::sysid::shift_run(t, one, std::nan(""), 0, 5, out), std::invalid_argument);
}

TEST_CASE("output error: a sideslip reconstructed from the side force moves its rudder part with the rudder's delay") {
  // beta as sysid reconstructs it from the side force carries -C_Y_delta_r / C_Y_beta of the
  // rudder at the series' timing. The rates simulated with the rudder acting 12 ms late, in the
  // moments and in beta alike, noise-free; the fit frees the rudder's delay and C_n_delta_r. With
  // beta_per_delta_r the shifted rudder's part of beta moves too and both come back; without it
  // the fit found the delay at -1.2 ms (C_n_beta times the rudder's part of beta, pinned at the
  // stamps, outweighed the shift of C_n_delta_r's).
  const tern::Aircraft ac = aerosonde();
  const double delay = 0.012, per_rudder = -ac.aero.C_Y_delta_r / ac.aero.C_Y_beta;
  RateData late = synthetic(ac, ac.aero, RateAxes::lateral, 0.0, 1);
  RateData d = late;
  for (std::size_t k = 0; k < late.size(); ++k) {
    const double t = late.t[k];
    late.delta_r[k] = multisine(t - delay, 1, 0.06);
    late.beta[k] = d.beta[k] + per_rudder * late.delta_r[k];
    d.beta[k] += per_rudder * d.delta_r[k];  // the series as loaded: the rudder's part at its stamps
  }
  const std::vector<Eigen::Vector3d> w = tern::core::sysid::simulate_rates(late, ac, ac.aero, RateAxes::lateral);
  for (std::size_t k = 0; k < d.size(); ++k) d.p[k] = w[k].x(), d.q[k] = w[k].y(), d.r[k] = w[k].z();
  d.beta_per_delta_r = per_rudder;
  const OutputErrorFit f = output_error(d, ac, ac.aero, RateAxes::lateral, {"C_n_delta_r", "delay_r"}, {});
  CHECK(f.theta[1] == doctest::Approx(delay).epsilon(0.01));
  CHECK(f.theta[0] == doctest::Approx(ac.aero.C_n_delta_r).epsilon(0.002));
}
