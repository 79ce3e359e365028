// control_tecs tests: the TECS law alone, and the plugin in the SDK harness flying the uavbook's
// linearised models (control_common/testing/linear_model.hpp) with the gains files
// configs/gains/*_tecs.yaml.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "control_common/testing/closed_loop.hpp"
#include "control_tecs.hpp"

using namespace tern;
using namespace tern::control;
using namespace tern::control::testmodel;

namespace {

struct Aircraft {
  const char* gains;
  Coefficients k;
};
const Aircraft kAircraft[] = {{TERN_GAINS_DIR "/anaconda_tecs.yaml", anaconda()}, {TERN_GAINS_DIR "/aerosonde_tecs.yaml", aerosonde()}};

std::unique_ptr<ClosedLoop> make(const Aircraft& a) { return settled_loop(std::make_unique<ControlTecs>(), a.k, a.gains); }
}  // namespace

TEST_CASE("tecs law: a climb demand raises throttle and pitch; a speed demand raises throttle, lowers pitch") {
  Tecs t;
  VehicleState x;
  x.Va = 18.0;
  x.h = 100.0;
  Command c{18.0, 100.0, 0.0, 0.0, 0.0, 0.0, false, false};
  t.update(x, c, false, 0.0);
  const auto level = t.update(x, c, false, 0.01);
  t.reset();
  c.h_c = 120.0;
  t.update(x, c, false, 0.0);
  const auto climb = t.update(x, c, false, 0.01);
  CHECK(climb.delta_t > level.delta_t + 0.05);
  CHECK(climb.theta_c > level.theta_c + 0.05);
  t.reset();
  c.h_c = 100.0;
  c.Va_c = 22.0;
  t.update(x, c, false, 0.0);
  const auto faster = t.update(x, c, false, 0.01);
  CHECK(faster.delta_t > level.delta_t + 0.05);
  CHECK(faster.theta_c < level.theta_c - 0.02);
}

TEST_CASE("tecs law: underspeed protection gives full throttle and trades height for speed") {
  TecsGains g;
  g.Va_min = 15.0;
  g.max_t = 0.9;
  Tecs t;
  t.set_gains(g);
  VehicleState x;
  x.Va = 13.0;
  x.h = 100.0;
  Command c{18.0, 150.0, 0.0, 0.0, 0.0, 0.0, false, false};  // climb demanded while too slow
  t.update(x, c, false, 0.0);
  const auto o = t.update(x, c, false, 0.01);
  CHECK(t.underspeed());
  CHECK(o.delta_t == doctest::Approx(0.9));
  CHECK(o.theta_c < 0.0);  // nose down to gain speed despite the climb demand
  x.Va = 15.5;             // inside the hysteresis band: still protecting
  t.update(x, c, false, 0.01);
  CHECK(t.underspeed());
  x.Va = 16.5;
  t.update(x, c, false, 0.01);
  CHECK_FALSE(t.underspeed());
  // airspeed demands below Va_min are raised to Va_min
  Tecs t2;
  t2.set_gains(g);
  x.Va = 15.5;
  c = {10.0, 100.0, 0.0, 0.0, 0.0, 0.0, false, false};
  t2.update(x, c, false, 0.0);
  const auto slow = t2.update(x, c, false, 0.01);
  c.Va_c = 15.0;
  Tecs t3;
  t3.set_gains(g);
  t3.update(x, c, false, 0.0);
  CHECK(slow.delta_t == doctest::Approx(t3.update(x, c, false, 0.01).delta_t));
}

TEST_CASE("tecs: 10 m altitude step settles within 2 m in < 15 s with < 3 m overshoot") {
  for (const auto& a : kAircraft) {
    CAPTURE(std::string(a.gains));
    for (double step : {10.0, -10.0}) {
      auto Lp = make(a);
      auto& L = *Lp;
      const double h0 = L.plant.h;
      L.cmd.h_c = h0 + step;
      StepResponse r{h0, h0 + step, 2.0};
      const double t0 = to_seconds(L.t);
      double V_dev = 0.0;
      L.run(40.0, [&](double t, const LinearAircraft& p) {
        r.add(t - t0, p.h);
        V_dev = std::max(V_dev, std::fabs(p.Va - a.k.Va_trim));
      });
      MESSAGE(std::string(a.gains), ": altitude step ", step, " m: overshoot ", r.overshoot, " m, settles at ", r.settle_time,
              " s, airspeed deviation ", V_dev, " m/s");
      CHECK(r.overshoot < 3.0);
      CHECK(r.settle_time < 15.0);
      CHECK(std::fabs(L.plant.h - (h0 + step)) < 0.5);
      CHECK(V_dev < 2.0);  // energy is traded, not lost
    }
  }
}

