// The instrumentation-error parameters beside the drag polar (sysid/instrumentation.hpp): a pitot
// reading 4 % slow and an accelerometer with a 0.07 m/s^2 x bias, on synthetic trim at three
// airspeeds in a steady wind. The wind triangle must give the pitot's scale, and the polar, with
// the dynamic pressure corrected by it, C_D_p, e and the bias, each within 3 of its reported
// standard errors; at one airspeed on one heading neither the scale nor the bias is identifiable.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "sysid/identify_lateral.hpp"
#include "sysid/instrumentation.hpp"
#include "sysid/pitot_scale_share.hpp"
#include "tern/math.hpp"

namespace {

using tern::core::sysid::FlightSeries;
using tern::core::sysid::PolarWindow;

constexpr double kRho = 1.2682, kMass = 13.5, kS = 0.55, kAR = 2.8956 * 2.8956 / 0.55;
constexpr double kScale = 1.04;  // Va_true = kScale Va_pitot
constexpr double kBias = 0.07;   // m/s^2, accelerometer x
constexpr double kCDp = 0.012, kE = 0.8;
constexpr double kWindN = 4.0, kWindE = -3.0;

/// `seconds` of level flight at Va (true) at 50 Hz, turning at `turn_rate` rad/s, in the wind above;
/// the pitot reads Va / kScale, the ground velocity carries 0.3 m/s of gust-like noise.
void fly(double Va, double seconds, double turn_rate, std::mt19937& rng, FlightSeries& s) {
  std::normal_distribution<double> gust(0.0, 0.3);
  const double alpha = 0.05 - 0.002 * (Va - 20.0), t0 = s.t.empty() ? 0.0 : s.t.back() + 0.02;
  for (double t = 0.0; t < seconds; t += 0.02) {
    const double psi = turn_rate * t;
    const Eigen::Matrix3d R = tern::rotation_from_euler(0.0, alpha, psi);
    const Eigen::Vector3d wind_body = R.transpose() * Eigen::Vector3d(kWindN, kWindE, 0.0);
    s.t.push_back(t0 + t);
    s.phi.push_back(0.0), s.theta.push_back(alpha), s.psi.push_back(psi);
    s.alpha.push_back(alpha), s.beta.push_back(0.0);
    const double Va_pitot = Va / kScale;
    s.qbar.push_back(0.5 * kRho * Va_pitot * Va_pitot), s.Va.push_back(Va_pitot);
    s.u.push_back(Va * std::cos(alpha) + wind_body.x() + gust(rng));
  }
}

std::vector<std::size_t> all(const FlightSeries& s) {
  std::vector<std::size_t> idx(s.t.size());
  for (std::size_t k = 0; k < idx.size(); ++k) idx[k] = k;
  return idx;
}

/// Trim windows at Va (true) with load factors n as the turns give them, measured as identify.cpp
/// measures them: the pitot's dynamic pressure corrected by `k_est`, the drag force carrying the
/// accelerometer's bias (m b along body x), plus noise of 2e-4 on C_D.
void windows(double Va, const std::vector<double>& loads, double k_est, std::mt19937& rng, std::vector<PolarWindow>& w) {
  std::normal_distribution<double> noise(0.0, 2e-4);
  const double alpha = 0.05 - 0.002 * (Va - 20.0);
  const double qbar_true = 0.5 * kRho * Va * Va, Va_pitot = Va / kScale;
  const double qbar = 0.5 * kRho * (k_est * Va_pitot) * (k_est * Va_pitot);
  for (const double n : loads) {
    const double lift = n * kMass * tern::kGravity;
    const double C_L = lift / (qbar_true * kS);
    const double drag_force = qbar_true * kS * (kCDp + C_L * C_L / (tern::kPi * kE * kAR));
    const double measured = drag_force - kMass * kBias * std::cos(alpha);
    w.push_back({measured / (qbar * kS) + noise(rng), std::pow(lift / (qbar * kS), 2), -kMass * std::cos(alpha) / (qbar * kS)});
  }
}

/// Trim windows at Va (true) and 1 g to 1.2 g with the pitot read right and no accelerometer bias,
/// noise of 2e-4 on C_D, on a polar whose parasitic drag is C_D_p.
void windows_without_bias(double Va, std::mt19937& rng, std::vector<PolarWindow>& w, double C_D_p = kCDp) {
  std::normal_distribution<double> noise(0.0, 2e-4);
  const double qbar = 0.5 * kRho * Va * Va;
  for (const double n : {1.0, 1.05, 1.1, 1.2}) {
    const double C_L = n * kMass * tern::kGravity / (qbar * kS);
    w.push_back({C_D_p + C_L * C_L / (tern::kPi * kE * kAR) + noise(rng), C_L * C_L, 0.0});
  }
}

/// One row of an identification's coefficients, as the consider terms read them.
tern::core::sysid::CoefficientEstimate row(const char* name, double estimate, double se, bool identified = true) {
  tern::core::sysid::CoefficientEstimate e;
  e.name = name, e.estimate = estimate, e.std_error = se, e.identified = identified;
  return e;
}

}  // namespace

