// Logs tern did not write (issue 76): where the ground is (airborne.hpp) and the excitation of a
// closed loop recovered from its commands (excitation_recovery.hpp), on synthetic series whose
// answers are known.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "sysid/airborne.hpp"
#include "sysid/excitation_recovery.hpp"

using namespace tern::core::sysid;

namespace {
constexpr double kRate = 50.0;  // Hz

// A series of n samples at kRate, valid, level and still at the estimator's origin.
FlightSeries still_series(std::size_t n) {
  FlightSeries s;
  for (std::size_t k = 0; k < n; ++k) s.t.push_back(static_cast<double>(k) / kRate);
  for (auto* v : {&s.p_n, &s.p_e, &s.p_d, &s.u, &s.v, &s.w, &s.phi, &s.theta, &s.psi, &s.p, &s.q, &s.r, &s.beta, &s.delta_a, &s.delta_e,
                  &s.delta_r, &s.delta_t})
    v->assign(n, 0.0);
  s.Va.assign(n, 0.0);
  s.valid.assign(n, 1);
  return s;
}

// A smooth signal independent of the others: a sum of sines of random frequency (0.1-2 Hz) and phase.
std::vector<double> smooth(std::mt19937& rng, std::size_t n, double amplitude) {
  std::uniform_real_distribution<double> f(0.1, 2.0), ph(0.0, 6.283);
  std::vector<double> x(n, 0.0);
  for (int i = 0; i < 6; ++i) {
    const double w = 6.283 * f(rng), p = ph(rng);
    for (std::size_t k = 0; k < n; ++k) x[k] += amplitude / 6.0 * std::sin(w * static_cast<double>(k) / kRate + p);
  }
  return x;
}

// A 3-2-1-1 of 0.2-s units every 15 s: the injected manoeuvres, zero between them.
std::vector<double> manoeuvres(std::size_t n, double amplitude) {
  const int units[] = {1, 1, 1, -1, -1, 1, -1};
  std::vector<double> e(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const double into = std::fmod(static_cast<double>(k) / kRate, 15.0) - 5.0;
    if (into >= 0.0 && into < 1.4) e[k] = amplitude * units[static_cast<int>(into / 0.2)];
  }
  return e;
}

// A still series in level flight at 20 m/s, 100 m up, its roll, roll rate and yaw rate smooth signals.
FlightSeries flying_series(std::mt19937& rng, std::size_t n) {
  FlightSeries s = still_series(n);
  s.phi = smooth(rng, n, 0.2);
  s.p = smooth(rng, n, 0.5);
  s.r = smooth(rng, n, 0.2);
  for (std::size_t k = 0; k < n; ++k) s.Va[k] = 20.0, s.p_d[k] = -100.0, s.u[k] = 20.0;
  return s;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ab = 0, aa = 0, bb = 0, ma = 0, mb = 0;
  for (std::size_t k = 0; k < a.size(); ++k) ma += a[k], mb += b[k];
  ma /= static_cast<double>(a.size());
  mb /= static_cast<double>(b.size());
  for (std::size_t k = 0; k < a.size(); ++k)
    ab += (a[k] - ma) * (b[k] - mb), aa += (a[k] - ma) * (a[k] - ma), bb += (b[k] - mb) * (b[k] - mb);
  return ab / std::sqrt(aa * bb);
}

double rms(const std::vector<double>& a) {
  double s = 0;
  for (double v : a) s += v * v;
  return std::sqrt(s / static_cast<double>(a.size()));
}
}  // namespace

TEST_CASE("airborne: the ground is where the aircraft stood still; a log that never did has its ground far below") {
  // stood 5 s at 30 m below the estimator's origin (a first fix taken up a hill), then flew at 100 m
  FlightSeries s = still_series(1000);
  for (std::size_t k = 0; k < s.size(); ++k) {
    const bool flying = k >= 250;
    s.p_d[k] = flying ? -100.0 : 30.0;
    s.u[k] = flying ? 20.0 : 0.3;
  }
  const auto ground = ground_height(s, AirborneRule{});
  REQUIRE(ground.has_value());
  CHECK(*ground == doctest::Approx(-30.0));
  put_ground_at_zero(s, AirborneRule{});
  CHECK(s.p_d[0] == doctest::Approx(0.0));
  CHECK(s.p_d[500] == doctest::Approx(-130.0));
  // the estimate invalid while standing: no ground; the log starts and ends in the air
  FlightSeries air = still_series(1000);
  for (std::size_t k = 0; k < air.size(); ++k) air.p_d[k] = -50.0 - 0.01 * static_cast<double>(k), air.u[k] = 20.0;
  CHECK_FALSE(ground_height(air, AirborneRule{}).has_value());
  put_ground_at_zero(air, AirborneRule{});
  CHECK(air.p_d[0] == doctest::Approx(-1000.0));  // the lowest sample, the first, 1000 m up
  CHECK(air.p_d[999] == doctest::Approx(-1009.99));
}

