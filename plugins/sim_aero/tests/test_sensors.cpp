// Tests of the sensor error models and the named profiles: statistics (steady sigma and
// correlation time), installation geometry (lever arms, mounting rotation), per-seed errors
// (scale, cross-axis, hard/soft iron, pitot scale), determinism and the ideal profile.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "statistics.hpp"
#include "tern/math.hpp"
#include "tern/magnetic_model.hpp"
#include "tern_sim_aero/earth_field.hpp"
#include "tern/aero/model.hpp"
#include "tern_sim_aero/profiles.hpp"
#include "tern_sim_aero/rangefinder.hpp"
#include "tern_sim_aero/sensors.hpp"

using tern::kGravity;

using namespace tern::sim;
using tern::sim::test::mean;
using tern::sim::test::stddev;

namespace {

using Series = std::vector<std::vector<double>>;  // independent series of one zero-mean process

/// RMS about the known zero mean over all series.
double rms(const Series& ss) {
  double s = 0, n = 0;
  for (const auto& v : ss) {
    for (double x : v) s += x * x;
    n += static_cast<double>(v.size());
  }
  return std::sqrt(s / n);
}

/// Lag-k autocorrelation about the known zero mean, pooled over the series.
double autocorr(const Series& ss, std::size_t k) {
  double c = 0, v = 0;
  for (const auto& e : ss) {
    for (std::size_t i = 0; i + k < e.size(); ++i) {
      c += e[i] * e[i + k];
      v += 0.5 * (e[i] * e[i] + e[i + k] * e[i + k]);
    }
  }
  return c / v;
}

/// Correlation time of a first-order Gauss-Markov process from its lag autocorrelation.
double tau_from(const Series& ss, std::size_t k, double dt) { return -static_cast<double>(k) * dt / std::log(autocorr(ss, k)); }

/// Level flight at 17 m/s, 100 m up: the accelerometer sees -g on z.
Truth level_truth() {
  Truth t;
  t.x = make_state({0, 0, -100}, {17, 0, 0}, 0, 0, 0);
  t.mass = 4.5;
  t.fm.f_gravity = Eigen::Vector3d(0, 0, 4.5 * kGravity);
  t.fm.air.v_air = Eigen::Vector3d(17, 0, 0);
  t.fm.air.Va = 17.0;
  return t;
}

/// A truth whose specific force (body) and body rates are given.
Truth kinematic_truth(const Eigen::Vector3d& f, const Eigen::Vector3d& pqr) {
  Truth t;
  t.x = make_state({0, 0, -100}, {17, 0, 0}, 0, 0, 0, pqr);
  t.mass = 1.0;
  t.fm.force = f;  // gravity zero: specific force = force / 1 kg
  return t;
}

SensorParams ideal_with(void (*set)(SensorParams&)) {
  SensorParams p = sensor_profile("ideal");
  set(p);
  return p;
}

/// Columns: the accelerometer's reading of a unit specific force along each body axis.
Eigen::Matrix3d accel_matrix(Sensors& s) {
  Eigen::Matrix3d M;
  for (int j = 0; j < 3; ++j) {
    M.col(j) = s.imu(kinematic_truth(Eigen::Vector3d::Unit(j), Eigen::Vector3d::Zero()), 0.0025).accel;
  }
  return M;
}
/// Columns: the gyro's reading of a unit rate about each body axis.
Eigen::Matrix3d gyro_matrix(Sensors& s) {
  Eigen::Matrix3d M;
  for (int j = 0; j < 3; ++j) {
    M.col(j) = s.imu(kinematic_truth(Eigen::Vector3d::Zero(), Eigen::Vector3d::Unit(j)), 0.0025).gyro;
  }
  return M;
}

/// Earth's field in NED from the declination, inclination and intensity the world takes.
Eigen::Vector3d field_ned(const SensorParams& p) {
  const SensorParams q = with_earth_field(p);
  const double I = q.mag_inclination, D = q.mag_declination;
  return q.mag_intensity * Eigen::Vector3d(std::cos(I) * std::cos(D), std::cos(I) * std::sin(D), std::sin(I));
}

/// Every output of every sensor over n rounds, in one vector (for bit-for-bit comparisons).
std::vector<double> sample_all(Sensors& s, int n) {
  Truth t = level_truth();
  t.x.segment<3>(P) = Eigen::Vector3d(0.1, -0.2, 0.3);
  t.omega_dot = Eigen::Vector3d(0.5, 0.2, -0.1);
  t.throttle = 0.6;
  std::vector<double> out;
  for (int i = 0; i < n; ++i) {
    const ImuSample a = s.imu(t, 0.0025);
    const MagSample m = s.mag(t, 0.02);
    const GnssSample g = s.gnss(t, 0.1);
    out.insert(out.end(), {a.accel.x(), a.accel.y(), a.accel.z(), a.gyro.x(), a.gyro.y(), a.gyro.z(), m.field.x(), m.field.y(), m.field.z(),
                           s.baro(t, 0.01).pressure, s.diff_pressure(t, 0.01).pressure, g.lat, g.lon, g.alt, g.vel_ned.x(), g.vel_ned.y(),
                           g.vel_ned.z()});
  }
  return out;
}
}  // namespace

// ---------------------------------------------------------------- profiles -------------------

