// aerobatic_sim.hpp: an aerobatic flight (aileron rolls, inside loops, an Immelmann, banked
// turns) as kinematic truth, read through sim_aero's sensor models with a sensor profile
// (sim::Sensors: `realistic` = datasheet IMU with vibration, scale and cross-axis errors, a
// hand-mounted board, residual hard and soft iron, the motor's field, a u-blox M8N delivered
// gnss_latency after its epoch). Issue 61's aerobatic target: no yaw reset, yaw within 3 deg RMS,
// the magnetometer fused throughout. Only built when the sim_aero plugin is part of the build.
//
// The kinematics (no aerodynamic model: the attitude is scripted, the path follows from it):
//   R' = R [omega]x, omega = the manoeuvre's body rate (a quintic bell that turns by exactly its
//   angle), or between manoeuvres the coordinated turn psi' = g tan(phi) / Va about the vertical;
//   v_r = Va (cos alpha, 0, sin alpha) in body axes (no sideslip), Va from the energy,
//   Va^2 = Va0^2 - 2 g (h - h0) (a loop trades speed for height), at least Va_min;
//   v = R v_r + wind, a = R (omega x v_r + v_r'), specific force f = R^T (a - g e3).
// The yaw error is the vertical component of the attitude error's rotation vector (NED): defined
// in every attitude, where the Euler yaw is not (vertical flight in a loop).
#pragma once

#include <cmath>
#include <cstdint>
#include <deque>
#include <vector>

#include <Eigen/Geometry>

#include "tern/estimator_ekf/estimator.hpp"
#include "tern/math.hpp"
#include "tern_sim_aero/profiles.hpp"
#include "tern_sim_aero/sensors.hpp"
#include "fly.hpp"

namespace tern::ekf::test {

/// One manoeuvre: a body rate about `axis` (0 roll, 1 pitch) turning by `angle` rad over
/// [t0, t0 + duration] s.
struct Manoeuvre {
  double t0, duration;
  int axis;
  double angle;
  bool active(double t) const { return t >= t0 && t <= t0 + duration; }
  /// d/dt of angle * smooth_step((t - t0) / duration)
  double rate(double t) const {
    const double x = (t - t0) / duration;
    if (x <= 0.0 || x >= 1.0) return 0.0;
    return angle * 30.0 * x * x * (1.0 - x) * (1.0 - x) / duration;
  }
};

/// The flight: 30-deg banked turns (the yaw observed), then rolls, loops and an Immelmann every
/// 12-15 s from 60 s, then turns again. Wind 5 m/s.
inline std::vector<Manoeuvre> aerobatic_sequence() {
  constexpr double d = kRadPerDeg;
  return {{10, 2, 0, 30 * d},   {25, 2, 0, -30 * d},      {35, 2, 0, -30 * d}, {48, 2, 0, 30 * d},  // turns
          {60, 3, 0, 360 * d},                                                                      // aileron roll
          {72, 6, 1, 360 * d},                                                                      // inside loop
          {86, 3, 0, -360 * d},                                                                     // roll the other way
          {98, 6, 1, 360 * d},                                                                      // loop
          {112, 3, 1, 180 * d}, {115.5, 1.5, 0, 180 * d},                                           // Immelmann: half loop, half roll
          {126, 2, 0, 720 * d},                                                                     // two fast rolls (360 deg/s)
          {138, 6, 1, 360 * d}, {150, 3, 0, 360 * d},                                               // loop, roll
          {165, 2, 0, 45 * d},  {185, 2, 0, -45 * d},                                               // a 45-deg turn
          {200, 2, 0, -30 * d}, {215, 2, 0, 30 * d}};
}

class AerobaticTruth {
 public:
  static constexpr Nanos kImuPeriod = 2'500'000;
  double Va0 = 26.0, Va_min = 10.0, alpha = 0.05, g = kGravity;
  Eigen::Vector3d wind = Eigen::Vector3d(4.0, -3.0, 0.0);
  std::vector<Manoeuvre> script = aerobatic_sequence();

  explicit AerobaticTruth(double psi0) : R_(rotation_from_euler(0.0, 0.0, psi0)) { evaluate(); }

