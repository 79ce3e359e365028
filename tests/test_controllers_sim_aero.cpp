// control_slc and control_tecs flying the nonlinear 6-DOF model (Beard & McLain ch. 3-4,
// tern/aero/model.hpp, in sim_aero's world) with the gains files: the step-response requirements
// of issue 5 on the full model, and a takeoff from rest through takeoff -> climb -> cruise.
// The state is the simulator's truth (no estimator).
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "control_common/testing/closed_loop.hpp"
#include "control_slc.hpp"
#include "control_tecs.hpp"
#include "tern/aircraft.hpp"
#include "tern_sim_aero/simulator.hpp"
#include "tern/aero/trim.hpp"
#include "tern_sim_aero/wind.hpp"

using namespace tern;
using namespace tern::control;

namespace {

msg::State truth(const sim::Simulator& s) {
  const auto& x = s.state();
  const Eigen::Quaterniond q(x[sim::E0], x[sim::E1], x[sim::E2], x[sim::E3]);
  const Eigen::Vector3d eul = euler_from_quaternion(q);
  const Eigen::Vector3d v_body(x[sim::U], x[sim::V], x[sim::W]);
  const Eigen::Vector3d v_ned = q.normalized() * v_body;
  msg::State m;
  m.p_n = x[sim::PN];
  m.p_e = x[sim::PE];
  m.p_d = x[sim::PD];
  m.u = v_body.x();
  m.v = v_body.y();
  m.w = v_body.z();
  m.v_n = v_ned.x();
  m.v_e = v_ned.y();
  m.v_d = v_ned.z();
  m.phi = eul.x();
  m.theta = eul.y();
  m.psi = eul.z();
  m.quat = q.normalized();
  m.p = x[sim::P];
  m.q = x[sim::Q];
  m.r = x[sim::R];
  m.Va = (v_ned - s.wind_ned()).norm();
  const Eigen::Vector3d w = s.wind_ned();
  m.w_n = w.x();
  m.w_e = w.y();
  m.w_d = w.z();
  m.Vg = std::hypot(v_ned.x(), v_ned.y());
  m.chi = m.Vg > 0.5 ? std::atan2(v_ned.y(), v_ned.x()) : m.psi;
  m.valid = true;
  return m;
}

struct Flight {
  sim::Simulator sim;
  testing::Harness h;
  msg::ControllerCommand cmd;
  msg::FlightPhase phase;
  Nanos t = 0;
  Flight(const std::string& aircraft, std::unique_ptr<Plugin> ctl, const std::string& gains)
      : sim(tern::load_aircraft(aircraft), 7), h(std::move(ctl), testmodel::load_gains(gains)) {
    phase.phase = msg::Phase::cruise;
  }
  void start_at_trim(double Va, double altitude) {
    sim::TrimRequest req;
    req.Va = Va;
    req.altitude = altitude;
    const auto tr = sim::compute_trim(sim.aircraft(), req);
    sim.set_state(tr.x, tr.delta);
    sim.set_command(tr.delta);
    cmd.Va_c = Va;
    cmd.h_c = altitude;
    cmd.chi_c = 0.0;
  }
  /// 100 Hz controller, 400 Hz simulation.
  void run(double seconds, const std::function<void(double, const msg::State&)>& watch = {}) {
    const int n = static_cast<int>(std::lround(seconds * 100));
    for (int i = 0; i < n; ++i) {
      const msg::State s = truth(sim);
      h.set_input("state", s);
      h.set_input("controller_command", cmd);
      h.set_input("flight_phase", phase);
      h.step(t);
      const auto& a = h.output<msg::Actuators>("actuators");
      sim::Deltas d;
      d.delta_a = a.delta_a;
      d.delta_e = a.delta_e;
      d.delta_r = a.delta_r;
      d.delta_t = a.delta_t;
      sim.set_command(d);
      for (int k = 0; k < 4; ++k) sim.step(0.0025);
      t += 10'000'000;
      if (watch) watch(to_seconds(t), truth(sim));
    }
  }
};

struct Case {
  const char* name;
  const char* aircraft;
  const char* gains;
  double Va;
  bool tecs;
};
const Case kCases[] = {
    {"slc anaconda", TERN_AIRCRAFT_DIR "/anaconda.yaml", TERN_GAINS_DIR "/anaconda.yaml", 17.0, false},
    {"tecs anaconda", TERN_AIRCRAFT_DIR "/anaconda.yaml", TERN_GAINS_DIR "/anaconda_tecs.yaml", 17.0, true},
    {"slc aerosonde", TERN_AIRCRAFT_DIR "/aerosonde.yaml", TERN_GAINS_DIR "/aerosonde.yaml", 25.0, false},
    {"tecs aerosonde", TERN_AIRCRAFT_DIR "/aerosonde.yaml", TERN_GAINS_DIR "/aerosonde_tecs.yaml", 25.0, true},
};

std::unique_ptr<Plugin> controller(const Case& c) {
  if (c.tecs) return std::make_unique<ControlTecs>();
  return std::make_unique<ControlSlc>();
}
}  // namespace

