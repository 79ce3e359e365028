// The signal_generator's surface mode through the harness: pass-through outside a manoeuvre,
// the excitation added and clamped, the sequence, engagement from a parameter, the RC switch and
// the airspeed sequence, and the aborts (envelope, phase change).
#include <doctest/doctest.h>

#include <string>

#include "signal_generator_plugin.hpp"
#include "tern/aircraft.hpp"
#include "tern/testing/harness.hpp"

using namespace tern;
using tern::testing::Harness;

namespace {
msg::Actuators controller() {
  msg::Actuators a;
  a.delta_a = 0.01;
  a.delta_e = -0.03;
  a.delta_r = 0.002;
  a.delta_t = 0.55;
  return a;
}
msg::State level(double Va) {
  msg::State s;
  s.valid = true;
  s.Va = Va;
  s.p_d = -100.0;
  s.theta = 0.03;
  return s;
}
msg::FlightPhase cruise_since(double s) {
  msg::FlightPhase p;
  p.phase = msg::Phase::cruise;
  p.since = from_seconds(s);
  return p;
}
bool same(const msg::Actuators& a, const msg::Actuators& b) {
  return a.delta_a == b.delta_a && a.delta_e == b.delta_e && a.delta_r == b.delta_r && a.delta_t == b.delta_t && a.brake == b.brake;
}
std::map<std::string, ParamValue> doublet_on_elevator() {
  return {{"axis", std::string("delta_e")},
          {"waveform", std::string("doublet")},
          {"magnitude", std::vector<double>{0.05}},
          {"pulse_width", std::vector<double>{1.0}},
          {"start_time", 2.0},
          {"h_min", 50.0},
          {"Va_min", 15.0}};
}
}  // namespace

TEST_CASE("surface mode: pass-through before, the doublet added during, pass-through after") {
  Harness h(std::make_unique<signal::SignalGeneratorPlugin>(), doublet_on_elevator());
  h.start();
  h.set_input("controller_actuators", controller());
  h.set_input("state", level(25.0));
  h.set_input("flight_phase", cruise_since(1.0));
  h.step(from_seconds(2.5));
  CHECK(same(h.output<msg::Actuators>("actuators"), controller()));  // 1.5 s into cruise: not yet
  CHECK(h.output<msg::Actuators>("excitation").delta_e == 0.0);
  h.step(from_seconds(3.0));  // engaged: +magnitude for T_p
  CHECK(h.output<msg::Actuators>("actuators").delta_e == doctest::Approx(-0.03 + 0.05));
  CHECK(h.output<msg::Actuators>("actuators").delta_a == 0.01);
  CHECK(h.output<msg::Actuators>("actuators").delta_t == 0.55);
  CHECK(h.output<msg::Actuators>("excitation").delta_e == doctest::Approx(0.05));
  h.step(from_seconds(4.5));
  CHECK(h.output<msg::Actuators>("actuators").delta_e == doctest::Approx(-0.03 - 0.05));
  h.step(from_seconds(5.0));  // 2 T_p: over
  CHECK(same(h.output<msg::Actuators>("actuators"), controller()));
  h.step(from_seconds(30.0));
  CHECK(same(h.output<msg::Actuators>("actuators"), controller()));
  const auto s = h.plugin().summary();
  CHECK(s[0] == std::pair<std::string, double>{"manoeuvres", 1.0});
}

TEST_CASE("surface mode: surfaces clamped to the aircraft's limits, the throttle to [0, 1]") {
  auto p = doublet_on_elevator();
  p["axis"] = std::string("delta_a, delta_t");
  p["magnitude"] = std::vector<double>{0.9, 0.9};
  p["t_gap"] = 0.0;
  Harness h(std::make_unique<signal::SignalGeneratorPlugin>(), p);
  h.start();
  h.set_input("controller_actuators", controller());
  h.set_input("state", level(25.0));
  h.set_input("flight_phase", cruise_since(0.0));
  h.step(from_seconds(2.0));
  const double limit = tern::Aircraft{}.max_delta_a;
  CHECK(h.output<msg::Actuators>("actuators").delta_a == limit);
  h.step(from_seconds(3.5));
  CHECK(h.output<msg::Actuators>("actuators").delta_a == -limit);
  h.step(from_seconds(4.0));  // the aileron's doublet ended; the throttle's begins after t_gap 0 on the next step
  h.step(from_seconds(4.01));
  CHECK(h.output<msg::Actuators>("actuators").delta_t == 1.0);
  CHECK(h.output<msg::Actuators>("actuators").delta_a == 0.01);
  h.step(from_seconds(5.5));
  CHECK(h.output<msg::Actuators>("actuators").delta_t == 0.0);
}

