// sample_field (tern echo --field) and TopicRate (tern hz), without DDS.
#include <doctest/doctest.h>

#include "topic_tools.hpp"

using namespace tern::core;

TEST_CASE("echo --field: a field's value, a nested field's lines, nothing for an unknown name") {
  const std::string s = "header.stamp: 1.5\np_n: 12.25\np_e: -3\nquat.w: 1\nquat.x: 0\nva: 15\n";
  CHECK(sample_field(s, "p_n") == "12.25\n");
  CHECK(sample_field(s, "p_n", false) == "p_n: 12.25\n");
  CHECK(sample_field(s, "quat") == "quat.w: 1\nquat.x: 0\n");
  CHECK(sample_field(s, "header.stamp") == "1.5\n");
  CHECK(sample_field(s, "p") == std::nullopt);  // not a prefix match of p_n
  CHECK(sample_field(s, "vb") == std::nullopt);
}

TEST_CASE("hz: the rate and the spread of the periods over the window") {
  TopicRate r(4);
  CHECK(r.report() == "no new messages");
  const auto t0 = TopicRate::Clock::time_point{};
  for (int i = 0; i <= 6; ++i) r.arrived(t0 + std::chrono::milliseconds(i < 3 ? 100 * i : 200 + 50 * (i - 2)));
  // periods: 100, 100 ms, then 50 ms x4: the window keeps the last four
  CHECK(r.samples() == 7);
  CHECK(r.report() == "average rate: 20.000\n\tmin: 0.050s max: 0.050s std dev: 0.00000s window: 5");
  r.arrived(t0 + std::chrono::milliseconds(500));  // a 100 ms gap
  CHECK(r.report() == "average rate: 16.000\n\tmin: 0.050s max: 0.100s std dev: 0.02165s window: 5");
}