TEST_CASE("tecs: 3 m/s airspeed step settles in < 10 s and holds altitude") {
  for (const auto& a : kAircraft) {
    CAPTURE(std::string(a.gains));
    for (double step : {3.0, -3.0}) {
      auto Lp = make(a);
      auto& L = *Lp;
      const double V0 = L.plant.Va;
      const double h0 = L.plant.h;
      L.cmd.Va_c = V0 + step;
      StepResponse r{V0, V0 + step, 0.3};
      const double t0 = to_seconds(L.t);
      double h_dev = 0.0;
      L.run(30.0, [&](double t, const LinearAircraft& p) {
        r.add(t - t0, p.Va);
        h_dev = std::max(h_dev, std::fabs(p.h - h0));
      });
      MESSAGE(std::string(a.gains), ": airspeed step ", step, " m/s settles at ", r.settle_time, " s, altitude deviation ", h_dev, " m");
      CHECK(r.settle_time < 10.0);
      CHECK(h_dev < 3.0);
    }
  }
}

TEST_CASE("tecs: the lateral loops are the shared ones: 90-degree course step overshoots < 10 degrees") {
  for (const auto& a : kAircraft) {
    auto Lp = make(a);
    auto& L = *Lp;
    L.cmd.chi_c = 90 * kRadPerDeg;
    double overshoot = 0.0;
    L.run(40.0, [&](double, const LinearAircraft& p) { overshoot = std::max(overshoot, (p.chi - 90 * kRadPerDeg) / kRadPerDeg); });
    CHECK(overshoot < 10.0);
    CHECK(std::fabs(L.plant.chi - 90 * kRadPerDeg) < 1 * kRadPerDeg);
  }
}

TEST_CASE("tecs: take_over is bumpless and the flight continues") {
  auto Lp = make(kAircraft[0]);
  auto& L = *Lp;
  msg::Actuators last;
  last.delta_a = -0.1;
  last.delta_e = L.last.delta_e + 0.1;
  last.delta_r = -0.05;
  last.delta_t = 0.9;
  L.cmd.h_c += 15.0;
  L.h.plugin().take_over(last);
  L.run(0.01);
  const auto& a = L.h.output<msg::Actuators>("actuators");
  CHECK(std::fabs(a.delta_a - last.delta_a) < 0.05);
  CHECK(std::fabs(a.delta_e - last.delta_e) < 0.05);
  CHECK(std::fabs(a.delta_r - last.delta_r) < 0.05);
  CHECK(std::fabs(a.delta_t - last.delta_t) < 0.05);
  Surfaces prev = L.last;
  double max_jump = 0.0;
  for (int i = 0; i < 3000; ++i) {
    L.run(0.01);
    const double j = std::max(std::fabs(L.last.delta_a - prev.delta_a), std::fabs(L.last.delta_e - prev.delta_e));
    max_jump = std::max(max_jump, j);
    prev = L.last;
  }
  CHECK(max_jump < 0.08);  // the loops' own response to the disturbed state: no jumps (< 8 rad/s)
  CHECK(std::fabs(L.plant.h - L.cmd.h_c) < 2.0);
}

TEST_CASE("tecs: out-of-range parameters rejected, NaN input held") {
  CHECK_THROWS_AS(testing::Harness(std::make_unique<ControlTecs>(), {{"energy_kp", -1.0}}), ParamError);
  CHECK_THROWS_AS(testing::Harness(std::make_unique<ControlTecs>(), {{"climb_rate_max", 0.0}}), ParamError);
  CHECK_THROWS_AS(testing::Harness(std::make_unique<ControlTecs>(), {{"altitude_kp", 0.1}}), ParamError);  // an SLC gain
  for (const auto& a : kAircraft) CHECK_NOTHROW(testing::Harness(std::make_unique<ControlTecs>(), load_gains(a.gains)));
  auto Lp = make(kAircraft[0]);
  auto& L = *Lp;
  const Surfaces before = L.last;
  auto s = to_state(L.plant, L.t);
  s.p_d = std::numeric_limits<double>::quiet_NaN();
  L.h.set_input("state", s);
  L.h.step(L.t += from_seconds(0.01));
  const auto& out = L.h.output<msg::Actuators>("actuators");
  CHECK(out.delta_t == before.delta_t);
  CHECK(out.delta_e == before.delta_e);
}
