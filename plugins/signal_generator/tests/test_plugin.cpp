// The signal_generator adapter through the harness: it passes the follower's command, engages
// at start_time after the first cruise, and replaces exactly the chosen loop's command.
#include <doctest/doctest.h>

#include "signal_generator_plugin.hpp"
#include "tern/testing/harness.hpp"

using namespace tern;
using tern::testing::Harness;

namespace {
msg::ControllerCommand follower() {
  msg::ControllerCommand c;
  c.Va_c = 17.0;
  c.h_c = 70.0;
  c.chi_c = 0.5;
  return c;
}
msg::FlightPhase cruise_since(double s) {
  msg::FlightPhase p;
  p.phase = msg::Phase::cruise;
  p.since = from_seconds(s);
  return p;
}
}  // namespace

TEST_CASE("altitude square wave: passes through, engages after cruise + start_time, replaces h_c only") {
  Harness h(std::make_unique<signal::SignalGeneratorPlugin>(),
            {{"loop", std::string("altitude")}, {"amplitude", 10.0}, {"offset", -5.0}, {"period", 20.0}, {"start_time", 5.0}});
  h.start();
  h.set_input("follower_command", follower());
  h.step(from_seconds(1.0));
  CHECK(h.output<msg::ControllerCommand>("controller_command").h_c == 70.0);  // no cruise yet
  h.set_input("flight_phase", cruise_since(2.0));
  h.step(from_seconds(6.9));
  CHECK(h.output<msg::ControllerCommand>("controller_command").h_c == 70.0);  // 4.9 s into cruise
  h.step(from_seconds(7.0));
  const auto& low = h.output<msg::ControllerCommand>("controller_command");
  CHECK(low.h_c == doctest::Approx(65.0));
  CHECK(low.Va_c == 17.0);
  CHECK(low.chi_c == 0.5);
  CHECK(!low.override_phi);
  h.step(from_seconds(17.0));
  CHECK(h.output<msg::ControllerCommand>("controller_command").h_c == doctest::Approx(75.0));
  h.step(from_seconds(27.0));
  CHECK(h.output<msg::ControllerCommand>("controller_command").h_c == doctest::Approx(65.0));
}

TEST_CASE("roll: phi_c from the controller's inner command plus the signal, with override_phi") {
  Harness h(
      std::make_unique<signal::SignalGeneratorPlugin>(),
      {{"loop", std::string("roll")}, {"amplitude", 0.2}, {"period", 4.0}, {"start_time", 1.0}, {"start_phase", std::string("flight")}});
  h.start();
  h.set_input("follower_command", follower());
  msg::ControllerInternals in;
  in.phi_c = 0.05;
  h.set_input("controller_internals", in);
  h.step(from_seconds(0.5));
  CHECK(!h.output<msg::ControllerCommand>("controller_command").override_phi);
  h.step(from_seconds(1.0));
  CHECK(h.output<msg::ControllerCommand>("controller_command").override_phi);
  CHECK(h.output<msg::ControllerCommand>("controller_command").phi_c == doctest::Approx(0.05));
  h.step(from_seconds(3.0));
  CHECK(h.output<msg::ControllerCommand>("controller_command").phi_c == doctest::Approx(0.25));
  CHECK(h.output<msg::ControllerCommand>("controller_command").chi_c == 0.5);
}

TEST_CASE("reset: the next flight waits for its own cruise") {
  Harness h(std::make_unique<signal::SignalGeneratorPlugin>(), {{"loop", std::string("airspeed")},
                                                                {"start_time", 0.0},
                                                                {"amplitude", 2.0},
                                                                {"reference", std::string("absolute")},
                                                                {"offset", 15.0}});
  h.start();
  h.set_input("follower_command", follower());
  h.set_input("flight_phase", cruise_since(0.0));
  h.step(from_seconds(0.0));
  CHECK(h.output<msg::ControllerCommand>("controller_command").Va_c == doctest::Approx(15.0));
  h.reset();  // as between flights: the inputs are empty until the producers publish again
  h.set_input("follower_command", follower());
  msg::FlightPhase climb;
  climb.phase = msg::Phase::climb;
  h.set_input("flight_phase", climb);
  h.step(from_seconds(1.0));
  CHECK(h.output<msg::ControllerCommand>("controller_command").Va_c == 17.0);
}

TEST_CASE("an unknown loop is refused when configured") {
  CHECK_THROWS_AS(Harness(std::make_unique<signal::SignalGeneratorPlugin>(), {{"loop", std::string("yaw_rate")}}), ParamError);
}
