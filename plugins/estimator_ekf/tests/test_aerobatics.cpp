// The estimator through aerobatics (issue 61): rolls, loops and an Immelmann read through sim_aero's
// `realistic` sensor models (aerobatic_sim.hpp). Built only when the sim_aero plugin is part of
// the build (TERN_EKF_HAVE_SIM_AERO). The 10-seed figure: bench_aerobatics.
#include <doctest/doctest.h>

#ifdef TERN_EKF_HAVE_SIM_AERO

#include <cstdio>

#include "aerobatic_sim.hpp"

using namespace tern;
using namespace tern::ekf;
using namespace tern::ekf::test;

TEST_CASE("aerobatics with realistic sensors: no yaw reset, yaw within 3 deg RMS, the magnetometer fused throughout") {
  for (std::uint64_t seed : {1u, 2u}) {
    const AerobaticResult r = fly_aerobatics(seed, aerobatic_config(), GnssEpoch::reported);
    std::printf("aerobatics, seed %d: yaw %.2f (max %.1f) tilt %.2f deg, vel %.2f m/s, yaw resets %d, gnss resets %d, mag fused %.1f %%\n",
                static_cast<int>(seed), r.yaw.rms() / kRadPerDeg, r.yaw.max / kRadPerDeg, r.tilt.rms() / kRadPerDeg, r.vel.rms(),
                static_cast<int>(r.gnss_yaw_resets), static_cast<int>(r.gnss_resets), 100.0 * r.mag_fused_fraction());
    INFO("seed " << seed);
    CHECK(r.gnss_yaw_resets == 0);
    CHECK(r.gnss_resets == 0);
    CHECK(r.mag_resets == 0);
    CHECK(r.yaw.rms() < 3.0 * kRadPerDeg);
    CHECK(r.mag_fused_fraction() == 1.0);
  }
}

#endif
