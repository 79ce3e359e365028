// PhaseMachine alone, through the SDK's test harness (tern/testing/harness.hpp): each transition
// of phase_machine.hpp at its criterion and not before, the dwell of the transitions back, the
// arming checks' hold and time-out, the disarmed wait, and reset() between flights.
#include <doctest/doctest.h>

#include <memory>

#include "safety/phase_machine.hpp"
#include "tern/testing/harness.hpp"

using namespace tern;
using namespace tern::core;
using tern::testing::Harness;

namespace {

msg::State at_altitude(double h) {
  msg::State s;
  s.p_d = -h;
  s.valid = true;
  s.status = msg::StateStatus::ok;  // P_diag all 0: the covariance checks are skipped
  return s;
}

msg::ControllerCommand commanding(double h_c) {
  msg::ControllerCommand c;
  c.h_c = h_c;
  c.Va_c = 25.0;
  return c;
}

/// A phase machine after preflight (skipped), alt_toz 5 m, alt_hz 20 m, dwell 1 s.
Harness flying_machine() {
  return Harness(std::make_unique<PhaseMachine>(),
                 {{"preflight", false}, {"alt_toz", 5.0}, {"alt_hz", 20.0}, {"min_phase_time", 1.0}, {"safety", false}});
}

PhaseMachine& machine(Harness& h) { return static_cast<PhaseMachine&>(h.plugin()); }

/// Feeds altitude h (and h_c when given) and steps at t seconds.
void fly_at(Harness& h, double t, double alt, std::optional<double> h_c = std::nullopt) {
  h.set_input("state", at_altitude(alt));
  if (h_c) h.set_input("controller_command", commanding(*h_c));
  h.step(from_seconds(t));
}

}  // namespace

TEST_CASE("phase machine: takeoff -> climb at alt_toz, climb -> cruise within alt_hz of h_c, each published once") {
  Harness h = flying_machine();
  PhaseMachine& pm = machine(h);
  h.start();
  CHECK(pm.phase() == msg::Phase::takeoff);
  CHECK(h.output<msg::FlightPhase>("flight_phase").phase == msg::Phase::takeoff);
  const auto published_at_start = h.published("flight_phase");

  fly_at(h, 1.0, 4.9, 100.0);
  CHECK(pm.phase() == msg::Phase::takeoff);  // below alt_toz
  fly_at(h, 1.1, 5.0, 100.0);
  CHECK(pm.phase() == msg::Phase::climb);  // h >= alt_toz
  const auto& fp = h.output<msg::FlightPhase>("flight_phase");
  CHECK(fp.previous == msg::Phase::takeoff);
  CHECK(fp.phase == msg::Phase::climb);
  CHECK(fp.since == from_seconds(1.1));
  CHECK(h.published("flight_phase") == published_at_start + 1);

  fly_at(h, 2.0, 80.0, 100.0);  // |h_c - h| = 20: not < alt_hz
  CHECK(pm.phase() == msg::Phase::climb);
  fly_at(h, 2.1, 80.5, 100.0);
  CHECK(pm.phase() == msg::Phase::cruise);
  CHECK(h.published("flight_phase") == published_at_start + 2);

  REQUIRE(pm.transitions().size() == 2);
  CHECK(pm.transitions()[0].to == msg::Phase::climb);
  CHECK(pm.transitions()[0].t == from_seconds(1.1));
  CHECK(pm.transitions()[0].reason.find("alt_toz") != std::string::npos);
  CHECK(pm.transitions()[1].from == msg::Phase::climb);
  CHECK(pm.transitions()[1].to == msg::Phase::cruise);
  CHECK(pm.transitions()[1].reason.find("alt_hz") != std::string::npos);
}

TEST_CASE("phase machine: without a controller_command h_c is h: climb -> cruise at once") {
  Harness h = flying_machine();
  h.start();
  fly_at(h, 0.1, 6.0);
  CHECK(machine(h).phase() == msg::Phase::climb);
  fly_at(h, 0.2, 6.0);
  CHECK(machine(h).phase() == msg::Phase::cruise);
  CHECK(machine(h).commanded_altitude() == std::nullopt);
}

TEST_CASE("phase machine: cruise -> climb only after the altitude loss held min_phase_time; an interruption restarts the dwell") {
  Harness h = flying_machine();
  PhaseMachine& pm = machine(h);
  h.start();
  fly_at(h, 0.1, 6.0, 100.0);
  fly_at(h, 0.2, 95.0, 100.0);
  REQUIRE(pm.phase() == msg::Phase::cruise);

  fly_at(h, 10.0, 75.0, 100.0);  // 25 m below h_c: more than alt_hz
  fly_at(h, 10.5, 75.0, 100.0);
  fly_at(h, 10.6, 90.0, 100.0);  // back within alt_hz: the dwell restarts
  fly_at(h, 10.7, 75.0, 100.0);
  fly_at(h, 11.6, 75.0, 100.0);  // 0.9 s since 10.7
  CHECK(pm.phase() == msg::Phase::cruise);
  fly_at(h, 11.7, 75.0, 100.0);  // 1.0 s
  CHECK(pm.phase() == msg::Phase::climb);
  CHECK(pm.transitions().back().t == from_seconds(11.7));
  CHECK(pm.transitions().back().reason.find("below h_c") != std::string::npos);
}

TEST_CASE("phase machine: climb or cruise -> takeoff after min_phase_time below alt_toz") {
  Harness h = flying_machine();
  PhaseMachine& pm = machine(h);
  h.start();
  fly_at(h, 0.1, 6.0, 100.0);
  REQUIRE(pm.phase() == msg::Phase::climb);
  fly_at(h, 1.0, 4.0, 100.0);
  fly_at(h, 1.9, 4.0, 100.0);
  CHECK(pm.phase() == msg::Phase::climb);
  fly_at(h, 2.0, 4.0, 100.0);
  CHECK(pm.phase() == msg::Phase::takeoff);
  CHECK(pm.transitions().back().reason.find("fell below alt_toz") != std::string::npos);
}