TEST_CASE("three airspeeds in turns: the pitot scale, the accelerometer's x bias, C_D_p and e within their bounds") {
  std::mt19937 rng(7);
  FlightSeries s;
  for (const double Va : {18.0, 24.0, 30.0}) fly(Va, 120.0, 0.1, rng, s);
  const auto scale = tern::core::sysid::airspeed_scale(s, all(s), kRho, 0.95);
  REQUIRE(scale.k.identified);
  CAPTURE(scale.k.estimate);
  CAPTURE(scale.k.std_error);
  CHECK(std::abs(scale.k.estimate - kScale) <= 3.0 * scale.k.std_error);
  CHECK(scale.k.std_error < 0.01);
  CHECK(std::abs(scale.w_n - kWindN) < 0.5);

  std::vector<PolarWindow> w;
  for (const double Va : {18.0, 24.0, 30.0}) windows(Va, {1.0, 1.0, 1.05, 1.1, 1.2, 1.0, 1.15, 1.0}, scale.k.estimate, rng, w);
  const auto p = tern::core::sysid::drag_polar(w, kAR, 0.5, 3);
  REQUIRE(p.bias_x.identified);
  REQUIRE(p.e.identified);
  CAPTURE(p.C_D_p.estimate);
  CAPTURE(p.C_D_p.std_error);
  CAPTURE(p.e.estimate);
  CAPTURE(p.e.std_error);
  CAPTURE(p.bias_x.estimate);
  CAPTURE(p.bias_x.std_error);
  // the scale's own error (a consider term in identify.cpp) is small here: 3 SE of each
  CHECK(std::abs(p.C_D_p.estimate - kCDp) <= 3.0 * p.C_D_p.std_error + 2.0 * kCDp * std::abs(scale.k.estimate - kScale));
  CHECK(std::abs(p.e.estimate - kE) <= 3.0 * p.e.std_error + 2.0 * kE * std::abs(scale.k.estimate - kScale));
  CHECK(std::abs(p.bias_x.estimate - kBias) <= 3.0 * p.bias_x.std_error);
  CHECK(p.bias_x.std_error < 0.03);
}

TEST_CASE("one airspeed on one heading: neither the pitot scale nor the accelerometer bias is identifiable") {
  std::mt19937 rng(11);
  FlightSeries s;
  fly(24.0, 120.0, 0.0, rng, s);
  const auto scale = tern::core::sysid::airspeed_scale(s, all(s), kRho, 0.95);
  CHECK_FALSE(scale.k.identified);
  CHECK(scale.k.estimate == 1.0);
  CHECK_FALSE(scale.k.note.empty());

  std::vector<PolarWindow> w;
  windows(24.0, {1.0, 1.0, 1.0, 1.0, 1.0, 1.0}, 1.0, rng, w);
  const auto p = tern::core::sysid::drag_polar(w, kAR, 0.5, 3);
  CHECK_FALSE(p.bias_x.identified);
  CHECK(p.bias_x.estimate == 0.0);
  CHECK(p.bias_x.note.find("not identifiable: one airspeed") != std::string::npos);
}

