// The estimator fed by sim_aero's sensor models (bias random walks, Gauss-Markov magnetometer and
// GNSS errors, barometer bias up to 500 Pa) on the kinematic truth flight. Built only when the
// sim_aero plugin is part of the build (TERN_EKF_HAVE_SIM_AERO).
#include <doctest/doctest.h>

#ifdef TERN_EKF_HAVE_SIM_AERO

#include <cstdio>

#include "fly.hpp"
#include "sim_aero_feed.hpp"

using namespace tern;
using namespace tern::ekf;
using namespace tern::ekf::test;

TEST_CASE("with sim_aero's sensor models: loose accuracy bounds over 200 s, 3 seeds") {
  SimOptions o;
  o.psi0 = 0.7;
  o.phi_ramps = {{30.0, 2.0, 30.0 * kPi / 180},   {50.0, 2.0, -30.0 * kPi / 180},  {90.0, 3.0, 60.0 * kPi / 180},
                 {110.0, 3.0, -60.0 * kPi / 180}, {150.0, 3.0, -30.0 * kPi / 180}, {170.0, 3.0, 30.0 * kPi / 180}};
  o.gamma_ramps = {{60.0, 2.0, 0.1}, {75.0, 2.0, -0.1}};
  o.wind = Eigen::Vector2d(5.0, 0.0);
  for (std::uint64_t seed : {1u, 3u, 4u}) {
    TruthSim sim(o);
    SimAeroFeed feed(sim, seed, 1.2682);
    EstimatorConfig c;
    c.rho = 1.2682;  // the density sim_aero's pitot model uses (Anaconda and Aerosonde files)
    // sim_aero's default (rosflight) receiver: an error-free velocity, unlike a real
    // receiver's correlated errors the 0.3-m/s default is for; configured as a user would
    c.gnss_vel_sigma_h = c.gnss_vel_sigma_v = 0.01;
    c.accel_level_calibrated = false;  // sim_aero's default accelerometer: a raw offset, no level calibration
    Estimator est(settled_receiver(c));
    Rms roll, pitch, yaw, vel, alt, pos, wind, gnss_pos;
    int k = 0;
    fly_sim_aero(sim, feed, est, 200.0, {}, [&](const Truth& t, const Estimator& x) {
      if (++k < 400 * 20) return;  // 20 s of convergence
      const msg::State s = x.state();
      const Eigen::Vector3d p = truth_position(t, x, sim);
      roll.add(wrap_pi(s.phi - t.phi) * 180 / kPi);
      pitch.add((s.theta - t.theta) * 180 / kPi);
      yaw.add(wrap_pi(s.psi - t.psi) * 180 / kPi);
      vel.add((x.filter().x().v - t.v).norm());
      alt.add(s.p_d - p.z());
      pos.add((x.filter().x().p - p).head<2>().norm());
      wind.add((x.filter().x().wind - o.wind).norm());
    });
    std::printf(
        "sim_aero sensors, seed %d: roll %.3f pitch %.3f yaw %.3f deg, vel %.3f m/s, alt %.3f m, "
        "horizontal %.3f m, wind %.3f m/s (RMSE)\n",
        static_cast<int>(seed), roll.rms(), pitch.rms(), yaw.rms(), vel.rms(), alt.rms(), pos.rms(), wind.rms());
    INFO("seed " << seed);
    CHECK(roll.rms() < 0.6);
    CHECK(pitch.rms() < 0.6);
    CHECK(yaw.rms() < 2.5);
    CHECK(vel.rms() < 0.1);
    CHECK(alt.rms() < 0.5);
    CHECK(pos.rms() < 1.0);
    CHECK(wind.rms() < 0.8);
    CHECK(est.gnss_resets() == 0);
    CHECK(est.filter_resets() == 0);
  }
}

#endif
