// truth_sim.hpp: a small kinematic truth generator for the estimator tests and benchmark.
//
// The aircraft's attitude is scripted as smooth Euler-angle profiles; its air-relative velocity
// in the body frame is fixed, Va (cos alpha, 0, sin alpha) (zero sideslip by construction), and
// the ground velocity is v = R v_r + w with a constant wind w. Turns are coordinated: psi_dot =
// g tan(phi) / Va. From this exact kinematics:
//   omega (body rates) from the Euler rates (Beard & McLain eq. 3.2),
//   a_ned = R (omega x v_r)  (v_r constant in the body frame),
//   specific force f = R^T (a_ned - g e3).
// A `static` mode keeps the aircraft at rest (v = 0) at a fixed attitude.
// Sensors follow the ROSflight simulator's models: IMU 400 Hz (accel 0.2 m/s^2, gyro 0.0023
// rad/s white noise, constant biases), GNSS 10 Hz (Gauss-Markov position error 0.21 m / 0.4 m,
// time constant 1100 s; velocity noise 0.01 m/s), baro 100 Hz (ISA pressure, 4 Pa, bias),
// pitot 100 Hz (1.15 Pa), magnetometer 50 Hz (3e-6 T per axis). Seeded std::mt19937_64.
#pragma once

#include <cmath>
#include <functional>
#include <random>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "tern/geodesy.hpp"
#include "tern/math.hpp"
#include "tern/msg/sensors.hpp"
#include "tern/time.hpp"

namespace tern::ekf::test {

/// Quintic smooth step from 0 (x <= 0) to 1 (x >= 1), C2.
inline double smooth_step(double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  return x * x * x * (10.0 + x * (-15.0 + 6.0 * x));
}

/// A change of an angle by `delta` rad (or of the airspeed by `delta` m/s) starting at `t0` s,
/// lasting `duration` s.
struct Ramp {
  double t0, duration, delta;
  double at(double t) const { return delta * smooth_step((t - t0) / duration); }
};

struct Truth {
  double t = 0.0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
  double phi = 0.0, theta = 0.0, psi = 0.0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();  ///< body rates
  Eigen::Vector3d f = Eigen::Vector3d::Zero();      ///< specific force, body
  Eigen::Quaterniond q() const { return Eigen::Quaterniond(R); }
};

struct SimOptions {
  bool static_mode = false;  ///< at rest (v = 0) at attitude (phi0, theta0, psi0)
  double Va = 18.0, alpha = 0.05;
  double phi0 = 0.0, gamma0 = 0.0, psi0 = 0.0;
  std::vector<Ramp> phi_ramps, gamma_ramps, Va_ramps;
  Eigen::Vector2d wind = Eigen::Vector2d(3.0, -4.0);
  // sensor errors
  Eigen::Vector3d gyro_bias = Eigen::Vector3d(0.01, -0.015, 0.008);
  Eigen::Vector3d accel_bias = Eigen::Vector3d(0.1, -0.08, 0.12);
  double baro_bias = 25.0;         ///< Pa
  double baro_static_error = 0.0;  ///< the static port reads p + this x the dynamic pressure
  double accel_noise = 0.2, gyro_noise = 0.0023, baro_noise = 4.0, pitot_noise = 1.15, mag_noise = 3e-6, gnss_h = 0.21, gnss_v = 0.4,
         gnss_vel_noise = 0.01;
  double gnss_k = 1.0 / 1100.0;
  double declination = 0.1857972802, inclination = 1.139436457, field = 5.07163e-5;
  double lat0 = 40.2463724, lon0 = -111.6474138, alt0 = 1387.0;
  double g = 9.81, rho = 1.225;
  std::uint64_t seed = 7;
};

/// The flight the tests and the benchmark share: straight and level, a 30-degree-bank turn, a
/// climb, a 60-degree-bank turn.
inline SimOptions mixed_flight() {
  constexpr double deg = tern::kPi / 180.0;
  SimOptions o;
  o.psi0 = 0.7;
  o.phi_ramps = {{30.0, 2.0, 30.0 * deg}, {50.0, 2.0, -30.0 * deg}, {90.0, 3.0, 60.0 * deg}, {110.0, 3.0, -60.0 * deg}};
  o.gamma_ramps = {{60.0, 2.0, 0.1}, {75.0, 2.0, -0.1}};
  return o;
}

/// Steps the truth at 400 Hz and produces the sensor messages due at each step.
class TruthSim {
 public:
  static constexpr Nanos kImuPeriod = 2'500'000;