TEST_CASE("sensors: profiles are rosflight (default, first), realistic and ideal; others throw") {
  const auto& names = sensor_profile_names();
  REQUIRE(names.size() == 3);
  CHECK(names[0] == "rosflight");
  CHECK(std::find(names.begin(), names.end(), "realistic") != names.end());
  CHECK(std::find(names.begin(), names.end(), "ideal") != names.end());
  // rosflight is SensorParams{} with the FCU's accelerometer calibration at power-up: the same
  // outputs draw for draw (the calibration draws from a stream of its own)
  SensorParams raw;
  raw.accel_calibrated_level = raw.accel_calibrated_at_power_up = true;
  Sensors a(sensor_profile("rosflight"), 3), b(raw, 3);
  CHECK(sample_all(a, 50) == sample_all(b, 50));
  CHECK(a.accel_calibration().norm() > 0.0);
  CHECK_THROWS_AS(sensor_profile("nope"), std::invalid_argument);
  std::string msg;
  try {
    sensor_profile("nope");
  } catch (const std::invalid_argument& e) {
    msg = e.what();
  }
  CHECK(msg.find("nope") != std::string::npos);
  for (const std::string& n : names) CHECK(msg.find(n) != std::string::npos);
  // realistic: the per-sample IMU noise is density * sqrt(157 Hz)
  const SensorParams r = sensor_profile("realistic");
  CHECK(r.gyro_noise == doctest::Approx(0.004 * tern::kRadPerDeg * 12.53).epsilon(0.001));
  CHECK(r.accel_noise == doctest::Approx(100e-6 * tern::kStandardGravity * 12.53).epsilon(0.001));
  CHECK(r.gnss_latency == 0.12);
}

TEST_CASE("sensors: the ideal profile gives exactly the true values") {
  const SensorParams p = sensor_profile("ideal");
  Sensors s(p, 21);
  Truth t;
  t.x = make_state({120, -40, -75}, {18, 1, -0.5}, 0.2, 0.1, 2.0, {0.3, -0.2, 0.4});
  t.mass = 4.5;
  t.fm.force = Eigen::Vector3d(2, -1, -40);
  t.fm.f_gravity = Eigen::Vector3d(1, 3, 42);
  t.fm.air.v_air = Eigen::Vector3d(17, 0.5, 1);
  t.fm.air.Va = t.fm.air.v_air.norm();
  t.omega_dot = Eigen::Vector3d(1, -2, 0.5);
  t.throttle = 0.8;
  for (int i = 0; i < 3; ++i) {
    const ImuSample a = s.imu(t, 0.0025);
    CHECK(a.accel == t.fm.specific_force(t.mass));
    CHECK(a.gyro == Eigen::Vector3d(t.x.segment<3>(P)));
    CHECK(s.mag(t, 0.02).field == attitude(t.x).conjugate() * field_ned(p));
    CHECK(s.baro(t, 0.01).pressure == standard_pressure(p.origin_alt + 75));
    CHECK(s.diff_pressure(t, 0.01).pressure == 0.5 * t.rho * 17 * 17);
    const GnssSample g = s.gnss(t, 0.1);
    const tern::GeoPoint fix = s.origin().to_geodetic(t.x.segment<3>(PN));
    CHECK(g.lat == fix.lat);
    CHECK(g.lon == fix.lon);
    CHECK(g.alt == fix.alt);
    CHECK(g.vel_ned == attitude(t.x).toRotationMatrix() * Eigen::Vector3d(t.x.segment<3>(U)));
    CHECK(g.h_acc > 0);
    CHECK(g.h_acc < 0.1);
  }
}

// ---------------------------------------------------------------- GNSS -----------------------

TEST_CASE("sensors: realistic GNSS position error has its steady sigma and correlation time") {
  const SensorParams p = sensor_profile("realistic");
  const double dt = 1.0;  // the discretisation is exact: any fix interval gives the same process
  const int n = 3600, seeds = 60;
  Series h, v;
  const Truth t = level_truth();
  for (int k = 0; k < seeds; ++k) {
    Sensors s(p, 1000 + static_cast<std::uint64_t>(k));
    std::vector<double> n_, e_, d_;
    for (int i = 0; i < n; ++i) {
      s.gnss(t, dt);
      n_.push_back(s.gnss_error().x());
      e_.push_back(s.gnss_error().y());
      d_.push_back(s.gnss_error().z());
    }
    h.push_back(n_);
    h.push_back(e_);
    v.push_back(d_);
  }
  CHECK(rms(h) == doctest::Approx(p.gnss_h_sigma).epsilon(0.1));
  CHECK(rms(v) == doctest::Approx(p.gnss_v_sigma).epsilon(0.1));
  Series all = h;
  all.insert(all.end(), v.begin(), v.end());
  const std::size_t lag = 90;  // tau / 2
  CHECK(tau_from(all, lag, dt) == doctest::Approx(p.gnss_tau).epsilon(0.1));
  CHECK(tau_from(v, lag, dt) == doctest::Approx(p.gnss_tau).epsilon(0.15));
}