  Nanos now() const { return k_ * kImuPeriod; }
  double t() const { return to_seconds(now()); }
  const Eigen::Matrix3d& R() const { return R_; }
  const Eigen::Vector3d& p() const { return p_; }
  const Eigen::Vector3d& v() const { return v_; }
  const Eigen::Vector3d& omega() const { return omega_; }
  const Eigen::Vector3d& omega_dot() const { return omega_dot_; }
  const Eigen::Vector3d& specific_force() const { return f_; }
  double Va() const { return Va_; }
  Eigen::Vector3d air_velocity_body() const { return Va_ * Eigen::Vector3d(std::cos(alpha), 0.0, std::sin(alpha)); }
  void advance() {
    const double dt = to_seconds(kImuPeriod);
    const Eigen::Vector3d v0 = v_, w0 = omega_;
    const Eigen::Vector3d w_mid = body_rate(t() + dt / 2);
    const Eigen::Vector3d rv = w_mid * dt;
    const double a = rv.norm();
    if (a > 0.0) R_ = R_ * Eigen::AngleAxisd(a, rv / a).toRotationMatrix();
    ++k_;
    evaluate();
    p_ += dt / 2 * (v0 + v_);
    omega_dot_ = (omega_ - w0) / dt;
  }

 private:
  Eigen::Vector3d body_rate(double t) const {
    Eigen::Vector3d w = Eigen::Vector3d::Zero();
    bool man = false;
    for (const auto& m : script) {
      if (!m.active(t)) continue;
      w[m.axis] += m.rate(t);
      man = true;
    }
    const double phi = std::atan2(R_(2, 1), R_(2, 2));
    if (!man && std::fabs(phi) < 70.0 * kRadPerDeg) w += R_.transpose() * Eigen::Vector3d(0, 0, g * std::tan(phi) / Va_);
    return w;
  }
  void evaluate() {
    const double h = -p_.z();
    Va_ = std::sqrt(std::max(Va0 * Va0 - 2.0 * g * h, Va_min * Va_min));
    omega_ = body_rate(t());
    const Eigen::Vector3d v_r = air_velocity_body();
    v_ = R_ * v_r + wind;
    const double Va_dot = Va_ > Va_min + 1e-9 ? g * v_.z() / Va_ : 0.0;  // d/dt of the energy's Va
    const Eigen::Vector3d a = R_ * (omega_.cross(v_r) + Va_dot / Va_ * v_r);
    f_ = R_.transpose() * (a - Eigen::Vector3d(0, 0, g));
  }

