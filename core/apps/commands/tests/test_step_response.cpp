// Step-response figures (core/apps/commands/step_response.hpp) on systems whose answers are known in
// closed form: first order (rise 2.197 tau, settling 3.912 tau) and second order (overshoot
// exp(-zeta pi / sqrt(1 - zeta^2)), settling bounded by the envelope).
#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

#include "commands/step_response.hpp"
#include "tern/math.hpp"

using tern::core::step_metrics;

namespace {
using tern::kPi;

struct Series {
  std::vector<double> t, y;
};
/// y(t) sampled every dt from 0 to t_end, shifted to start at t0 (the step's flight time).
Series sample(const std::function<double(double)>& y, double t_end, double dt = 1e-3, double t0 = 0.0) {
  Series s;
  for (int i = 0; i * dt <= t_end + 1e-12; ++i) s.t.push_back(t0 + i * dt), s.y.push_back(y(i * dt));
  return s;
}
}  // namespace

TEST_CASE("first order: rise 2.197 tau, settling 3.912 tau, no overshoot, no steady-state error") {
  const double tau = 0.5;
  const auto s = sample([&](double t) { return 1.0 - std::exp(-t / tau); }, 20 * tau, 1e-3, 42.0);
  const auto m = step_metrics(s.t, s.y, 1.0);
  CHECK(m.rise_time == doctest::Approx(std::log(9.0) * tau).epsilon(1e-3));        // ln 9 = 2.197
  CHECK(m.settling_time == doctest::Approx(-std::log(0.02) * tau).epsilon(1e-3));  // 3.912
  CHECK(m.overshoot_pct < 1e-3);
  CHECK(std::abs(m.steady_state_error) < 1e-6);
  CHECK(m.y0 == 0.0);
}

TEST_CASE("first order with DC gain 0.8: the steady-state error is 0.2 of the command; a step down mirrors it") {
  const double tau = 0.2;
  const auto up = sample([&](double t) { return 0.8 * (1.0 - std::exp(-t / tau)); }, 30 * tau);
  const auto mu = step_metrics(up.t, up.y, 1.0);
  CHECK(mu.steady_state_error == doctest::Approx(0.2).epsilon(1e-4));
  CHECK(mu.rise_time == doctest::Approx(2.197 * tau).epsilon(1e-3));
  const auto down = sample([&](double t) { return 5.0 - 0.8 * 2.0 * (1.0 - std::exp(-t / tau)); }, 30 * tau);
  const auto md = step_metrics(down.t, down.y, 3.0);
  CHECK(md.steady_state_error == doctest::Approx(-0.4).epsilon(1e-4));
  CHECK(md.rise_time == doctest::Approx(mu.rise_time).epsilon(1e-6));
  CHECK(md.settling_time == doctest::Approx(mu.settling_time).epsilon(1e-6));
}

TEST_CASE("second order: overshoot exp(-zeta pi / sqrt(1 - zeta^2)), settling inside the envelope's bound") {
  for (double zeta : {0.3, 0.5, 0.7}) {
    const double wn = 2.0, wd = wn * std::sqrt(1 - zeta * zeta), phi = std::acos(zeta);
    const auto y = [&](double t) { return 1.0 - std::exp(-zeta * wn * t) * std::sin(wd * t + phi) / std::sqrt(1 - zeta * zeta); };
    const auto s = sample(y, 40.0 / (zeta * wn));
    const auto m = step_metrics(s.t, s.y, 1.0);
    CAPTURE(zeta);
    CHECK(m.overshoot_pct == doctest::Approx(100.0 * std::exp(-zeta * kPi / std::sqrt(1 - zeta * zeta))).epsilon(1e-3));
    // the envelope 1 +- exp(-zeta wn t)/sqrt(1-zeta^2) enters the 2 % band at t_env; the response
    // itself settles no later, and at most half a damped period earlier
    const double t_env = -std::log(0.02 * std::sqrt(1 - zeta * zeta)) / (zeta * wn);
    CHECK(m.settling_time <= t_env + 1e-3);
    CHECK(m.settling_time >= t_env - kPi / wd);
    // rise time: the analytic crossings of 10 % and 90 %, found by bisection on y(t)
    const auto cross = [&](double level) {
      double a = 0.0, b = kPi / wd;  // y rises monotonically up to the first peak
      for (int i = 0; i < 60; ++i) (y((a + b) / 2) < level ? a : b) = (a + b) / 2;
      return a;
    };
    CHECK(m.rise_time == doctest::Approx(cross(0.9) - cross(0.1)).epsilon(2e-3));
    CHECK(std::abs(m.steady_state_error) < 1e-4);
  }
}

TEST_CASE("a response outside the band at its last sample has no settling time (NaN)") {
  Series s;
  for (int i = 0; i <= 100; ++i) s.t.push_back(i * 0.01), s.y.push_back(i <= 90 ? 0.0 : 1.0);  // a jump at the end
  s.y.back() = 0.5;                                                                            // leaves the band at the last sample
  const auto m = step_metrics(s.t, s.y, 1.0);
  CHECK(std::isnan(m.settling_time));
}

TEST_CASE("bad input is refused") {
  CHECK_THROWS_AS(step_metrics({0, 1, 2}, {0, 1, 1}, 1.0), std::invalid_argument);
  CHECK_THROWS_AS(step_metrics({0, 1, 1, 2}, {0, 1, 1, 1}, 1.0), std::invalid_argument);
  CHECK_THROWS_AS(step_metrics({0, 1, 2, 3}, {1, 1, 1, 1}, 2.0), std::invalid_argument);
}