TEST_CASE("sensors: gnss_start_steady gives the first fix the steady error; rosflight starts at zero") {
  const SensorParams p = sensor_profile("realistic");
  const Truth t = level_truth();
  Series h0(1), v0(1), vel0(1), h50(1);
  for (std::uint64_t k = 0; k < 2000; ++k) {
    Sensors s(p, 5000 + k);
    const GnssSample g = s.gnss(t, 0.1);
    h0[0].push_back(s.gnss_error().x());
    h0[0].push_back(s.gnss_error().y());
    v0[0].push_back(s.gnss_error().z());
    for (int i = 0; i < 3; ++i) vel0[0].push_back(g.vel_ned[i] - (i == 0 ? 17.0 : 0.0));
    for (int i = 0; i < 49; ++i) s.gnss(t, 0.1);
    h50[0].push_back(s.gnss_error().x());
  }
  CHECK(rms(h0) == doctest::Approx(p.gnss_h_sigma).epsilon(0.1));
  CHECK(rms(v0) == doctest::Approx(p.gnss_v_sigma).epsilon(0.1));
  CHECK(rms(vel0) == doctest::Approx(p.gnss_vel_noise).epsilon(0.1));
  CHECK(rms(h50) == doctest::Approx(p.gnss_h_sigma).epsilon(0.1));  // stays steady at 10 Hz
  // rosflight: zero error at reset, then it grows from zero (first fix: sigma sqrt(1 - exp(-2 T_s / tau)),
  // 2 cm horizontal and 4 cm vertical)
  const SensorParams r;
  double worst = 0;
  for (std::uint64_t k = 0; k < 200; ++k) {
    Sensors s(r, 5000 + k);
    CHECK(s.gnss_error() == Eigen::Vector3d::Zero());
    s.gnss(t, 0.1);
    worst = std::max(worst, s.gnss_error().cwiseAbs().maxCoeff());
  }
  CHECK(worst > 0.0);
  CHECK(worst < 0.2);
}

TEST_CASE("sensors: realistic GNSS velocity error has its sigma and correlation time") {
  const SensorParams p = sensor_profile("realistic");
  const Truth t = level_truth();
  const double dt = 0.1;  // 10 Hz
  Series e;
  for (std::uint64_t k = 0; k < 4; ++k) {
    Sensors s(p, 77 + k);
    std::vector<double> x, y, z;
    for (int i = 0; i < 10000; ++i) {
      const Eigen::Vector3d v = s.gnss(t, dt).vel_ned;
      x.push_back(v.x() - 17.0);
      y.push_back(v.y());
      z.push_back(v.z());
    }
    e.push_back(x);
    e.push_back(y);
    e.push_back(z);
  }
  CHECK(rms(e) == doctest::Approx(p.gnss_vel_noise).epsilon(0.1));
  CHECK(tau_from(e, 10, dt) == doctest::Approx(p.gnss_vel_tau).epsilon(0.1));
  // tau <= 0: white (no correlation from fix to fix)
  SensorParams w = p;
  w.gnss_vel_tau = 0.0;
  Sensors s(w, 3);
  Series ew(1);
  for (int i = 0; i < 20000; ++i) ew[0].push_back(s.gnss(t, dt).vel_ned.y());
  CHECK(rms(ew) == doctest::Approx(p.gnss_vel_noise).epsilon(0.05));
  CHECK(std::fabs(autocorr(ew, 1)) < 0.03);
}

TEST_CASE("sensors: the GNSS fix is the antenna's position and velocity") {
  SensorParams p = sensor_profile("ideal");
  p.gnss_antenna_position = Eigen::Vector3d(1.0, 0.0, -0.5);  // 1 m ahead, 0.5 m above the CG
  Sensors s(p, 1);
  Truth t;
  // heading east (yaw 90 deg), 20 m/s forward, yaw rate 0.5 rad/s
  t.x = make_state({100, 50, -80}, {20, 0, 0}, 0, 0, 90 * tern::kRadPerDeg, {0, 0, 0.5});
  const GnssSample g = s.gnss(t, 0.1);
  // body x points east: the antenna is 1 m east of the CG and 0.5 m above it
  const Eigen::Vector3d pos = s.origin().to_ned(g.lat, g.lon, g.alt);
  CHECK((pos - Eigen::Vector3d(100, 51, -80.5)).norm() < 1e-6);
  // omega x r = (0, 0.5, 0) body (to the right = south): v_ned = (-0.5, 20, 0)
  CHECK((g.vel_ned - Eigen::Vector3d(-0.5, 20, 0)).norm() < 1e-12);
  // realistic: the reported position is CG + antenna + gnss_error()
  const SensorParams r = sensor_profile("realistic");
  Sensors sr(r, 2);
  const GnssSample gr = sr.gnss(t, 0.1);
  const Eigen::Vector3d expected = t.x.segment<3>(PN) + attitude(t.x) * r.gnss_antenna_position + sr.gnss_error();
  CHECK((sr.origin().to_ned(gr.lat, gr.lon, gr.alt) - expected).norm() < 1e-6);
  CHECK(sr.gnss_error().norm() > 0.01);
  CHECK(gr.h_acc == 1.2);
  CHECK(gr.v_acc == 2.5);
  CHECK(gr.s_acc == 0.05);
}

// ---------------------------------------------------------------- IMU ------------------------

TEST_CASE("sensors: IMU white noise plus vibration scaled by the throttle") {
  SensorParams p = sensor_profile("realistic");
  p.accel_bias_walk = p.gyro_bias_walk = 0.0;  // the noise alone
  auto sigmas = [&](double throttle) {
    Sensors s(p, 31);
    Truth t = level_truth();
    t.throttle = throttle;
    std::vector<double> ax, ay, gz, gx;
    for (int i = 0; i < 20000; ++i) {
      const ImuSample m = s.imu(t, 0.0025);
      ax.push_back(m.accel.x());
      ay.push_back(m.accel.y());
      gx.push_back(m.gyro.x());
      gz.push_back(m.gyro.z());
    }
    return std::vector<double>{stddev(ax), stddev(ay), stddev(gx), stddev(gz)};
  };
  const std::vector<double> half = sigmas(0.5), idle = sigmas(0.0);
  // whole counts add the quantisation noise lsb^2 / 12 (Widrow: the noise spans several counts)
  auto counted = [](double sigma, double lsb) { return std::sqrt(sigma * sigma + lsb * lsb / 12.0); };
  const double sa = counted(std::hypot(p.accel_noise, 0.5 * p.accel_vibration), p.accel_resolution);  // 0.750 m/s^2
  const double sg = counted(std::hypot(p.gyro_noise, 0.5 * p.gyro_vibration), p.gyro_resolution);     // 0.00508 rad/s
  CHECK(half[0] == doctest::Approx(sa).epsilon(0.03));
  CHECK(half[1] == doctest::Approx(sa).epsilon(0.03));
  CHECK(half[2] == doctest::Approx(sg).epsilon(0.03));
  CHECK(half[3] == doctest::Approx(sg).epsilon(0.03));
  CHECK(idle[0] == doctest::Approx(counted(p.accel_noise, p.accel_resolution)).epsilon(0.03));
  CHECK(idle[3] == doctest::Approx(counted(p.gyro_noise, p.gyro_resolution)).epsilon(0.03));
}