  Eigen::Matrix3d R_;
  Eigen::Vector3d p_ = Eigen::Vector3d::Zero(), v_ = Eigen::Vector3d::Zero(), omega_ = Eigen::Vector3d::Zero(),
                  omega_dot_ = Eigen::Vector3d::Zero(), f_ = Eigen::Vector3d::Zero();
  double Va_ = 0.0;
  std::int64_t k_ = 0;
};

/// The vertical component (rad) of the rotation from the true attitude to the estimate, in NED.
inline double heading_error(const Eigen::Matrix3d& R_est, const Eigen::Matrix3d& R_true) {
  const Eigen::AngleAxisd d(R_est * R_true.transpose());
  return (d.angle() * d.axis()).z();
}
/// The horizontal part (rad): the tilt error.
inline double tilt_error(const Eigen::Matrix3d& R_est, const Eigen::Matrix3d& R_true) {
  const Eigen::AngleAxisd d(R_est * R_true.transpose());
  return (d.angle() * d.axis()).head<2>().norm();
}

struct AerobaticResult {
  Rms yaw, tilt, vel;  // rad, rad, m/s: from `settle` s
  std::uint64_t gnss_yaw_resets = 0, gnss_resets = 0, mag_resets = 0, mag_resumes = 0;
  long mag_samples = 0, mag_inhibited_samples = 0;  ///< magnetometer samples from `settle` s; of them while not fused
  double mag_fused_fraction() const {
    return mag_samples ? 1.0 - static_cast<double>(mag_inhibited_samples) / static_cast<double>(mag_samples) : 0.0;
  }
};

/// How the receiver's epoch reaches the estimator.
enum class GnssEpoch {
  reported,  ///< time_of_validity set (sim_aero's receiver), the estimator's gnss_delay 0
  assumed    ///< not reported (a log without it): the estimator assumes gnss_delay `assumed_delay`
};

/// Flies the aerobatic sequence for `seconds` with the sensor `profile`, seed `seed`; errors from
/// `settle` s. `cfg` as a user configures it (installation, gnss_delay for GnssEpoch::assumed).
/// `latency` >= 0 replaces the profile's GNSS latency (s).
inline AerobaticResult fly_aerobatics(std::uint64_t seed, const EstimatorConfig& cfg, GnssEpoch epoch, double latency = -1.0,
                                      const char* profile = "realistic", double seconds = 230.0, double settle = 30.0) {
  AerobaticTruth sim(0.7);
  sim::SensorParams params = sim::sensor_profile(profile);
  if (latency >= 0.0) params.gnss_latency = latency;
  sim::Sensors sensors(params, seed);
  sensors.calibrated_before_start();
  constexpr double rho = 1.2682;  // sim_aero's air density (its Truth default)
  Estimator est(cfg);
  const Nanos gnss_late = from_seconds(params.gnss_latency);
  std::deque<msg::Gnss> pending;
  AerobaticResult r;
  const auto truth = [&] {
    sim::Truth s;
    const Eigen::Quaterniond q(sim.R());
    s.x.segment<3>(sim::PN) = sim.p();
    s.x.segment<3>(sim::U) = sim.R().transpose() * sim.v();
    s.x[sim::E0] = q.w();
    s.x[sim::E1] = q.x();
    s.x[sim::E2] = q.y();
    s.x[sim::E3] = q.z();
    s.x.segment<3>(sim::P) = sim.omega();
    s.mass = 1.0;
    s.rho = rho;
    s.fm.f_gravity = sim.R().transpose() * Eigen::Vector3d(0, 0, sim.g);
    s.fm.force = sim.specific_force() + s.fm.f_gravity;
    s.fm.air.v_air = sim.air_velocity_body();
    s.fm.air.Va = sim.Va();
    s.omega_dot = sim.omega_dot();
    s.throttle = 0.6;
    return s;
  };
  const std::int64_t steps = std::llround(seconds / to_seconds(AerobaticTruth::kImuPeriod));
  for (std::int64_t k = 1; k <= steps; ++k) {
    sim.advance();
    const Nanos t = sim.now();
    const sim::Truth tr = truth();
    const auto imu_s = sensors.imu(tr, 0.0025);
    msg::Imu imu;
    imu.stamp = t;
    imu.accel = imu_s.accel;
    imu.gyro = imu_s.gyro;
    est.add_imu(imu);
    if (k % 40 == 0) {
      // the world's fix, or none where the antenna sees too few satellites (inverted: gnss_sky)
      msg::Gnss m = sim::gnss_message(sensors.gnss(tr, 0.1), t + gnss_late);
      m.time_of_validity = epoch == GnssEpoch::reported ? t : 0;
      pending.push_back(m);
    }
    while (!pending.empty() && pending.front().stamp <= t) {
      est.add_gnss(pending.front());
      pending.pop_front();
    }
    if (k % 4 == 0) {
      msg::Baro b;
      b.stamp = t;
      b.pressure = sensors.baro(tr, 0.01).pressure;
      est.add_baro(b);
    }
    if (k % 4 == 2) {
      msg::DiffPressure d;
      d.stamp = t;
      d.pressure = sensors.diff_pressure(tr, 0.01).pressure;
      est.add_diff_pressure(d);
    }
    const bool mag_due = k % 8 == 1;
    if (mag_due) {
      msg::Mag m;
      m.stamp = t;
      m.field = sensors.mag(tr, 0.02).field;
      est.add_mag(m);
    }
    est.check_timeouts(t);
    if (to_seconds(t) < settle || !est.initialized()) continue;
    const Eigen::Matrix3d R_est = est.filter().x().q.toRotationMatrix();
    r.yaw.add(heading_error(R_est, sim.R()));
    r.tilt.add(tilt_error(R_est, sim.R()));
    r.vel.add((est.filter().x().v - sim.v()).norm());
    if (mag_due) {
      ++r.mag_samples;
      if (est.mag_inhibited()) ++r.mag_inhibited_samples;
    }
  }
  r.gnss_yaw_resets = est.gnss_yaw_resets();
  r.gnss_resets = est.gnss_resets();
  r.mag_resets = est.mag_resets();
  r.mag_resumes = est.mag_resumes();
  return r;
}

/// The estimator as a user configures it for sim_aero's `realistic` aircraft (default.yaml's
/// installation: antenna and IMU positions from the CG, body FRD, m).
inline EstimatorConfig aerobatic_config() {
  EstimatorConfig c;
  c.gnss_antenna = Eigen::Vector3d(-0.1, 0.0, -0.08);
  c.imu_position = Eigen::Vector3d(0.05, 0.0, 0.02);
  c.rho = 1.2682;
  return c;
}

}  // namespace tern::ekf::test