TEST_CASE("excitation recovery: the command less the controller's feedback is the injected manoeuvre") {
  const std::size_t n = static_cast<std::size_t>(120 * kRate);
  std::mt19937 rng(7);
  FlightSeries s = flying_series(rng, n);
  s.theta = smooth(rng, n, 0.05);
  s.q = smooth(rng, n, 0.3);
  s.beta = smooth(rng, n, 0.03);
  const std::vector<double> dVa = smooth(rng, n, 1.0);
  for (std::size_t k = 0; k < n; ++k) s.Va[k] += dVa[k];
  // the autopilot: the aileron and the elevator feed back roll and pitch and add manoeuvres; the
  // rudder and the throttle are feedback only
  const std::vector<double> e_a = manoeuvres(n, 0.1), e_e = manoeuvres(n, 0.05);
  for (std::size_t k = 0; k < n; ++k) {
    s.delta_a[k] = -0.4 * s.phi[k] - 0.1 * s.p[k] + e_a[k];
    s.delta_e[k] = 0.8 * s.theta[k] + 0.2 * s.q[k] + e_e[k];
    s.delta_r[k] = -0.3 * s.r[k] + 0.5 * s.beta[k];
    s.delta_t[k] = 0.5 - 0.02 * dVa[k];
  }
  recover_excitation(s);
  REQUIRE(s.exc_delta_a.size() == n);
  CHECK(s.notes.size() == 4);
  CHECK(correlation(s.exc_delta_a, e_a) > 0.95);
  CHECK(correlation(s.exc_delta_e, e_e) > 0.95);
  CHECK(rms(s.exc_delta_r) < 0.05 * rms(s.delta_r));
  CHECK(rms(s.exc_delta_t) < 0.05 * rms(dVa) * 0.02);
  // a log with an excitation table keeps it
  FlightSeries logged = s;
  logged.exc_delta_a.assign(n, 1.0);
  recover_excitation(logged);
  CHECK(logged.exc_delta_a == std::vector<double>(n, 1.0));
}

TEST_CASE("excitation recovery: a controller with memory (a washed-out yaw damper, a PI roll loop) is modelled too") {
  const std::size_t n = static_cast<std::size_t>(300 * kRate);
  std::mt19937 rng(11);
  FlightSeries s = flying_series(rng, n);
  const std::vector<double> e_a = manoeuvres(n, 0.05), e_r = manoeuvres(n, 0.05);
  // the book's yaw damper: delta_r = k_r (r less r through a 0.5-rad/s washout's low-pass); the
  // roll loop: proportional, derivative and integral of the roll error (uavbook sec. 6.3.1)
  const double dt = 1.0 / kRate;
  double r_low = 0.0, phi_integral = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    r_low += 0.5 * dt * (s.r[k] - r_low);
    phi_integral += s.phi[k] * dt;
    s.delta_r[k] = -0.5 * (s.r[k] - r_low) + e_r[k];
    s.delta_a[k] = -0.4 * s.phi[k] - 0.1 * s.p[k] - 0.2 * phi_integral + e_a[k];
  }
  FlightSeries lags_only = s;
  ExcitationRecoveryOptions o;
  o.lowpass_s.clear();
  recover_excitation(lags_only, o);
  recover_excitation(s);
  // what the recovery leaves of the controller's answer: the recovered less the injected
  auto leak = [&](const std::vector<double>& recovered, const std::vector<double>& injected) {
    std::vector<double> d(n);
    for (std::size_t k = 0; k < n; ++k) d[k] = recovered[k] - injected[k];
    return rms(d) / rms(injected);
  };
  CAPTURE(leak(lags_only.exc_delta_r, e_r));
  CAPTURE(leak(lags_only.exc_delta_a, e_a));
  CAPTURE(leak(s.exc_delta_r, e_r));
  CAPTURE(leak(s.exc_delta_a, e_a));
  CHECK(leak(s.exc_delta_r, e_r) < 0.1);
  CHECK(leak(s.exc_delta_a, e_a) < 0.1);
  CHECK(leak(lags_only.exc_delta_a, e_a) > 2.0 * leak(s.exc_delta_a, e_a));  // the integrator's memory (0.22 against 0.07)
  CHECK(s.notes.back().find("low-passes of 0.5, 2, 8 s") != std::string::npos);
  FlightSeries refused = lags_only;
  refused.exc_delta_a.clear();
  o.lowpass_s = {2.0, 0.0};
  CHECK_THROWS_AS(recover_excitation(refused, o), std::invalid_argument);
}
