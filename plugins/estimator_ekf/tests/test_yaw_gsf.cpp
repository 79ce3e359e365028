// The yaw from the IMU and GNSS velocity alone (yaw_gsf.hpp), on the kinematic truth flight.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>

#include "tern/estimator_ekf/yaw_gsf.hpp"
#include "truth_sim.hpp"

using namespace tern;
using namespace tern::ekf;
using namespace tern::ekf::test;

namespace {

double deg(double rad) { return rad * 180.0 / kPi; }

/// Flies `seconds` of `sim` through `gsf` (IMU at 400 Hz, GNSS velocity at 10 Hz, 0.3 m/s).
void fly_gsf(TruthSim& sim, YawGsf& gsf, double seconds) {
  const auto steps = std::llround(seconds / to_seconds(TruthSim::kImuPeriod));
  for (long long i = 0; i < steps; ++i) {
    sim.advance();
    const msg::Imu imu = sim.imu();
    // the gyro bias removed, as the estimator gives it (its own estimate)
    gsf.predict(imu.accel, imu.gyro - sim.options().gyro_bias, to_seconds(TruthSim::kImuPeriod), sim.options().Va);
    if (sim.gnss_due()) gsf.fuse_velocity(sim.gnss().vel.head<2>(), 0.3);
  }
}

}  // namespace

TEST_CASE("yaw GSF: converges to the true heading from any start once the aircraft turns") {
  for (const double psi0 : {0.7, -2.5, 3.0}) {
    SimOptions o = mixed_flight();
    o.psi0 = psi0;
    TruthSim sim(o);
    YawGsf gsf;
    fly_gsf(sim, gsf, 25.0);  // straight and level: the heading is not observable yet
    REQUIRE(gsf.active());
    const double straight_sigma = std::sqrt(gsf.yaw_variance());
    fly_gsf(sim, gsf, 35.0);  // the 30-deg-bank turns (30-50 s) and the climb
    const double err = std::remainder(gsf.yaw() - sim.truth().psi, 2 * kPi);
    std::printf("yaw GSF from psi0 %.1f: sigma %.1f deg straight, after the turns error %.2f deg, sigma %.2f deg\n", psi0,
                deg(straight_sigma), deg(err), deg(std::sqrt(gsf.yaw_variance())));
    CHECK(std::fabs(err) < 3.0 * kPi / 180);
    CHECK(std::sqrt(gsf.yaw_variance()) < 5.0 * kPi / 180);
    CHECK(std::sqrt(gsf.yaw_variance()) < straight_sigma);
  }
}

TEST_CASE("yaw GSF: stopped on the ground, restarts from the next velocity") {
  TruthSim sim(mixed_flight());
  YawGsf gsf;
  CHECK_FALSE(gsf.active());
  fly_gsf(sim, gsf, 1.0);
  CHECK(gsf.active());
  gsf.stop();
  CHECK_FALSE(gsf.active());
  gsf.fuse_velocity(Eigen::Vector2d(10.0, 0.0), 0.3);
  CHECK(gsf.active());
  CHECK(std::sqrt(gsf.yaw_variance()) > 1.0);                  // five headings: nothing known yet
  gsf.fuse_velocity(Eigen::Vector2d(std::nan(""), 0.0), 0.3);  // ignored
  CHECK(std::isfinite(gsf.yaw()));
}