TEST_CASE("sensors: realistic readings are whole counts of the datasheets' resolutions; rosflight's are continuous") {
  SensorParams p = sensor_profile("realistic");
  p.calibrate_at_boot = false;  // the raw counts (the FCU's boot calibration subtracts a mean)
  p.accel_calibrated_level = false;
  CHECK(p.accel_resolution == doctest::Approx(tern::kStandardGravity / 2048.0));
  CHECK(p.gyro_resolution == doctest::Approx(tern::kRadPerDeg / 16.4));
  CHECK(p.baro_resolution == 1.0);
  auto whole = [](double x, double lsb) { return std::abs(x / lsb - std::round(x / lsb)) < 1e-6; };
  Sensors s(p, 5);
  Truth t = level_truth();
  t.throttle = 0.6;
  for (int i = 0; i < 200; ++i) {
    const ImuSample imu = s.imu(t, 0.0025);
    for (int k = 0; k < 3; ++k) {
      REQUIRE(whole(imu.accel[k], p.accel_resolution));
      REQUIRE(whole(imu.gyro[k], p.gyro_resolution));
      REQUIRE(whole(s.mag(t, 0.0025).field[k], p.mag_resolution));
    }
    REQUIRE(whole(imu.temperature, p.imu_temperature_resolution));
    REQUIRE(whole(s.baro(t, 0.0025).pressure, p.baro_resolution));
    REQUIRE(whole(s.diff_pressure(t, 0.0025).pressure, p.diff_resolution));
  }
  Sensors r(sensor_profile("rosflight"), 5);
  int off_grid = 0;
  for (int i = 0; i < 200; ++i) off_grid += !whole(r.imu(t, 0.0025).gyro.x(), tern::kRadPerDeg / 16.4);
  CHECK(off_grid > 190);
}

TEST_CASE("sensors: the accelerometer off the CG sees centripetal and tangential accelerations") {
  SensorParams p = sensor_profile("ideal");
  p.imu_position = Eigen::Vector3d(0.3, 0, 0);  // 30 cm ahead of the CG
  Sensors s(p, 1);
  // pure yaw rate r = 2 rad/s: centripetal -r^2 x = -1.2 m/s^2 along x
  Truth t = kinematic_truth(Eigen::Vector3d::Zero(), {0, 0, 2.0});
  CHECK((s.imu(t, 0.0025).accel - Eigen::Vector3d(-1.2, 0, 0)).norm() < 1e-12);
  // pitch acceleration q_dot = 3 rad/s^2 (nose up): the point ahead accelerates up, -0.9 on z
  t = kinematic_truth(Eigen::Vector3d(0, 0, -kGravity), Eigen::Vector3d::Zero());
  t.omega_dot = Eigen::Vector3d(0, 3.0, 0);
  CHECK((s.imu(t, 0.0025).accel - Eigen::Vector3d(0, 0, -kGravity - 0.9)).norm() < 1e-12);
  // and the gyro is unaffected by the lever arm
  t = kinematic_truth(Eigen::Vector3d::Zero(), {0.1, 0.2, 0.3});
  CHECK((s.imu(t, 0.0025).gyro - Eigen::Vector3d(0.1, 0.2, 0.3)).norm() < 1e-15);
}

TEST_CASE("sensors: IMU mounting rotation (3-2-1, body v reads R_mount^T v)") {
  SensorParams p = sensor_profile("ideal");
  p.imu_misalignment = Eigen::Vector3d(0, 0, 90 * tern::kRadPerDeg);  // IMU yawed 90 deg
  Sensors s(p, 1);
  const ImuSample m = s.imu(kinematic_truth({1, 0, 0}, {0.1, 0, 0}), 0.0025);
  CHECK((m.accel - Eigen::Vector3d(0, -1, 0)).norm() < 1e-15);  // body x reads -y
  CHECK((m.gyro - Eigen::Vector3d(0, -0.1, 0)).norm() < 1e-15);
  // a general mount against the Euler rotation of tern/math.hpp
  const Eigen::Vector3d rpy(0.5 * tern::kRadPerDeg, -0.5 * tern::kRadPerDeg, 1.0 * tern::kRadPerDeg);
  p.imu_misalignment = rpy;
  Sensors s2(p, 1);
  const Eigen::Vector3d f(1, 2, -9), w(0.3, -0.1, 0.2);
  const Eigen::Matrix3d Rt = tern::rotation_from_euler(rpy.x(), rpy.y(), rpy.z()).transpose();
  const ImuSample m2 = s2.imu(kinematic_truth(f, w), 0.0025);
  CHECK((m2.accel - Rt * f).norm() < 1e-12);
  CHECK((m2.gyro - Rt * w).norm() < 1e-12);
  CHECK((m2.accel - f).norm() > 0.1);  // the mount does change the reading
}

