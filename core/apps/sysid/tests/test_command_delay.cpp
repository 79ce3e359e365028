// Which command delays sysid adopts from the timing pass (command_delay.hpp, choose_delays): the
// surfaces the flight times, the one it leaves undetermined, and the prior's delay as the last word.
#include <doctest/doctest.h>

#include <string>

#include "sysid/command_delay.hpp"

using namespace tern::core::sysid;

namespace {

NuisanceEstimate fit(double estimate_s, double std_error_s) {
  NuisanceEstimate e;
  e.estimate = estimate_s, e.std_error = std_error_s, e.identified = true;
  return e;
}

bool says(const DelayChoice& c, const std::string& text) {
  for (const auto& line : c.lines)
    if (line.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("choose_delays: a rudder the flight leaves undetermined takes the other surfaces' delay") {
  // a 10-Hz log 20 ms late: aileron and elevator timed, the rudder's own fit 26 +- 13 ms
  const DelayChoice c = choose_delays({0.0, 0.0, 0.0}, {fit(0.030, 0.001), fit(0.028, 0.0005), fit(0.026, 0.013)}, DelayOptions{});
  CHECK(c.moved);
  CHECK(c.delays[0] == doctest::Approx(0.030));
  CHECK(c.delays[1] == doctest::Approx(0.028));
  CHECK(c.delays[2] == doctest::Approx((0.030 / 1e-6 + 0.028 / 0.25e-6) / (1 / 1e-6 + 1 / 0.25e-6)));  // weighted by 1 / SE^2
  CHECK(c.shift[0].identified);
  CHECK_FALSE(c.shift[2].identified);
  CHECK(c.shift[2].note.find("the other surfaces' delay taken") != std::string::npos);
  CHECK(says(c, "command delay (rudder): not estimated alone (26.0 +- 13.0 ms"));
}

TEST_CASE("choose_delays: an undetermined surface whose own fit disagrees keeps the prior's delay") {
  // the rudder's fit, -40 +- 6 ms, is 11 standard errors from the others' 28 ms: not one output loop's
  const DelayChoice c = choose_delays({0.0, 0.0, 0.0}, {fit(0.028, 0.001), fit(0.028, 0.001), fit(-0.040, 0.006)}, DelayOptions{});
  CHECK(c.delays[2] == 0.0);
  CHECK(says(c, "standard errors from the other surfaces' 28.0 ms"));
  CHECK(says(c, "0 ms taken (the prior's servos.delay_r)"));
}

TEST_CASE("choose_delays: nothing adopted keeps the prior's delays; a given delay stays") {
  DelayOptions d;
  const DelayChoice none = choose_delays({0.005, 0.005, 0.005}, {fit(0.01, 0.02), fit(0.01, 0.02), NuisanceEstimate{}}, d);
  CHECK_FALSE(none.moved);
  CHECK(none.delays == std::array<double, 3>{0.005, 0.005, 0.005});
  CHECK(says(none, "its axis had no output-error fit"));

  d.estimate = {true, true, false};  // --command-delay for the rudder
  const DelayChoice given = choose_delays({0.0, 0.0, 0.012}, {fit(0.02, 0.001), fit(0.02, 0.001), fit(0.0, 0.02)}, d);
  CHECK(given.delays[2] == 0.012);
  CHECK(says(given, "command delay (rudder): 12 ms, given"));
  CHECK(given.shift[2].note == "given");
}

TEST_CASE("choose_delays: any adopted shift calls for a second pass, however small") {
  // a 1.5 +- 0.2 ms aileron, under the former 3-ms rule: each millisecond moves C_ell_p by some 2 %
  // on the Aerosonde's 47-ms roll mode (command_delay.hpp)
  const DelayChoice small = choose_delays({0.0, 0.0, 0.0}, {fit(0.0015, 0.0002), fit(0.0005, 0.001), fit(0.0005, 0.0003)}, DelayOptions{});
  CHECK(small.moved);
  CHECK(small.delays[0] == doctest::Approx(0.0015));
  CHECK(small.delays[1] == doctest::Approx(0.0005));
  CHECK(says(small, "command delay (aileron): 1.5 +- 0.2 ms after its stamp, from the output error of the roll and yaw rates"));
}