TEST_CASE("C_D_p held at its prior: the slope fitted through it, its bound the joint fit's") {
  // Windows at three airspeeds, 1 g to 1.2 g, noise of 2e-4 on C_D, no accelerometer bias: held at the
  // true C_D_p, the slope is the truth's within the joint fit's bound. A C_D_p of 0.003 held at a
  // prior of 0 (the Aerosonde's): the slope through it stays nearer the windows' drag at their mean
  // C_Lw^2 than the joint slope beside a C_D_p of 0, which misses by the whole C_D_p dropped.
  std::mt19937 rng(5);
  std::vector<PolarWindow> w;
  for (const double Va : {18.0, 24.0, 30.0}) windows_without_bias(Va, rng, w);
  const auto truth = tern::core::sysid::drag_polar(w, kAR, 0.5, 3, false, kCDp);
  REQUIRE(truth.e.identified);
  REQUIRE(truth.e_held.identified);
  CAPTURE(truth.e.estimate);
  CAPTURE(truth.e_held.estimate);
  CAPTURE(truth.e_held.std_error);
  CHECK(std::abs(truth.e_held.estimate - kE) <= 3.0 * truth.e_held.std_error);
  CHECK(truth.K_held.std_error == truth.K.std_error);

  std::vector<PolarWindow> small;
  for (const double Va : {18.0, 24.0, 30.0}) windows_without_bias(Va, rng, small, 0.003);
  const auto zero = tern::core::sysid::drag_polar(small, kAR, 0.5, 3, false, 0.0);
  double z = 0.0, x = 0.0;
  for (const PolarWindow& p : small)
    z += p.C_D / static_cast<double>(small.size()), x += p.C_Lw_squared / static_cast<double>(small.size());
  const double held_miss = std::abs(zero.K_held.estimate * x - z), dropped_miss = std::abs(zero.K.estimate * x - z);
  CAPTURE(z);
  CAPTURE(held_miss);
  CAPTURE(dropped_miss);
  CHECK(dropped_miss > 0.002);
  CHECK(held_miss < 0.5 * dropped_miss);
}

TEST_CASE("the polar at the windows' mean C_Lw^2: the joint fit's drag there, bounded tighter than C_D_p's and the slope's bounds added") {
  // Windows at three airspeeds, 1 g to 1.2 g, noise of 2e-4 on C_D: the centred fit's intercept is
  // the joint polar at the mean C_Lw^2 (the same line), the truth's drag there inside 3 of its bound;
  // C_D_p and the slope trade against each other, so their bounds added overstate the drag's.
  std::mt19937 rng(11);
  std::vector<PolarWindow> w;
  for (const double Va : {18.0, 24.0, 30.0}) windows_without_bias(Va, rng, w);
  const auto p = tern::core::sysid::drag_polar(w, kAR, 0.5, 3, false, kCDp);
  double x = 0.0;
  for (const PolarWindow& v : w) x += v.C_Lw_squared / static_cast<double>(w.size());
  CHECK(p.C_Lw_squared_mean == doctest::Approx(x).epsilon(1e-12));
  REQUIRE(p.C_D_at_mean.identified);
  CHECK(p.C_D_at_mean.estimate == doctest::Approx(p.C_D_p.estimate + p.K.estimate * x).epsilon(1e-9));
  const double truth = kCDp + x / (tern::kPi * kE * kAR);
  CAPTURE(p.C_D_at_mean.estimate);
  CAPTURE(p.C_D_at_mean.std_error);
  CHECK(std::abs(p.C_D_at_mean.estimate - truth) <= 3.0 * p.C_D_at_mean.std_error);
  CHECK(p.C_D_at_mean.std_error > 0.0);
  CHECK(p.C_D_at_mean.std_error < 0.5 * (p.C_D_p.std_error + x * p.K.std_error));
}

