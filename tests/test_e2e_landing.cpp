// End-to-end: the landing and the takeoff's aborts (issue 46) on the default mission's world, on
// seeds the tuning never saw: the land item flown to a stop in a crosswind with gusts, a go-around
// when the approach is not stabilised (and the landing abandoned after land_attempts) or the
// operator commands it, a takeoff
// aborted on its run, and a takeoff refused in more wind than the preflight allows.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "e2e_util.hpp"

using namespace tern;
using namespace tern::core;

namespace {
/// default.yaml flown one loop of the hourglass before the land item, with `edits`.
std::string one_loop(std::vector<std::pair<std::string, std::string>> edits) {
  edits.insert(edits.begin(), {"loops: 5", "loops: 1"});
  return default_mission_with(edits);
}

std::vector<std::string> phases_of(const nlohmann::json& s) {
  std::vector<std::string> out;
  for (const auto& p : s["phases"]) out.push_back(p["phase"]);
  return out;
}
}  // namespace

TEST_CASE("landing: a 5 m/s crosswind with gusts, seeds the tuning never saw: landed on the centre line") {
  // runway heading 135 deg; the wind blows from the north-east (45 deg), across it
  for (const int seed : {101, 102, 103}) {
    CAPTURE(seed);
    const std::string text = one_loop({{"seed: 1", "seed: " + std::to_string(seed)},
                                       {"wind: [3.5355, -3.5355, 0.0]", "wind: [-3.5355, -3.5355, 0.0]"},
                                       {"turbulence: light", "turbulence: light\n      gust_rate: 0.1\n      gust_max: 3.0"}});
    const FlightResult r = fly_text(text, "land_cross.yaml", "e2e_land_cross_" + std::to_string(seed), 900.0);
    const auto s = summary(r);
    CHECK(s["end_reason"] == "landed");
    CHECK(r.ok);
    const auto& td = s["metrics"]["landing"];
    MESSAGE("seed " << seed << ": " << td.dump() << ", go-arounds " << s["instances"]["phase_machine"]["go_arounds"] << " "
                    << s.value("end_detail", ""));
    CHECK(td["stopped"] == true);
    CHECK(std::fabs(td["touchdown_across_m"].get<double>()) < 4.0);
    CHECK(std::fabs(td["touchdown_along_m"].get<double>()) < 40.0);
    CHECK(td["sink_rate_mps"].get<double>() < 2.0);
    CHECK(std::fabs(td["roll_deg"].get<double>()) < 10.0);
  }
}

TEST_CASE("landing: an approach not stabilised at the decision height goes around; after land_attempts it is abandoned") {
  // a cross-track limit no approach meets: every approach goes around at the decision height
  const std::string text = one_loop({{"phases:", "phase_machine: {land_max_cross_track: 0.1}\nphases:"},
                                     {"params: {turn_bank: 0.52}", "params: {turn_bank: 0.52, land_attempts: 2}"}});
  const FlightResult r = fly_text(text, "land_goaround.yaml", "e2e_land_goaround", 1500.0);
  const auto s = summary(r);
  CHECK(s["end_reason"] == "duration");  // no landing: the aircraft orbits above the touchdown point
  CHECK(s["instances"]["phase_machine"]["go_arounds"] == 2.0);
  CHECK(s["instances"]["manager"]["land_approaches"] == 2.0);
  CHECK(s["instances"]["manager"]["land_abandoned"] == 1.0);
  CHECK(s["instances"]["sim"]["sim_crashed"] == 0.0);
  int go_arounds = 0;
  for (const auto& p : s["phases"]) {
    const std::string reason = p.value("reason", "");
    if (reason.find("go-around: not stabilised") != std::string::npos) {
      ++go_arounds;
      CHECK(reason.find("cross-track") != std::string::npos);
      CHECK(p["phase"] == "climb");
    }
  }
  CHECK(go_arounds == 2);
  CHECK_FALSE(s["metrics"].contains("landing"));  // never touched down
}

TEST_CASE("landing: the operator's go-around is taken on the approach and refused in cruise; the next approach lands") {
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / "e2e_land_operator";
  o.duration = 1100.0;
  Host h(load_config(write_file("land_operator.yaml", one_loop({}))), o);
  h.build();
  const OutputBase* phase = h.topic_source("flight_phase");
  REQUIRE(phase != nullptr);
  bool asked_in_cruise = false, asked_on_approach = false;
  Nanos approach_since = -1;
  h.add_tick_observer([&](Nanos now) {
    const auto ph = static_cast<const msg::FlightPhase*>(phase->data())->phase;
    if (ph == msg::Phase::cruise && !asked_in_cruise && now > from_seconds(60.0)) {
      asked_in_cruise = true;  // not on a landing: logged, not taken
      h.go_around("test, in cruise");
    }
    if (ph == msg::Phase::approach && approach_since < 0) approach_since = now;
    if (ph == msg::Phase::approach && !asked_on_approach && now - approach_since > from_seconds(10.0)) {
      asked_on_approach = true;
      h.go_around("test");
    }
  });
  const FlightResult r = h.fly();
  const auto s = summary(r);
  CHECK(asked_in_cruise);
  CHECK(asked_on_approach);
  CHECK(s["end_reason"] == "landed");
  CHECK(s["instances"]["phase_machine"]["go_arounds"] == 1.0);
  CHECK(s["instances"]["manager"]["land_approaches"] == 2.0);
  int commanded = 0;
  for (const auto& p : s["phases"])
    if (p.value("reason", "").find("go-around: the operator's command (test)") != std::string::npos) ++commanded;
  CHECK(commanded == 1);
}

TEST_CASE("takeoff: the airspeed not building within the runway aborts it: motor off, brakes, stopped, the criterion named") {
  const std::string text =
      default_mission_with({{"phases:", "phase_machine: {takeoff_run_length: 15, takeoff_min_airspeed: 30}\nphases:"}});
  const FlightResult r = fly_text(text, "takeoff_abort.yaml", "e2e_takeoff_abort", 120.0);
  const auto s = summary(r);
  CHECK_FALSE(r.ok);
  const std::string reason = s["end_reason"];
  CHECK(reason.rfind("takeoff_aborted: airspeed", 0) == 0);
  CHECK(reason.find("after 15 m of runway") != std::string::npos);
  CHECK(phases_of(s) == std::vector<std::string>{"preflight", "takeoff", "rollout", "stopped"});
  CHECK(s["instances"]["phase_machine"]["takeoff_aborted"] == 1.0);
  CHECK(s["instances"]["sim"]["sim_crashed"] == 0.0);
}

TEST_CASE("preflight: more wind at rest than preflight_max_wind refuses the takeoff with one line naming it") {
  // 12 m/s from the south-east, the way the aircraft points: its pitot sees it
  const std::string text = default_mission_with(
      {{"wind: [3.5355, -3.5355, 0.0]", "wind: [8.485, -8.485, 0.0]"}, {"phases:", "phase_machine: {preflight_timeout: 20}\nphases:"}});
  const FlightResult r = fly_text(text, "preflight_wind.yaml", "e2e_preflight_wind", 120.0);
  const auto s = summary(r);
  const std::string reason = s["end_reason"];
  MESSAGE(reason);
  CHECK(reason.rfind("preflight_failed", 0) == 0);
  CHECK(reason.find("wind at rest") != std::string::npos);
  CHECK(reason.find("preflight_max_wind") != std::string::npos);
}