TEST_CASE("sensors: the stored accelerometer calibration (ROSflight calibrate_accel) makes level read -g0 z") {
  // A misaligned, cross-coupled, scaled IMU calibrated on a level floor: at rest level it reads
  // the firmware's (0, 0, -kStandardGravity) exactly; in a 2-g pull-up the errors of the second g remain.
  SensorParams p = ideal_with([](SensorParams& q) {
    q.accel_scale_range = 0.01;
    q.imu_cross_axis_range = 0.02;
    q.accel_calibrated_level = true;
  });
  p.imu_misalignment = Eigen::Vector3d(0.5, -0.5, 1.0) * tern::kRadPerDeg;
  Sensors s(p, 3);
  const Eigen::Vector3d level(0, 0, -kGravity), pull_up(0, 0, -2 * kGravity);
  const Eigen::Vector3d g0(0, 0, -tern::kStandardGravity);
  CHECK((s.imu(kinematic_truth(level, Eigen::Vector3d::Zero()), 0.0025).accel - g0).norm() < 1e-12);
  // The offset is a constant: at 2 g the reading is the uncalibrated one (same seed, same draws)
  // minus it, and the errors of the second g are left.
  SensorParams uncalibrated = p;
  uncalibrated.accel_calibrated_level = false;
  Sensors raw(uncalibrated, 3);
  const Eigen::Vector3d cal = s.accel_calibration();
  CHECK(cal.norm() > 0.05);  // mount and cross-axis terms seen at 1 g
  const Eigen::Vector3d f2 = s.imu(kinematic_truth(pull_up, Eigen::Vector3d::Zero()), 0.0025).accel;
  CHECK((f2 - (raw.imu(kinematic_truth(pull_up, Eigen::Vector3d::Zero()), 0.0025).accel - cal)).norm() < 1e-12);
  CHECK((f2 - (g0 + (pull_up - level))).norm() > 0.05);
  // A tilted floor is taken as level: the tilt goes into the offset (about g sin(tilt) on x/y).
  p.accel_calibration_tilt_range = 0.3 * tern::kRadPerDeg;
  Sensors tilted(p, 3);
  const double tilt_err = (tilted.accel_calibration() - cal).head<2>().norm();
  CHECK(tilt_err > 0.0);
  CHECK(tilt_err < kGravity * std::sin(0.3 * tern::kRadPerDeg) * std::sqrt(2.0) * 1.05);
  // The firmware refuses an offset of 3 m/s^2 or more ("large accel bias"): nothing is stored.
  p.imu_misalignment = Eigen::Vector3d(0, 30 * tern::kRadPerDeg, 0);
  Sensors refused(p, 3);
  CHECK(refused.accel_calibration().norm() == 0.0);
  // Without the calibration nothing is subtracted.
  p.accel_calibrated_level = false;
  CHECK(Sensors(p, 3).accel_calibration().norm() == 0.0);
}

TEST_CASE("sensors: a calibration taken at this power-up holds the turn-on bias; the rosflight profile's FCU has one") {
  // ROSflight refuses to arm until calibrate_imu has run, so its aircraft flies with this
  // power-up's accelerometer offset stored: what is left at rest level is the mean's noise
  // (sigma / sqrt(1000)), not the +-accel_bias_range turn-on bias.
  SensorParams p = sensor_profile("rosflight");
  REQUIRE(p.accel_calibrated_level);
  REQUIRE(p.accel_calibrated_at_power_up);
  p.accel_bias_walk = 0.0;
  const Eigen::Vector3d g0(0, 0, -tern::kStandardGravity);
  const double mean_sigma = p.accel_noise / std::sqrt(1000.0);
  double worst_calibrated = 0.0, worst_earlier = 0.0;
  for (std::uint64_t seed = 1; seed <= 50; ++seed) {
    Sensors s(p, seed);
    // at rest level the residual offset is the calibration mean's noise ...
    worst_calibrated = std::max(
        worst_calibrated,
        (s.accel_bias() - (s.accel_calibration() - Eigen::Vector3d(0, 0, tern::kStandardGravity - kGravity))).cwiseAbs().maxCoeff());
    // ... where a calibration from an earlier session leaves the whole turn-on bias
    SensorParams q = p;
    q.accel_calibrated_at_power_up = false;
    Sensors e(q, seed);
    worst_earlier = std::max(
        worst_earlier,
        (e.accel_bias() - (e.accel_calibration() - Eigen::Vector3d(0, 0, tern::kStandardGravity - kGravity))).cwiseAbs().maxCoeff());
    CHECK(e.accel_bias() == s.accel_bias());  // same draws either way
  }
  CHECK(worst_calibrated < 4.5 * mean_sigma);
  CHECK(worst_earlier > 0.8 * p.accel_bias_range);
  // The reading at rest level: the firmware's (0, 0, -kStandardGravity) plus that residual.
  p.accel_noise = 0.0;
  Sensors quiet(p, 7);
  CHECK((quiet.imu(kinematic_truth(Eigen::Vector3d(0, 0, -kGravity), Eigen::Vector3d::Zero()), 0.0025).accel - g0).norm() < 1e-12);
}