TEST_CASE("surface mode: the envelope aborts at once and hands control back for the rest of the flight") {
  auto p = doublet_on_elevator();
  p["waveform"] = std::string("chirp");
  p["t_rec"] = std::vector<double>{20.0};
  p["phi_max"] = 0.5;
  Harness h(std::make_unique<signal::SignalGeneratorPlugin>(), p);
  h.start();
  h.set_input("controller_actuators", controller());
  h.set_input("state", level(25.0));
  h.set_input("flight_phase", cruise_since(0.0));
  h.step(from_seconds(2.0));
  h.step(from_seconds(5.0));
  CHECK(!same(h.output<msg::Actuators>("actuators"), controller()));
  auto rolled = level(25.0);
  rolled.phi = -0.6;
  h.set_input("state", rolled);
  h.step(from_seconds(5.01));
  CHECK(same(h.output<msg::Actuators>("actuators"), controller()));
  h.set_input("state", level(25.0));
  h.step(from_seconds(6.0));
  CHECK(same(h.output<msg::Actuators>("actuators"), controller()));
  const auto s = h.plugin().summary();
  CHECK(s[1] == std::pair<std::string, double>{"aborts", 1.0});
}

TEST_CASE("surface mode: below Va_min, below h_min, an invalid estimate or a phase change aborts") {
  for (int cause = 0; cause < 4; ++cause) {
    auto p = doublet_on_elevator();
    p["pulse_width"] = std::vector<double>{5.0};
    Harness h(std::make_unique<signal::SignalGeneratorPlugin>(), p);
    h.start();
    h.set_input("controller_actuators", controller());
    h.set_input("state", level(25.0));
    h.set_input("flight_phase", cruise_since(0.0));
    h.step(from_seconds(2.0));
    CHECK(!same(h.output<msg::Actuators>("actuators"), controller()));
    auto s = level(25.0);
    if (cause == 0) s.Va = 14.0;
    if (cause == 1) s.p_d = -40.0;
    if (cause == 2) s.valid = false;
    h.set_input("state", s);
    if (cause == 3) {
      msg::FlightPhase approach;
      approach.phase = msg::Phase::approach;
      h.set_input("flight_phase", approach);
    }
    h.step(from_seconds(2.01));
    CHECK(same(h.output<msg::Actuators>("actuators"), controller()));
  }
}

TEST_CASE("surface mode: a multisine on two surfaces at once; engage now and off at run time") {
  auto p = doublet_on_elevator();
  p["axis"] = std::string("delta_a+delta_r");
  p["waveform"] = std::string("multisine");
  p["magnitude"] = std::vector<double>{0.06, 0.04};
  p["engage"] = std::string("off");
  p["f_start_hz"] = std::vector<double>{0.1};
  p["f_stop_hz"] = std::vector<double>{2.0};
  p["t_rec"] = std::vector<double>{20.0};
  Harness h(std::make_unique<signal::SignalGeneratorPlugin>(), p);
  h.start();
  h.set_input("controller_actuators", controller());
  h.set_input("state", level(25.0));
  h.set_input("flight_phase", cruise_since(0.0));
  h.step(from_seconds(10.0));
  CHECK(same(h.output<msg::Actuators>("actuators"), controller()));  // engage off: the mission's start is skipped
  h.set_param("engage", std::string("now"));
  double peak_a = 0.0, peak_r = 0.0;
  for (int i = 0; i < 1000; ++i) {
    h.step(from_seconds(10.0 + 0.01 * i));
    const auto& x = h.output<msg::Actuators>("excitation");
    peak_a = std::max(peak_a, std::abs(x.delta_a));
    peak_r = std::max(peak_r, std::abs(x.delta_r));
    CHECK(x.delta_e == 0.0);
  }
  CHECK(peak_a <= 0.06);
  CHECK(peak_a > 0.05);
  CHECK(peak_r <= 0.04);
  CHECK(peak_r > 0.033);
  h.set_param("engage", std::string("off"));
  h.step(from_seconds(20.01));
  CHECK(same(h.output<msg::Actuators>("actuators"), controller()));
}