TEST_CASE("a stated pitot scale is held, not estimated: the wind fitted beside it, one heading or several") {
  std::mt19937 rng(3);
  FlightSeries s;
  for (const double Va : {18.0, 24.0, 30.0}) fly(Va, 120.0, 0.1, rng, s);
  const auto held = tern::core::sysid::stated_airspeed_scale(s, all(s), kRho, kScale, 0.002);
  CHECK_FALSE(held.k.identified);
  CHECK(held.k.estimate == kScale);
  CHECK(held.k.std_error == 0.002);
  CHECK(held.k.note == tern::core::sysid::kStatedPitotScale);
  CAPTURE(held.w_n);
  CAPTURE(held.w_e);
  CHECK(std::abs(held.w_n - kWindN) < 0.2);
  CHECK(std::abs(held.w_e - kWindE) < 0.2);
  // a scale 3 % off leaves the wind triangle's residual larger than the true scale's
  const auto off = tern::core::sysid::stated_airspeed_scale(s, all(s), kRho, kScale * 1.03, 0.0);
  CHECK(off.rms_residual > held.rms_residual + 0.1);

  FlightSeries line;  // one heading: the wind's columns are constant, the least-norm wind is still finite
  fly(24.0, 60.0, 0.0, rng, line);
  const auto one = tern::core::sysid::stated_airspeed_scale(line, all(line), kRho, kScale, 0.0);
  CHECK(std::isfinite(one.w_n));
  CHECK(std::isfinite(one.w_e));
  CHECK_THROWS_AS(tern::core::sysid::stated_airspeed_scale(s, all(s), kRho, 0.3, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(tern::core::sysid::stated_airspeed_scale(s, all(s), kRho, 1.0, -0.1), std::invalid_argument);
}

TEST_CASE("consider_pitot_scale: the scale's share of each bound goes as k^-2, a rate derivative's as k^-1, the drag's not at all") {
  using tern::core::sysid::CoefficientEstimate;
  std::vector<CoefficientEstimate> c = {
      row("C_ell_delta_a", 0.17, 0.003), row("C_ell_p", -0.5, 0.004),           row("C_m_q", -38.0, 0.0),         row("C_n_0", -1e-4, 3e-5),
      row("C_D_p", 0.02, 0.001),         row("C_Y_delta_a", 0.075, 0.0, false), row("C_n_delta_r", -0.069, 0.002)};
  const double relative = 0.01;  // sigma_k / k
  tern::core::sysid::consider_pitot_scale(c, relative);
  CHECK(c[0].std_error == doctest::Approx(std::hypot(0.003, 2 * relative * 0.17)));
  CHECK(c[1].std_error == doctest::Approx(std::hypot(0.004, relative * 0.5)));
  CHECK(c[2].std_error == doctest::Approx(relative * 38.0));
  CHECK(c[3].std_error == doctest::Approx(std::hypot(3e-5, 2 * relative * 1e-4)));
  CHECK(c[4].std_error == 0.001);  // the polar's bound carries the scale already
  CHECK(c[5].std_error == 0.0);    // a kept prior has no bound to widen
  // a surface's derivative, though its name ends in _r
  CHECK(c[6].std_error == doctest::Approx(std::hypot(0.002, 2 * relative * 0.069)));
  const std::vector<CoefficientEstimate> before = c;
  tern::core::sysid::consider_pitot_scale(c, 0.0);  // no scale's bound (no pitot, or a stated exact one)
  for (std::size_t i = 0; i < c.size(); ++i) CHECK(c[i].std_error == before[i].std_error);
}

TEST_CASE("consider_side_force_terms: a side-force term's uncertainty reaches the moments' matching terms through beta") {
  tern::core::sysid::SysidResult r;
  r.coefficients = {row("C_Y_beta", -0.98, 0.05),           row("C_ell_beta", -0.13, 0.005),     row("C_n_beta", 0.073, 0.004),
                    row("C_Y_delta_r", 0.114, 0.0, false),  row("C_Y_delta_a", 0.075, 0.01),     row("C_Y_p", 0.0, 0.0, false),
                    row("C_ell_delta_r", -0.0074, 0.00064), row("C_n_delta_r", -0.0626, 0.0016), row("C_ell_delta_a", 0.17, 0.004),
                    row("C_n_delta_a", -0.011, 0.0, false), row("C_ell_p", -0.5, 0.006)};
  tern::core::sysid::consider_side_force_terms(r);
  const auto se = [&](const char* name) { return tern::core::sysid::find_estimate(r, name)->std_error; };
  // the kept C_Y_delta_r: 0.5 of its prior, times C_*_beta / C_Y_beta
  CHECK(se("C_ell_delta_r") == doctest::Approx(std::hypot(0.00064, 0.13 / 0.98 * 0.5 * 0.114)));
  CHECK(se("C_n_delta_r") == doctest::Approx(std::hypot(0.0016, 0.073 / 0.98 * 0.5 * 0.114)));
  // the identified C_Y_delta_a: its own bound
  CHECK(se("C_ell_delta_a") == doctest::Approx(std::hypot(0.004, 0.13 / 0.98 * 0.01)));
  CHECK(se("C_n_delta_a") == 0.0);   // kept: no bound to widen
  CHECK(se("C_ell_p") == 0.006);     // C_Y_p held at 0: nothing carried
  CHECK(se("C_ell_beta") == 0.005);  // the scale's share is consider_sideslip_scale's
  REQUIRE(r.notes.size() == 1);
  CHECK(r.notes[0].find("C_ell_delta_r, C_n_delta_r: beta from the side force rests on the prior's C_Y_delta_r") == 0);
}