TEST_CASE("sensors: IMU scale factors and cross-axis terms are per-seed, within their ranges") {
  // only the scale factors
  const SensorParams ps = ideal_with([](SensorParams& p) { p.accel_scale_range = p.gyro_scale_range = 0.01; });
  double lo = 1, hi = -1;
  for (std::uint64_t k = 0; k < 200; ++k) {
    Sensors s(ps, k);
    const Eigen::Matrix3d A = accel_matrix(s), G = gyro_matrix(s);
    for (const Eigen::Matrix3d& M : {A, G}) {
      const Eigen::Vector3d d = M.diagonal() - Eigen::Vector3d::Ones();
      CHECK(d.cwiseAbs().maxCoeff() <= 0.01);
      CHECK(d.cwiseAbs().minCoeff() > 0.0);
      CHECK((M - Eigen::Matrix3d(M.diagonal().asDiagonal())).norm() == 0.0);  // no cross terms
      lo = std::min(lo, d.minCoeff());
      hi = std::max(hi, d.maxCoeff());
    }
  }
  CHECK(lo < -0.009);  // the draws span the range
  CHECK(hi > 0.009);
  Sensors a(ps, 1), b(ps, 2);
  CHECK((accel_matrix(a) - accel_matrix(b)).norm() > 1e-4);
  // only the cross-axis terms
  const SensorParams pc = ideal_with([](SensorParams& p) { p.imu_cross_axis_range = 0.02; });
  double worst = 0;
  for (std::uint64_t k = 0; k < 200; ++k) {
    Sensors s(pc, k);
    const Eigen::Matrix3d A = accel_matrix(s);
    CHECK(A.diagonal() == Eigen::Vector3d::Ones());
    const Eigen::Matrix3d off = A - Eigen::Matrix3d::Identity();
    CHECK(off.cwiseAbs().maxCoeff() <= 0.02);
    CHECK(off.cwiseAbs().maxCoeff() > 0.0);
    worst = std::max(worst, off.cwiseAbs().maxCoeff());
  }
  CHECK(worst > 0.019);
}

// ---------------------------------------------------------------- magnetometer ---------------

TEST_CASE("sensors: magnetometer hard iron, soft iron and motor field") {
  const Truth level = level_truth();
  // hard iron: a constant per-seed offset within the range
  const SensorParams ph = ideal_with([](SensorParams& p) { p.mag_hard_iron_range = 1e-6; });
  Sensors h1(ph, 1), h2(ph, 2);
  const Eigen::Vector3d b0 = field_ned(ph);
  const Eigen::Vector3d o1 = h1.mag(level, 0.02).field - b0, o2 = h2.mag(level, 0.02).field - b0;
  CHECK(o1.cwiseAbs().maxCoeff() <= 1e-6 + 1e-18);
  CHECK(o1.cwiseAbs().minCoeff() > 0.0);
  CHECK((o1 - o2).norm() > 1e-8);
  CHECK((h1.mag(level, 0.02).field - b0 - o1).norm() < 1e-20);  // constant in time
  // soft iron: S recovered from three attitudes, each element of S - I within +-2 %
  const SensorParams ps = ideal_with([](SensorParams& p) { p.mag_soft_iron_range = 0.02; });
  const StateVector xs[3] = {make_state({0, 0, -100}, {17, 0, 0}, 0, 0, 0),
                             make_state({0, 0, -100}, {17, 0, 0}, 0, 0, 90 * tern::kRadPerDeg),
                             make_state({0, 0, -100}, {17, 0, 0}, 90 * tern::kRadPerDeg, 0, 0)};
  double worst = 0;
  for (std::uint64_t k = 0; k < 100; ++k) {
    Sensors s(ps, k);
    Eigen::Matrix3d B, F;
    for (int j = 0; j < 3; ++j) {
      Truth t = level;
      t.x = xs[j];
      B.col(j) = attitude(t.x).conjugate() * field_ned(ps);
      F.col(j) = s.mag(t, 0.02).field;
    }
    const Eigen::Matrix3d E = F * B.inverse() - Eigen::Matrix3d::Identity();
    CHECK(E.cwiseAbs().maxCoeff() <= 0.02 + 1e-9);
    worst = std::max(worst, E.cwiseAbs().maxCoeff());
  }
  CHECK(worst > 0.018);
  // motor field: proportional to the throttle
  const SensorParams pm = ideal_with([](SensorParams& p) { p.mag_motor_field = Eigen::Vector3d(0, 0.5e-6, 1.5e-6); });
  Sensors m(pm, 1);
  Truth t = level;
  CHECK(m.mag(t, 0.02).field == b0);
  t.throttle = 0.6;
  CHECK((m.mag(t, 0.02).field - b0 - Eigen::Vector3d(0, 0.3e-6, 0.9e-6)).norm() < 1e-18);
}

// ---------------------------------------------------------------- air data -------------------

TEST_CASE("sensors: barometer static-port error and pitot installation scale") {
  const SensorParams pb = ideal_with([](SensorParams& p) {
    p.baro_static_error = 0.05;
    p.baro_static_error_yp = -0.3;
    p.baro_static_error_yn = 0.2;
    p.baro_static_error_z = -0.1;
  });
  Sensors b(pb, 1);
  Truth t = level_truth();
  t.rho = 1.2;
  t.fm.air.v_air = Eigen::Vector3d(20.0, 0.0, 0.0);
  const double p_static = standard_pressure(pb.origin_alt + 100);
  CHECK(b.baro(t, 0.01).pressure - p_static == doctest::Approx(0.05 * 0.5 * 1.2 * 400).epsilon(1e-6));
  // each body component of the relative wind with its own coefficient; y by its sign
  t.fm.air.v_air = Eigen::Vector3d(20.0, 5.0, 4.0);
  CHECK(b.baro(t, 0.01).pressure - p_static == doctest::Approx(0.6 * (0.05 * 400 - 0.3 * 25 - 0.1 * 16)).epsilon(1e-6));
  t.fm.air.v_air = Eigen::Vector3d(20.0, -5.0, -4.0);
  CHECK(b.baro(t, 0.01).pressure - p_static == doctest::Approx(0.6 * (0.05 * 400 + 0.2 * 25 - 0.1 * 16)).epsilon(1e-6));
  CHECK(b.effects().baro_static_error_max == doctest::Approx(0.6 * (0.05 * 400 + 0.2 * 25 - 0.1 * 16)).epsilon(1e-9));
  t.fm.air.v_air.setZero();
  CHECK(b.baro(t, 0.01).pressure == p_static);
  const SensorParams pd = ideal_with([](SensorParams& p) { p.diff_scale_range = 0.05; });
  t.fm.air.v_air = Eigen::Vector3d(20, 0, 0);
  double lo = 2, hi = 0;
  for (std::uint64_t k = 0; k < 200; ++k) {
    Sensors s(pd, k);
    const double ratio = s.diff_pressure(t, 0.01).pressure / (0.5 * 1.2 * 400);
    CHECK(std::fabs(ratio - 1.0) <= 0.05 + 1e-12);
    CHECK(s.diff_pressure(t, 0.01).pressure / (0.5 * 1.2 * 400) == ratio);  // per seed, constant
    lo = std::min(lo, ratio);
    hi = std::max(hi, ratio);
  }
  CHECK(lo < 0.955);
  CHECK(hi > 1.045);
}