TEST_CASE("surface mode: the RC switch engages and aborts") {
  auto p = doublet_on_elevator();
  p["engage"] = std::string("off");
  p["rc_channel"] = std::int64_t{2};
  p["pulse_width"] = std::vector<double>{5.0};
  Harness h(std::make_unique<signal::SignalGeneratorPlugin>(), p);
  h.start();
  h.set_input("controller_actuators", controller());
  h.set_input("state", level(25.0));
  msg::Rc rc;
  h.set_input("rc", rc);
  h.step(from_seconds(1.0));
  CHECK(same(h.output<msg::Actuators>("actuators"), controller()));
  rc.aux[2] = 1.0;
  h.set_input("rc", rc);
  h.step(from_seconds(1.01));
  CHECK(h.output<msg::Actuators>("excitation").delta_e == doctest::Approx(0.05));
  rc.aux[2] = -1.0;
  h.set_input("rc", rc);
  h.step(from_seconds(1.02));
  CHECK(same(h.output<msg::Actuators>("actuators"), controller()));
  rc.aux[2] = 1.0;  // up again: a new run
  h.set_input("rc", rc);
  h.step(from_seconds(1.03));
  CHECK(h.output<msg::Actuators>("excitation").delta_e == doctest::Approx(0.05));
  rc.rc_override = true;  // the pilot takes over: abort, whatever the switch says
  h.set_input("rc", rc);
  h.step(from_seconds(1.04));
  CHECK(same(h.output<msg::Actuators>("actuators"), controller()));
  CHECK(h.plugin().summary()[1].second == 2.0);
}

TEST_CASE("surface mode: with Va_sequence the list is flown at each airspeed once the estimate holds it") {
  auto p = doublet_on_elevator();
  p["Va_sequence"] = std::vector<double>{20.0, 25.0};
  p["t_settle"] = 2.0;
  p["start_time"] = 0.0;
  Harness h(std::make_unique<signal::SignalGeneratorPlugin>(), p);
  h.start();
  h.set_input("controller_actuators", controller());
  h.set_input("flight_phase", cruise_since(0.0));
  h.set_input("state", level(23.0));
  h.step(from_seconds(0.0));
  h.step(from_seconds(5.0));
  CHECK(h.output<msg::Actuators>("excitation").delta_e == 0.0);  // 3 m/s off the first airspeed
  h.set_input("state", level(20.3));
  h.step(from_seconds(6.0));
  h.step(from_seconds(7.9));
  CHECK(h.output<msg::Actuators>("excitation").delta_e == 0.0);  // steady 1.9 s of 2
  h.step(from_seconds(8.0));
  CHECK(h.output<msg::Actuators>("excitation").delta_e == doctest::Approx(0.05));
  h.step(from_seconds(10.0));  // the doublet ends; the next airspeed is awaited
  h.step(from_seconds(20.0));
  CHECK(h.output<msg::Actuators>("excitation").delta_e == 0.0);
  h.set_input("state", level(25.2));
  h.step(from_seconds(21.0));
  h.step(from_seconds(23.0));
  CHECK(h.output<msg::Actuators>("excitation").delta_e == doctest::Approx(0.05));
  h.reset();  // as between flights: everything again from the start
  h.set_input("controller_actuators", controller());
  h.set_input("state", level(25.2));
  h.step(from_seconds(1.0));
  CHECK(same(h.output<msg::Actuators>("actuators"), controller()));
}

TEST_CASE("surface mode: bad lists are one error naming the parameter and the value") {
  const auto refused = [](std::map<std::string, ParamValue> p, const std::string& needle) {
    auto q = doublet_on_elevator();
    for (auto& [k, v] : p) q[k] = v;
    try {
      Harness h(std::make_unique<signal::SignalGeneratorPlugin>(), q);
    } catch (const ParamError& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(needle) != std::string::npos);
      return;
    }
    FAIL("accepted");
  };
  refused({{"axis", std::string("delta_x")}}, "\"delta_x\": not a surface");
  refused({{"axis", std::string("roll")}}, "a loop");
  refused({{"axis", std::string("delta_a+delta_r")}}, "need waveform multisine");
  refused({{"waveform", std::string("chirp")}, {"f_start_hz", std::vector<double>{2.0}}, {"f_stop_hz", std::vector<double>{1.0}}},
          "f_stop_hz 1 must be above f_start_hz 2");
  refused({{"axis", std::string("delta_a, delta_e")}, {"magnitude", std::vector<double>{0.1, 0.2, 0.3}}}, "magnitude");
  refused({{"waveform", std::string("sine")}}, "\"sine\": not a surface-mode waveform");
  CHECK_THROWS_AS(
      Harness(std::make_unique<signal::SignalGeneratorPlugin>(), {{"axis", std::string("delta_e")}, {"t_rec", std::vector<double>{-1.0}}}),
      ParamError);
}
