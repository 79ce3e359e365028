// The campaign's pure pieces (core/apps/campaign): counter-based draws, the Wilson interval,
// percentiles, summary flattening, the pass/fail criteria and the campaign file's bounds. Whole
// campaigns: test_campaign.py.
#include <doctest/doctest.h>

#include <cmath>

#include "campaign_file.hpp"
#include "campaign_report.hpp"
#include "config/error.hpp"
#include "counter_rng.hpp"
#include "flight_row.hpp"
#include "test_util.hpp"

using namespace tern::campaign;

TEST_CASE("counter-based draws: uniform in [0, 1) with mean 1/2, normal with mean 0 and sd 1, distinct per flight and stream") {
  const std::uint64_t s = stream_id("sim.wind.speed");
  double sum = 0, nsum = 0, nsq = 0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const double u = draw_uniform(2026, static_cast<std::uint64_t>(k), s);
    CHECK((u >= 0 && u < 1));
    sum += u;
    const double z = draw_normal(2026, static_cast<std::uint64_t>(k), s);
    nsum += z;
    nsq += z * z;
  }
  CHECK(sum / n == doctest::Approx(0.5).epsilon(0.01));
  CHECK(nsum / n == doctest::Approx(0.0).epsilon(0.02));
  CHECK(std::sqrt(nsq / n) == doctest::Approx(1.0).epsilon(0.02));
  CHECK(draw_word(1, 5, s) != draw_word(1, 6, s));
  CHECK(draw_word(1, 5, s) != draw_word(1, 5, stream_id("sim.wind.from_deg")));
  CHECK(draw_word(1, 5, s) != draw_word(2, 5, s));
  CHECK(flight_seed(1, 0) != flight_seed(1, 1));
}

TEST_CASE("95 % Wilson score interval matches published values") {
  // Newcombe (1998), Table I: 0/10 -> [0, 0.2775]; 81/263 -> [0.2553, 0.3662]
  auto [lo0, hi0] = wilson95(0, 10);
  CHECK(lo0 == doctest::Approx(0.0));
  CHECK(hi0 == doctest::Approx(0.2775).epsilon(0.001));
  auto [lo, hi] = wilson95(81, 263);
  CHECK(lo == doctest::Approx(0.2553).epsilon(0.001));
  CHECK(hi == doctest::Approx(0.3662).epsilon(0.001));
}

TEST_CASE("percentiles interpolate linearly between order statistics (numpy's default)") {
  const std::vector<double> v = {1, 2, 3, 4, 10};
  CHECK(percentile(v, 0.5) == doctest::Approx(3));
  CHECK(percentile(v, 0.95) == doctest::Approx(8.8));
  CHECK(percentile(v, 0.0) == doctest::Approx(1));
}

TEST_CASE("summary.json flattens to dotted figures; lists become counts; library provenance is left out") {
  const auto j = nlohmann::ordered_json::parse(R"({"end_reason": "duration", "fallback_engaged": false, "phases": [1, 2, 3],
    "instances": {"sim": {"plugin": "sim_aero", "library": "/x.so", "steps": 4, "sim_crashed": 0.0}},
    "metrics": {"max_cross_track_m": 12.5, "tracking_rmse": {"north_m": null}}})");
  const auto f = flatten_summary(j);
  FlightRow row;
  row.figures = f;
  REQUIRE(row.find("phases.count") != nullptr);
  CHECK(row.find("phases.count")->number == 3);
  CHECK(row.find("instances.sim.library") == nullptr);
  CHECK(row.find("instances.sim.steps")->text == "4");
  CHECK(row.find("fallback_engaged")->text == "false");
  CHECK(row.find("metrics.tracking_rmse.north_m")->text.empty());
}

TEST_CASE("criteria: numbers, booleans and text; a failed or missing figure says why") {
  FlightRow row;
  row.figures = flatten_summary(
      nlohmann::ordered_json::parse(R"({"end_reason": "crash", "fallback_engaged": false, "metrics": {"max_cross_track_m": 17.25}})"));
  judge({{"fallback_engaged", "==", "false", ""}, {"metrics.max_cross_track_m", "<", "20", ""}}, row);
  CHECK(row.outcome == Outcome::pass);
  CHECK(row.why.empty());
  judge(
      {{"metrics.max_cross_track_m", "<", "15", ""}, {"end_reason", "==", "duration", ""}, {"metrics.nope", "<", "1", "metrics.nope < 1"}},
      row);
  CHECK(row.outcome == Outcome::fail);
  CHECK(row.why ==
        "metrics.max_cross_track_m = 17.25 (needs < 15); end_reason = crash (needs == duration); metrics.nope < 1: no such figure in "
        "summary.json");
}

TEST_CASE("a grid of more than kMaxFlights points is refused before its size wraps (16 grids of 16 values: 2^64 points, issue 78)") {
  write_file("grid_base.yaml", "name: base\n");
  std::string text = "base: grid_base.yaml\ndispersions:\n";
  for (int i = 0; i < 16; ++i)
    text += "  aircraft.aero.C_" + std::to_string(i) + ": {dist: grid, values: [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]}\n";
  const auto file = write_file("grid_2_64.yaml", text);
  CHECK_THROWS_WITH_AS(load_campaign(file),
                       doctest::Contains((file.string() + ":10:").c_str()),  // C_7: 16^7 points, times 16 past 1e9
                       tern::core::ConfigError);
  CHECK_THROWS_WITH_AS(load_campaign(file), doctest::Contains("aircraft.aero.C_7: the grid would have more than 1e+09 points"),
                       tern::core::ConfigError);
  const auto ok = write_file("grid_ok.yaml", "base: grid_base.yaml\ndispersions:\n  aircraft.mass: {dist: grid, values: [-0.1, 0, 0.1]}\n");
  CHECK(load_campaign(ok).flights == 3);
}