// ---------------------------------------------------------------- determinism ----------------

TEST_CASE("sensors: same seed, same samples bit for bit; reset() restarts the sequence") {
  const SensorParams p = sensor_profile("realistic");
  Sensors a(p, 42), b(p, 42), c(p, 43);
  const std::vector<double> sa = sample_all(a, 200);
  CHECK(sa == sample_all(b, 200));
  CHECK(sa != sample_all(c, 200));
  a.reset();
  CHECK(sample_all(a, 200) == sa);
  const std::vector<double> again = sample_all(a, 200);  // no reset: the sequence goes on
  CHECK(again != sa);
}

// ---------------------------------------------------------------- boot calibration ------------

namespace {
/// On the ground, at rest, with `wind` m/s blowing into the pitot (motor off).
Truth at_rest(double wind) {
  Truth t;
  t.x = make_state({0, 0, 0}, {0, 0, 0}, 0, 0, 0);
  t.mass = 4.5;
  t.fm.f_gravity = Eigen::Vector3d(0, 0, 4.5 * kGravity);
  t.fm.force = -t.fm.f_gravity;  // the ground carries the weight
  t.fm.air.v_air = Eigen::Vector3d(wind, 0, 0);
  t.fm.air.Va = wind;
  return t;
}
}  // namespace

TEST_CASE("sensors: boot calibration (ROSflight sensors.cpp): raw gyro until 1001 samples, then their mean removed") {
  SensorParams p = sensor_profile("realistic");
  REQUIRE(p.calibrate_at_boot);
  Sensors s(p, 11);
  const BootCalibration* cal = s.boot_calibration();
  REQUIRE(cal != nullptr);
  const Truth t = at_rest(0.0);
  const Eigen::Vector3d turn_on = s.gyro_bias();
  CHECK(turn_on.cwiseAbs().maxCoeff() > 0.002);  // a real turn-on bias, uniform in +-1 dps
  Eigen::Vector3d before = Eigen::Vector3d::Zero();
  for (int i = 0; i < 1000; ++i) before += s.imu(t, 0.0025).gyro / 1000.0;
  CHECK_FALSE(cal->gyro_done());
  const double sigma_mean = p.gyro_noise / std::sqrt(1000.0);
  CHECK((before - turn_on).cwiseAbs().maxCoeff() < 5.0 * sigma_mean);  // raw: the bias is there
  s.imu(t, 0.0025);
  REQUIRE(cal->gyro_done());
  CHECK((cal->gyro_bias() - turn_on).cwiseAbs().maxCoeff() < 5.0 * sigma_mean);
  Eigen::Vector3d after = Eigen::Vector3d::Zero();
  for (int i = 0; i < 4000; ++i) after += s.imu(t, 0.0025).gyro / 4000.0;
  CHECK(after.cwiseAbs().maxCoeff() < 5.0 * sigma_mean + 5.0 * p.gyro_bias_walk * std::sqrt(12.5));
  CHECK_FALSE(cal->done());  // the pressure calibrations take longer
}

TEST_CASE("sensors: boot calibration: a moving aircraft restarts the gyro window") {
  Sensors s(sensor_profile("realistic"), 3);
  const Truth spinning = kinematic_truth(Eigen::Vector3d(0, 0, -kGravity), Eigen::Vector3d(0, 0, 1.2));
  for (int i = 0; i < 2002; ++i) s.imu(spinning, 0.0025);
  CHECK_FALSE(s.boot_calibration()->gyro_done());
  CHECK(s.boot_calibration()->gyro_restarts() == 2);
}

