// sim_aero_feed.hpp: sensor messages from sim_aero's sensor models (tern::sim::Sensors, with its
// default figures: bias random walks, Gauss-Markov magnetometer and GNSS errors) applied to the
// kinematic truth of truth_sim.hpp. Only built when the sim_aero plugin is part of the build.
#pragma once

#include "tern_sim_aero/sensors.hpp"
#include "truth_sim.hpp"

namespace tern::ekf::test {

class SimAeroFeed {
 public:
  SimAeroFeed(TruthSim& sim, std::uint64_t seed, double rho, sim::SensorParams p = {}) : sim_(sim), sensors_(p, seed), rho_(rho) {}

  sim::Truth truth() const {
    const Truth& t = sim_.truth();
    sim::Truth s;
    s.x = sim::make_state(t.p, t.R.transpose() * t.v, t.phi, t.theta, t.psi, t.omega);
    s.mass = 1.0;
    s.fm.f_gravity = t.R.transpose() * Eigen::Vector3d(0, 0, sim_.options().g);
    s.fm.force = t.f + s.fm.f_gravity;
    s.fm.air.v_air = sim_.air_velocity_body();
    s.rho = rho_;
    return s;
  }
  msg::Imu imu() {
    const auto m = sensors_.imu(truth(), 0.0025);
    msg::Imu r;
    r.stamp = sim_.now();
    r.accel = m.accel;
    r.gyro = m.gyro;
    return r;
  }
  msg::Gnss gnss() {
    msg::Gnss r = sim::gnss_message(sensors_.gnss(truth(), 0.1), sim_.now());
    r.time_of_validity = 0;  // the stamp is the epoch
    return r;
  }
  msg::Baro baro() {
    msg::Baro r;
    r.stamp = sim_.now();
    r.pressure = sensors_.baro(truth(), 0.01).pressure;
    return r;
  }
  msg::DiffPressure pitot() {
    msg::DiffPressure r;
    r.stamp = sim_.now();
    r.pressure = sensors_.diff_pressure(truth(), 0.01).pressure;
    return r;
  }
  msg::Mag mag() {
    msg::Mag r;
    r.stamp = sim_.now();
    r.field = sensors_.mag(truth(), 0.02).field;
    return r;
  }
  const sim::Sensors& sensors() const { return sensors_; }

 private:
  TruthSim& sim_;
  sim::Sensors sensors_;
  double rho_;
};

/// fly() with sim_aero's sensors.
template <class OnStep>
void fly_sim_aero(TruthSim& sim, SimAeroFeed& feed, Estimator& est, double seconds, const Hooks& hooks, OnStep on_step) {
  const std::int64_t steps = std::llround(seconds / to_seconds(TruthSim::kImuPeriod));
  for (std::int64_t i = 0; i < steps; ++i) {
    sim.advance();
    msg::Imu imu = feed.imu();
    if (!hooks.imu || hooks.imu(imu)) est.add_imu(imu);
    if (sim.gnss_due()) {
      msg::Gnss g = feed.gnss();
      if (!hooks.gnss || hooks.gnss(g)) est.add_gnss(g);
    }
    if (sim.baro_due()) est.add_baro(feed.baro());
    if (sim.pitot_due()) est.add_diff_pressure(feed.pitot());
    if (sim.mag_due()) est.add_mag(feed.mag());
    est.check_timeouts(sim.now());
    on_step(sim.truth(), est);
  }
}

}  // namespace tern::ekf::test