  explicit TruthSim(SimOptions o) : o_(std::move(o)), rng_(o_.seed), geo_(o_.lat0, o_.lon0, o_.alt0) {
    std::normal_distribution<double> n(0.0, 1.0);
    gnss_err_ = Eigen::Vector3d(o_.gnss_h * n(rng_), o_.gnss_h * n(rng_), o_.gnss_v * n(rng_));
    truth_.psi = o_.psi0;
    evaluate(0.0);
  }

  const Truth& truth() const { return truth_; }
  const SimOptions& options() const { return o_; }
  Nanos now() const { return k_ * kImuPeriod; }

  /// Advances one IMU period.
  void advance() {
    const double t0 = to_seconds(now());
    const double dt = to_seconds(kImuPeriod);
    if (!o_.static_mode) {
      // psi: RK4 of psi_dot = g tan(phi) / Va; p: Simpson on the exact velocity.
      const auto psid = [&](double t) { return o_.g * std::tan(phi_at(t)) / Va_at(t); };
      const double psi0 = truth_.psi;
      const double k1 = psid(t0), k2 = psid(t0 + dt / 2), k4 = psid(t0 + dt);
      const double psi_mid = psi0 + dt / 2 * (k1 + k2) / 2;  // trapezoid to the midpoint
      const Eigen::Vector3d v0 = truth_.v;
      const double psi1 = psi0 + dt / 6 * (k1 + 4 * k2 + k4);
      const Eigen::Vector3d vm = velocity(t0 + dt / 2, psi_mid);
      const Eigen::Vector3d v1 = velocity(t0 + dt, psi1);
      truth_.p += dt / 6 * (v0 + 4 * vm + v1);
      truth_.psi = psi1;
    }
    ++k_;
    evaluate(to_seconds(now()));
  }

  msg::Imu imu() {
    msg::Imu m;
    m.stamp = now();
    m.accel = truth_.f + o_.accel_bias + noise3(o_.accel_noise);
    m.gyro = truth_.omega + o_.gyro_bias + noise3(o_.gyro_noise);
    return m;
  }
  bool gnss_due() const { return k_ % 40 == 0; }
  bool baro_due() const { return k_ % 4 == 0; }
  bool pitot_due() const { return k_ % 4 == 2; }
  bool mag_due() const { return k_ % 8 == 1; }

  msg::Gnss gnss() {
    const double dt = 0.1;
    const double a = std::exp(-o_.gnss_k * dt), s = std::sqrt(1 - a * a);
    std::normal_distribution<double> n(0.0, 1.0);
    gnss_err_ = a * gnss_err_ + s * Eigen::Vector3d(o_.gnss_h * n(rng_), o_.gnss_h * n(rng_), o_.gnss_v * n(rng_));
    const Eigen::Vector3d p = truth_.p + gnss_err_;
    msg::Gnss m;
    m.stamp = now();
    m.fix_type = msg::FixType::fix_3d;
    m.num_sats = 12;
    const GeoPoint fix = geo_.to_geodetic(p);
    m.lat = fix.lat;
    m.lon = fix.lon;
    m.alt = fix.alt;
    m.vel = truth_.v + noise3(o_.gnss_vel_noise);
    m.h_acc = o_.gnss_h;
    m.v_acc = o_.gnss_v;
    m.s_acc = o_.gnss_vel_noise;
    return m;
  }
  msg::Baro baro() {
    msg::Baro m;
    m.stamp = now();
    const double h = o_.alt0 - truth_.p.z();
    const double u_r = air_velocity_body().x();
    m.pressure = 101325.0 * std::pow(1.0 - h / 44330.769, 1.0 / 0.190263) + o_.baro_static_error * 0.5 * o_.rho * u_r * u_r + o_.baro_bias +
                 o_.baro_noise * normal();
    return m;
  }
  msg::DiffPressure pitot() {
    msg::DiffPressure m;
    m.stamp = now();
    const double u_r = air_velocity_body().x();
    m.pressure = 0.5 * o_.rho * u_r * u_r + o_.pitot_noise * normal();
    return m;
  }
  msg::Mag mag() {
    msg::Mag m;
    m.stamp = now();
    const Eigen::Vector3d mn(std::cos(o_.inclination) * std::cos(o_.declination), std::cos(o_.inclination) * std::sin(o_.declination),
                             std::sin(o_.inclination));
    m.field = truth_.R.transpose() * mn * o_.field + noise3(o_.mag_noise);
    return m;
  }
  /// NED position (sim frame) of a geodetic point.
  Eigen::Vector3d ned_of(double lat, double lon, double alt) const { return geo_.to_ned(lat, lon, alt); }
  Eigen::Vector3d wind_ned() const { return {o_.wind.x(), o_.wind.y(), 0.0}; }
  Eigen::Vector3d air_velocity_body() const { return truth_.R.transpose() * (truth_.v - wind_ned()); }