TEST_CASE("phase machine: preflight holds until the arming checks passed preflight_time, then takeoff") {
  Harness h(std::make_unique<PhaseMachine>(), {{"preflight_time", 2.0}});
  PhaseMachine& pm = machine(h);
  h.start();
  CHECK(pm.first_phase() == msg::Phase::preflight);
  CHECK(pm.phase() == msg::Phase::preflight);

  msg::State not_aligned = at_altitude(0.0);
  not_aligned.valid = false;
  not_aligned.status = msg::StateStatus::invalid;
  h.set_input("state", not_aligned);
  h.step(from_seconds(1.0));
  CHECK(pm.phase() == msg::Phase::preflight);

  for (double t : {3.0, 4.0, 4.9}) {  // checks pass from t = 3: 1.9 s is not enough
    fly_at(h, t, 0.0);
    CHECK(pm.phase() == msg::Phase::preflight);
  }
  fly_at(h, 5.0, 0.0);
  CHECK(pm.phase() == msg::Phase::takeoff);
  CHECK(pm.transitions().back().reason.find("aligned at t=3.000 s") != std::string::npos);
  CHECK(pm.failure().empty());
}

TEST_CASE("phase machine: a failing check after preflight_timeout ends the flight with preflight_failed") {
  Harness h(std::make_unique<PhaseMachine>(), {{"preflight_timeout", 5.0}});
  PhaseMachine& pm = machine(h);
  h.start();
  msg::State invalid = at_altitude(0.0);
  invalid.valid = false;
  invalid.status = msg::StateStatus::invalid;
  h.set_input("state", invalid);
  h.step(from_seconds(1.0));
  h.step(from_seconds(5.9));
  CHECK(pm.failure().empty());
  h.step(from_seconds(6.0));
  CHECK(pm.failure().rfind("preflight_failed: ", 0) == 0);
  CHECK(pm.phase() == msg::Phase::preflight);
}

TEST_CASE("phase machine: the preflight time-out counts only once the FCU is armed") {
  Harness h(std::make_unique<PhaseMachine>(), {{"preflight_timeout", 5.0}});
  PhaseMachine& pm = machine(h);
  h.start();
  msg::FcuStatus fcu;
  fcu.armed = false;
  h.set_input("fcu_status", fcu);
  h.set_input("state", at_altitude(0.0));
  h.step(from_seconds(1.0));
  h.step(from_seconds(20.0));
  CHECK(pm.failure().empty());  // disarmed: arming late is no failure
  fcu.armed = true;
  fcu.error_code = 0x4;  // armed, but in error: still failing
  h.set_input("fcu_status", fcu);
  h.step(from_seconds(21.0));
  h.step(from_seconds(25.9));
  CHECK(pm.failure().empty());
  h.step(from_seconds(26.0));
  CHECK(pm.failure().find("FCU error code 0x04") != std::string::npos);
}

TEST_CASE("phase machine: after preflight a disarmed FCU holds the flight; armed and error-free it re-enters takeoff") {
  Harness h = flying_machine();
  PhaseMachine& pm = machine(h);
  h.start();
  msg::FcuStatus fcu;
  fcu.armed = true;
  h.set_input("fcu_status", fcu);
  fly_at(h, 0.1, 6.0, 100.0);
  REQUIRE(pm.phase() == msg::Phase::climb);

  fcu.armed = false;
  h.set_input("fcu_status", fcu);
  fly_at(h, 1.0, 6.0, 100.0);
  CHECK(pm.disarmed());
  CHECK(h.output<msg::FlightPhase>("flight_phase").phase == msg::Phase::takeoff);
  const auto recorded = pm.transitions().size();
  fly_at(h, 2.0, 90.0, 100.0);  // within alt_hz of h_c: cruise, were it not disarmed
  CHECK(pm.disarmed());
  CHECK(pm.transitions().size() == recorded);

  fcu.armed = true;
  fcu.error_code = 1;
  h.set_input("fcu_status", fcu);
  fly_at(h, 3.0, 90.0, 100.0);
  CHECK(pm.disarmed());  // armed but in error
  fcu.error_code = 0;
  h.set_input("fcu_status", fcu);
  fly_at(h, 4.0, 4.0, 100.0);  // below alt_toz: takeoff stays
  CHECK_FALSE(pm.disarmed());
  CHECK(pm.phase() == msg::Phase::takeoff);
  CHECK(pm.transitions().back().reason.find("FCU armed") != std::string::npos);
}

TEST_CASE("phase machine: reset() returns to the first phase with no transitions and no failure; the next flight repeats the first") {
  Harness h(std::make_unique<PhaseMachine>(), {{"preflight_timeout", 1.0}, {"preflight_time", 0.0}});
  PhaseMachine& pm = machine(h);
  h.start();
  h.step(from_seconds(0.5));  // no state: failing
  h.step(from_seconds(1.5));
  REQUIRE_FALSE(pm.failure().empty());
  h.reset();
  CHECK(pm.failure().empty());
  CHECK(pm.phase() == msg::Phase::preflight);
  CHECK(pm.transitions().empty());

  fly_at(h, 0.5, 0.0);  // the checks pass: preflight_time 0
  CHECK(pm.phase() == msg::Phase::takeoff);
  fly_at(h, 0.6, 6.0);
  REQUIRE(pm.transitions().size() == 2);
  CHECK(pm.transitions()[1].to == msg::Phase::climb);
  CHECK(pm.failure().empty());
}