TEST_CASE("sensors: boot calibration: pitot zeroed after 128 + 127 cycles of > 20 ms, wind and all; baro unchanged") {
  SensorParams p = sensor_profile("realistic");
  Sensors s(p, 5);
  const Truth t = at_rest(3.0);  // 3 m/s of wind into the pitot while it calibrates
  const double q_wind = 0.5 * t.rho * 9.0;
  const BootCalibration& cal = *s.boot_calibration();
  double time = 0.0;
  int n = 0;
  while (!cal.diff().done && n < 2000) {
    s.diff_pressure(t, 0.01);
    time = 0.01 * n++;
  }
  // At 100 Hz a cycle every 30 ms (the first at 30 ms): 128 + 127 + 1 cycles end at 7.68 s.
  CHECK(time == doctest::Approx(7.68).epsilon(1e-9));
  CHECK(cal.diff().restarts == 0);
  const double noise_mean = p.diff_noise / std::sqrt(127.0);
  // the zero holds the wind's dynamic pressure (times the installation scale) and the offset
  CHECK(cal.diff().offset == doctest::Approx(q_wind).epsilon(0.07 + (p.diff_bias_range + 5 * noise_mean) / q_wind));
  double mean_after = 0;
  for (int i = 0; i < 1000; ++i) mean_after += s.diff_pressure(t, 0.01).pressure / 1000.0;
  CHECK(std::fabs(mean_after) < 5.0 * noise_mean + 5.0 * p.diff_bias_walk * std::sqrt(10.0));

  SensorParams off = p;
  off.calibrate_at_boot = false;
  Sensors raw(off, 5), calibrated(p, 5);
  double max_diff = 0;
  for (int i = 0; i < 1000; ++i) max_diff = std::max(max_diff, std::fabs(calibrated.baro(t, 0.01).pressure - raw.baro(t, 0.01).pressure));
  CHECK(max_diff == 0.0);  // the firmware sends the baro pressure as measured
  CHECK(calibrated.boot_calibration()->baro_ground().done);
}

// ---------------------------------------------------------------- the world's magnetic field ---

TEST_CASE("sensors: the world's field is the World Magnetic Model's at the origin on the date") {
  const SensorParams p;  // Provo, 1387 m, 2025-07-01, no mag_* settings
  CHECK(std::isnan(p.mag_declination));
  CHECK(p.date == tern::decimal_year(2025, 7, 1));
  const tern::MagneticField wmm = tern::world_magnetic_field(p.origin_lat, p.origin_lon, p.origin_alt, p.date);
  const Sensors s(p, 1);
  CHECK(s.earth_field().model == "WMM-2025");
  CHECK_FALSE(s.earth_field().extrapolated);
  CHECK((s.earth_field().ned - wmm.ned).norm() < 1e-18);  // T
  CHECK(s.earth_field().declination == wmm.declination);
  // Another place and date: another field, and a date past WMM2025's span is flagged.
  SensorParams q = p;
  q.origin_lat = 47.3977;  // Zurich
  q.origin_lon = 8.5456;
  q.date = tern::decimal_year(2031, 1, 1);
  const tern::MagneticField fq = earth_field(q);
  CHECK(fq.extrapolated);
  CHECK(std::fabs(fq.declination - wmm.declination) > 0.1);  // rad: ~4 deg east vs ~10 deg east
}

TEST_CASE("sensors: a set mag_declination / _inclination / _intensity overrides the model's") {
  SensorParams p;
  p.mag_declination = 0.1857972802;
  const tern::MagneticField one = earth_field(p);
  const tern::MagneticField wmm = tern::world_magnetic_field(p.origin_lat, p.origin_lon, p.origin_alt, p.date);
  CHECK(one.declination == 0.1857972802);
  CHECK(one.inclination == wmm.inclination);
  CHECK(one.intensity == wmm.intensity);
  CHECK(one.model == "WMM-2025");
  p.mag_inclination = 1.139436457;
  p.mag_intensity = 5.07163e-5;
  const tern::MagneticField fixed = earth_field(p);
  CHECK(fixed.model == "mag_* settings");
  const double I = 1.139436457, D = 0.1857972802;  // the old fixed field, bit for bit
  CHECK(fixed.ned ==
        Eigen::Vector3d(5.07163e-5 * std::cos(I) * std::cos(D), 5.07163e-5 * std::cos(I) * std::sin(D), 5.07163e-5 * std::sin(I)));
  CHECK(Sensors(p, 3).earth_field().ned == fixed.ned);
}

TEST_CASE("range finder: the slant distance to the ground, its noise by distance, no return beyond 40 m or looking up") {
  const SensorParams p;  // LIDAR-Lite v3's figures
  StateVector x = StateVector::Zero();
  x[E0] = 1.0;
  x[PD] = -3.0;
  RangeFinder r(p, 11);
  std::vector<double> near, far;
  for (int i = 0; i < 4000; ++i) near.push_back(r.distance(x) - 3.0);
  CHECK(std::fabs(mean(near)) < 0.003);
  CHECK(stddev(near) == doctest::Approx(0.025).epsilon(0.05));
  x[PD] = -20.0;
  for (int i = 0; i < 4000; ++i) far.push_back(r.distance(x) - 20.0);
  CHECK(stddev(far) == doctest::Approx(0.10).epsilon(0.05));
  x[PD] = -41.0;
  CHECK(r.distance(x) == std::numeric_limits<double>::infinity());
  // banked 60 deg at 10 m: the beam meets the ground at 20 m
  SensorParams ideal = sensor_profile("ideal");
  RangeFinder exact(ideal, 1);
  x[PD] = -10.0;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(std::acos(0.5), Eigen::Vector3d::UnitX()));
  x[E0] = q.w();
  x[E1] = q.x();
  CHECK(exact.distance(x) == doctest::Approx(20.0).epsilon(1e-12));
  const Eigen::Quaterniond up(Eigen::AngleAxisd(2.0, Eigen::Vector3d::UnitX()));  // axis above the horizon
  x[E0] = up.w();
  x[E1] = up.x();
  CHECK(exact.distance(x) == std::numeric_limits<double>::infinity());
  x[E0] = 1.0;  // level, 2 cm up: nearer than its 5 cm
  x[E1] = 0.0;
  x[PD] = -0.02;
  CHECK(exact.distance(x) == -std::numeric_limits<double>::infinity());
  SensorParams bad;
  bad.range_min = 50.0;  // beyond its 40-m range_max
  CHECK_THROWS_WITH_AS(RangeFinder(bad, 1), "range_min (50.000000 m) must be below range_max (40.000000 m)", std::invalid_argument);
}