 private:
  double phi_at(double t) const {
    double a = o_.phi0;
    for (const auto& r : o_.phi_ramps) a += r.at(t);
    return a;
  }
  double gamma_at(double t) const {
    double a = o_.gamma0;
    for (const auto& r : o_.gamma_ramps) a += r.at(t);
    return a;
  }
  double theta_at(double t) const { return o_.static_mode ? o_.gamma0 : gamma_at(t) + o_.alpha; }
  double Va_at(double t) const {
    double a = o_.Va;
    for (const auto& r : o_.Va_ramps) a += r.at(t);
    return a;
  }
  Eigen::Vector3d v_r_body(double t) const { return Va_at(t) * Eigen::Vector3d(std::cos(o_.alpha), 0.0, std::sin(o_.alpha)); }
  Eigen::Vector3d velocity(double t, double psi) const {
    return rotation_from_euler(phi_at(t), theta_at(t), psi) * v_r_body(t) + wind_ned();
  }
  void evaluate(double t) {
    truth_.t = t;
    truth_.phi = phi_at(t);
    truth_.theta = theta_at(t);
    truth_.R = rotation_from_euler(truth_.phi, truth_.theta, truth_.psi);
    const Eigen::Vector3d g_ned(0.0, 0.0, o_.g);
    if (o_.static_mode) {
      truth_.v.setZero();
      truth_.omega.setZero();
      truth_.f = -truth_.R.transpose() * g_ned;
      return;
    }
    const double h = 1e-5;
    const double phid = (phi_at(t + h) - phi_at(t - h)) / (2 * h);
    const double thetad = (theta_at(t + h) - theta_at(t - h)) / (2 * h);
    const double psid = o_.g * std::tan(truth_.phi) / Va_at(t);
    const double sf = std::sin(truth_.phi), cf = std::cos(truth_.phi);
    const double st = std::sin(truth_.theta), ct = std::cos(truth_.theta);
    truth_.omega = Eigen::Vector3d(phid - psid * st, thetad * cf + psid * sf * ct, -thetad * sf + psid * cf * ct);
    const Eigen::Vector3d v_r = v_r_body(t);
    const Eigen::Vector3d v_r_dot = (v_r_body(t + h) - v_r_body(t - h)) / (2 * h);  // along body x and z
    truth_.v = truth_.R * v_r + wind_ned();
    const Eigen::Vector3d a_ned = truth_.R * (truth_.omega.cross(v_r) + v_r_dot);
    truth_.f = truth_.R.transpose() * (a_ned - g_ned);
  }
  double normal() { return std::normal_distribution<double>(0.0, 1.0)(rng_); }
  Eigen::Vector3d noise3(double s) { return Eigen::Vector3d(s * normal(), s * normal(), s * normal()); }

  SimOptions o_;
  std::mt19937_64 rng_;
  GeoOrigin geo_;
  Truth truth_;
  Eigen::Vector3d gnss_err_;
  std::int64_t k_ = 0;
};

}  // namespace tern::ekf::test
