// The rendezvous plan (rendezvous.hpp): common arrival time, airspeeds, holds, slips.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "tern/coordination/rendezvous.hpp"
#include "tern/math.hpp"

using namespace tern::coord;

namespace {
VehicleKinematics at(double n, double e, double chi, Vec2 wind = Vec2::Zero()) {
  VehicleKinematics k;
  k.p = {n, e};
  k.chi = chi;
  k.wind = wind;
  return k;
}
}  // namespace

TEST_CASE("rendezvous config: inconsistent values are refused") {
  RendezvousConfig c;
  CHECK_NOTHROW(c.validate());
  c.Va_nominal = 25.0;
  CHECK_THROWS_AS(c.validate(), std::invalid_argument);
  c = RendezvousConfig{};
  c.Va_max = 10.0;
  CHECK_THROWS_AS(c.validate(), std::invalid_argument);
  c = RendezvousConfig{};
  c.turn_radius = 0.0;
  CHECK_THROWS_AS(c.validate(), std::invalid_argument);
}

TEST_CASE("rendezvous: three vehicles at different distances arrive together, the near one holds") {
  const RendezvousConfig cfg;
  const Vec2 point(0, 0);
  // all flying straight at the point (no turn): 3000, 2400 and 600 m away
  const std::vector<VehicleKinematics> ks = {at(-3000, 0, 0.0), at(0, 2400, -tern::kPi / 2), at(600, 0, tern::kPi)};
  const double t = 10.0;
  const double T = arrival_time(t, ks, point, cfg);
  CHECK(T == doctest::Approx(t + 3000.0 / cfg.Va_nominal));
  const VehicleCommand far = command_for(t, T, ks[0], point, cfg);
  const VehicleCommand mid = command_for(t, T, ks[1], point, cfg);
  const VehicleCommand near = command_for(t, T, ks[2], point, cfg);
  CHECK(far.Va_d == doctest::Approx(cfg.Va_nominal));
  CHECK(mid.Va_d == doctest::Approx(2400.0 / (T - t)));
  CHECK(mid.Va_d > cfg.Va_min);
  CHECK(far.hold_time == 0.0);
  CHECK(mid.hold_time == 0.0);
  // 600 m at Va_min = 46 s, far earlier than T - t = 176 s: a hold on a circle through it
  CHECK(near.hold_time > 100.0);
  CHECK((near.hold_center - ks[2].p).norm() == doctest::Approx(cfg.turn_radius));
  CHECK(near.Va_d == doctest::Approx(cfg.Va_nominal));
  for (const auto& c : {far, mid, near}) CHECK(c.eta == doctest::Approx(T));
}

TEST_CASE("rendezvous: in wind the airspeeds differ but the predicted arrivals agree") {
  const RendezvousConfig cfg;
  const Vec2 point(500, 500);
  const Vec2 wind(3.5355, -3.5355);
  const std::vector<VehicleKinematics> ks = {at(-2500, 300, 0.3, wind), at(2000, 2500, 2.0, wind), at(800, -1600, -0.5, wind)};
  const double T = arrival_time(0.0, ks, point, cfg);
  for (const auto& k : ks) {
    const VehicleCommand c = command_for(0.0, T, k, point, cfg);
    CHECK(c.hold_time == 0.0);
    CHECK(c.eta == doctest::Approx(T));
    CHECK(predicted_arrival(0.0, k, point, c.Va_d, cfg) == doctest::Approx(T));
  }
  const VehicleCommand c0 = command_for(0.0, T, ks[0], point, cfg);
  const double calm = path_length(ks[0], point, cfg) / T;  // the airspeed without wind
  CHECK(std::fabs(c0.Va_d - calm) > 0.5);
}

TEST_CASE("rendezvous: the turn allowance makes a vehicle pointing away later") {
  const RendezvousConfig cfg;
  const VehicleKinematics toward = at(-1000, 0, 0.0), away = at(-1000, 0, tern::kPi);
  CHECK(path_length(away, {0, 0}, cfg) == doctest::Approx(1000.0 + cfg.turn_radius * (tern::kPi + 2.0 * std::atan(0.05))));
  CHECK(predicted_arrival(0.0, away, {0, 0}, 17.0, cfg) > predicted_arrival(0.0, toward, {0, 0}, 17.0, cfg) + 9.0);
}

TEST_CASE("rendezvous: a vehicle that cannot make T at Va_max moves T later") {
  const RendezvousConfig cfg;
  const std::vector<VehicleKinematics> ks = {at(-2200, 0, 0.0), at(-500, 0, 0.0)};
  const double T = 50.0;  // 2200 m in 50 s would need 44 m/s
  const double T2 = arrival_time_slip(0.0, T, ks, {0, 0}, cfg);
  CHECK(T2 == doctest::Approx(2200.0 / cfg.Va_max));
  CHECK(arrival_time_slip(0.0, 1000.0, ks, {0, 0}, cfg) == 1000.0);  // feasible: unchanged
  const VehicleCommand c = command_for(0.0, T, ks[0], {0, 0}, cfg);
  CHECK(c.Va_d == cfg.Va_max);  // clamped
  CHECK(c.eta > T + 1.0);
}