TEST_CASE("sim_aero: altitude, course and airspeed steps on the nonlinear model") {
  for (const auto& c : kCases) {
    CAPTURE(std::string(c.name));
    Flight f(c.aircraft, controller(c), c.gains);
    f.start_at_trim(c.Va, 100.0);
    f.run(20.0);
    CHECK(std::fabs(-f.sim.state()[sim::PD] - 100.0) < 1.0);
    // altitude +10 m
    const double t0 = to_seconds(f.t);
    f.cmd.h_c = 110.0;
    testmodel::StepResponse rh{100.0, 110.0, 2.0};
    f.run(30.0, [&](double t, const msg::State& s) { rh.add(t - t0, s.altitude()); });
    // course +90 deg
    f.cmd.chi_c = 90 * kRadPerDeg;
    double chi_over = 0.0;
    f.run(40.0, [&](double, const msg::State& s) { chi_over = std::max(chi_over, wrap_pi(s.chi - 90 * kRadPerDeg) / kRadPerDeg); });
    const double chi_err = std::fabs(wrap_pi(truth(f.sim).chi - 90 * kRadPerDeg)) / kRadPerDeg;
    // airspeed +3 m/s
    const double t1 = to_seconds(f.t);
    f.cmd.Va_c = c.Va + 3.0;
    testmodel::StepResponse rv{c.Va, c.Va + 3.0, 0.3};
    f.run(30.0, [&](double t, const msg::State& s) { rv.add(t - t1, s.Va); });
    MESSAGE(std::string(c.name), ": altitude step overshoot ", rh.overshoot, " m, settles ", rh.settle_time, " s; course overshoot ",
            chi_over, " deg (final error ", chi_err, " deg); airspeed settles ", rv.settle_time, " s");
    CHECK(rh.overshoot < 3.0);
    CHECK(rh.settle_time < 15.0);
    CHECK(chi_over < 10.0);
    CHECK(chi_err < 2.0);
    CHECK(rv.settle_time < 10.0);
    CHECK_FALSE(f.sim.crashed());
  }
}

TEST_CASE("sim_aero: takeoff from rest, climb and cruise (ROSplane's phase thresholds)") {
  for (const auto& c : kCases) {
    CAPTURE(std::string(c.name));
    Flight f(c.aircraft, controller(c), c.gains);
    const auto& ac = f.sim.aircraft();
    f.sim.set_state(sim::make_state({0, 0, -sim::rest_height(ac)}, Eigen::Vector3d::Zero(), 0, 0, 0));
    f.cmd.Va_c = c.Va;
    f.cmd.h_c = 50.0;
    f.cmd.chi_c = 0.0;
    f.phase.phase = msg::Phase::takeoff;
    double t_climb = -1, t_cruise = -1;
    // the host's phase machine, as ROSplane: takeoff -> climb above alt_toz = 5 m,
    // climb -> cruise within alt_hz = 20 m of the commanded altitude
    f.run(90.0, [&](double t, const msg::State& s) {
      if (f.phase.phase == msg::Phase::takeoff && s.altitude() > 5.0) {
        f.phase.phase = msg::Phase::climb;
        t_climb = t;
      } else if (f.phase.phase == msg::Phase::climb && std::fabs(s.altitude() - 50.0) < 20.0) {
        f.phase.phase = msg::Phase::cruise;
        t_cruise = t;
      }
    });
    const msg::State s = truth(f.sim);
    MESSAGE(std::string(c.name), ": climb at ", t_climb, " s, cruise at ", t_cruise, " s; after 90 s h = ", s.altitude(), " m, Va = ", s.Va,
            " m/s, chi = ", s.chi / kRadPerDeg, " deg");
    CHECK(t_climb > 0);
    CHECK(t_cruise > t_climb);
    CHECK_FALSE(f.sim.crashed());
    CHECK(std::fabs(s.altitude() - 50.0) < 2.0);
    CHECK(std::fabs(s.Va - c.Va) < 1.0);
    CHECK(std::fabs(s.chi) < 3 * kRadPerDeg);
  }
}

TEST_CASE("sim_aero: cruise in 5 m/s wind from the south-east with light turbulence") {
  for (const auto& c : kCases) {
    CAPTURE(std::string(c.name));
    Flight f(c.aircraft, controller(c), c.gains);
    f.start_at_trim(c.Va, 100.0);
    // wind from the south-east blows towards the north-west
    f.sim.set_steady_wind(Eigen::Vector3d(5.0 / std::sqrt(2.0), -5.0 / std::sqrt(2.0), 0.0));
    f.sim.set_turbulence(sim::dryden_preset("light"));
    f.run(20.0);
    double se_h = 0, se_V = 0, se_chi = 0;
    int n = 0;
    for (double chi_c : {0.0, 90.0, 180.0, -90.0}) {
      f.cmd.chi_c = chi_c * kRadPerDeg;
      f.run(15.0);  // turn
      f.run(25.0, [&](double, const msg::State& s) {
        se_h += (s.altitude() - 100.0) * (s.altitude() - 100.0);
        se_V += (s.Va - c.Va) * (s.Va - c.Va);
        se_chi += wrap_pi(s.chi - chi_c * kRadPerDeg) * wrap_pi(s.chi - chi_c * kRadPerDeg);
        ++n;
      });
    }
    const double rms_h = std::sqrt(se_h / n), rms_V = std::sqrt(se_V / n), rms_chi = std::sqrt(se_chi / n) / kRadPerDeg;
    MESSAGE(std::string(c.name), ": RMS errors on straight legs: altitude ", rms_h, " m, airspeed ", rms_V, " m/s, course ", rms_chi,
            " deg");
    CHECK_FALSE(f.sim.crashed());
    CHECK(rms_h < 1.5);
    CHECK(rms_V < 1.0);
    CHECK(rms_chi < 3.0);
  }
}
