// Tests of @NAME@: the statistics alone and the plugin through the SDK harness.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include "flight_stats.hpp"
#include "plugin.hpp"
#include "tern/testing/harness.hpp"

TEST_CASE("stats: peak bank, airspeeds, time and episodes below the warning speed") {
  tern_@NAME@::FlightStats s;
  CHECK_FALSE(s.add(0.0, 0.1, 17.0, 12.0));
  CHECK(s.add(1.0, -0.5, 11.0, 12.0));   // a new episode
  CHECK_FALSE(s.add(2.0, 0.2, 10.0, 12.0));  // still the same one
  CHECK_FALSE(s.add(3.0, 0.0, 15.0, 12.0));
  CHECK(s.add(4.0, 0.0, 11.5, 12.0));    // a second one
  CHECK_FALSE(s.add(5.0, NAN, 11.5, 12.0));  // ignored
  CHECK(s.max_abs_phi() == doctest::Approx(0.5));
  CHECK(s.min_Va() == doctest::Approx(10.0));
  CHECK(s.mean_Va() == doctest::Approx((17.0 + 11.0 + 10.0 + 15.0 + 11.5) / 5));
  CHECK(s.time_below_warn() == doctest::Approx(2.0));  // 1..2, 2..3
  CHECK(s.episodes() == 2);
}

TEST_CASE("plugin: counts only valid airborne states and reports its summary") {
  tern::testing::Harness h(std::make_unique<@CLASS@>(), {{"Va_warn", 13.0}});
  tern::msg::State x;
  x.valid = true;
  x.p_d = -100.0;
  x.Va = 17.0;
  x.phi = 0.4;
  h.set_input("state", x);
  h.step(tern::from_seconds(1.0));
  x.Va = 12.0;
  h.set_input("state", x);
  h.step(tern::from_seconds(2.0));
  x.p_d = 0.0;  // on the ground: not counted
  x.Va = 0.0;
  h.set_input("state", x);
  h.step(tern::from_seconds(3.0));
  h.stop();
  std::map<std::string, double> sum;
  for (const auto& [k, v] : h.plugin().summary()) sum[k] = v;
  CHECK(sum.at("min_Va") == doctest::Approx(12.0));
  CHECK(sum.at("max_abs_phi") == doctest::Approx(0.4));
  CHECK(sum.at("low_airspeed_episodes") == 1.0);
  CHECK_THROWS_AS(h.set_param("Va_warn", -1.0), tern::ParamError);
}

TEST_CASE("plugin: after reset() a flight is the first one again") {
  // The contract of tern/plugin.hpp: what a flight changes lives in @CLASS@::Flight, which
  // reset() replaces. Two flights of the same states with a reset() between them must give the
  // same summary; a figure kept outside Flight would add the first flight to the second.
  tern::testing::Harness h(std::make_unique<@CLASS@>());
  auto fly = [&h] {
    for (int i = 1; i <= 100; ++i) {  // 10 s, the airspeed sagging below Va_warn and back twice
      tern::msg::State x;
      x.valid = true;
      x.p_d = -50.0;
      x.phi = 0.01 * (i % 30);
      x.Va = 14.0 + 3.0 * std::cos(0.13 * i);
      h.set_input("state", x);
      h.step(tern::from_seconds(0.1 * i));
    }
    h.stop();
    return h.plugin().summary();
  };
  const auto first = fly();
  REQUIRE(first.size() == 5);  // below 12 m/s twice: two episodes
  CHECK(first[4] == std::pair<std::string, double>("low_airspeed_episodes", 2.0));
  h.reset();
  CHECK(fly() == first);
}
