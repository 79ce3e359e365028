// fly.hpp: runs tern::ekf::Estimator against the truth generator, with hooks to corrupt or drop
// sensor messages, and measures errors.
#pragma once

#include <cmath>
#include <functional>

#include "tern/estimator_ekf/estimator.hpp"
#include "truth_sim.hpp"

namespace tern::ekf::test {

/// The estimator's configuration for TruthSim: its accelerometer has a raw offset (accel_bias),
/// not the board's tilt a level calibration stores (EstimatorConfig::accel_level_calibrated).
/// `c` with the origin on the first fix that passes the GNSS start-up checks, without their 10-s
/// hold: the truth simulation's receiver is settled from its first fix, and the tests of
/// everything else start there (test_gnss_checks.cpp tests the checks and the hold).
inline EstimatorConfig settled_receiver(EstimatorConfig c) {
  c.gnss_checks.hold_time = 0.0;
  return c;
}

inline EstimatorConfig truth_sim_config() {
  EstimatorConfig c;
  c.accel_level_calibrated = false;
  return settled_receiver(c);
}

/// Hooks: return false to drop the message; may modify it.
struct Hooks {
  std::function<bool(msg::Imu&)> imu;
  std::function<bool(msg::Gnss&)> gnss;
  std::function<bool(msg::Baro&)> baro;
  std::function<bool(msg::DiffPressure&)> pitot;
  std::function<bool(msg::Mag&)> mag;
};

/// Angle (rad) of the rotation between two attitudes.
inline double attitude_error(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::asin(std::min(1.0, d.vec().norm()));
}

/// Flies `seconds` of the truth, feeding est; after each IMU step calls on_step(truth, est).
template <class OnStep>
void fly(TruthSim& sim, Estimator& est, double seconds, const Hooks& hooks, OnStep on_step) {
  const std::int64_t steps = std::llround(seconds / to_seconds(TruthSim::kImuPeriod));
  for (std::int64_t i = 0; i < steps; ++i) {
    sim.advance();
    msg::Imu imu = sim.imu();
    if (!hooks.imu || hooks.imu(imu)) est.add_imu(imu);
    if (sim.gnss_due()) {
      msg::Gnss g = sim.gnss();
      if (!hooks.gnss || hooks.gnss(g)) est.add_gnss(g);
    }
    if (sim.baro_due()) {
      msg::Baro b = sim.baro();
      if (!hooks.baro || hooks.baro(b)) est.add_baro(b);
    }
    if (sim.pitot_due()) {
      msg::DiffPressure d = sim.pitot();
      if (!hooks.pitot || hooks.pitot(d)) est.add_diff_pressure(d);
    }
    if (sim.mag_due()) {
      msg::Mag m = sim.mag();
      if (!hooks.mag || hooks.mag(m)) est.add_mag(m);
    }
    est.check_timeouts(sim.now());
    on_step(sim.truth(), est);
  }
}

inline void fly(TruthSim& sim, Estimator& est, double seconds, const Hooks& hooks = {}) {
  fly(sim, est, seconds, hooks, [](const Truth&, const Estimator&) {});
}

/// Root-mean-square accumulator.
struct Rms {
  double sum = 0.0, max = 0.0;
  long n_ = 0;
  long n() const { return n_; }
  void add(double e) {
    sum += e * e;
    max = std::max(max, std::fabs(e));
    ++n_;
  }
  double rms() const { return n_ ? std::sqrt(sum / n_) : 0.0; }
};

/// True position in the estimator's NED frame (its origin is the first GNSS fix, not the sim's).
inline Eigen::Vector3d truth_position(const Truth& t, const Estimator& est, const TruthSim& sim) {
  const msg::State s = est.state();
  return t.p - sim.ned_of(s.origin_lat, s.origin_lon, s.origin_alt);
}

/// Error figures of a flight.
struct Errors {
  Rms pos_h, pos_v, vel, att, yaw, wind, gyro_bias, Va;
  void add(const Truth& t, const Estimator& est, const TruthSim& sim) {
    const NominalState& x = est.filter().x();
    const Eigen::Vector3d p_true = truth_position(t, est, sim);
    pos_h.add((x.p - p_true).head<2>().norm());
    pos_v.add(x.p.z() - p_true.z());
    vel.add((x.v - t.v).norm());
    att.add(attitude_error(x.q, t.q()));
    const msg::State s = est.state();
    yaw.add(wrap_pi(s.psi - t.psi));
    wind.add((x.wind - sim.options().wind).norm());
    gyro_bias.add((x.b_g - sim.options().gyro_bias).norm());
    Va.add(s.Va - sim.air_velocity_body().norm());
  }
};

}  // namespace tern::ekf::test
