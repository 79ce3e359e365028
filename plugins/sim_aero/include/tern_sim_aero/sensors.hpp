// tern_sim_aero/sensors.hpp: sensor models of the simulator (Beard & McLain, ch. 7, with the
// defaults of the ROSflight simulator): IMU, magnetometer, barometer, differential pressure and
// GNSS. Noise is drawn from the caller's seeded std::mt19937_64 through Boost's ziggurat normal
// distribution (its output is fixed by Boost's code, where std::normal_distribution's differs
// between standard libraries, and it is 2.4x faster); biases start uniformly in +-range and
// wander as random walks; magnetometer and GNSS position errors are Gauss-Markov.
#pragma once

#include <cstdint>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <boost/random/normal_distribution.hpp>

#include "tern_sim_aero/model.hpp"

namespace tern::sim {

/// Every noise, bias and error figure of the sensors (1-sigma values unless said otherwise).
struct SensorParams {
  // IMU (ROSflight: 400 Hz, accel 0.2 m/s^2, gyro noise as the 0.0023 rad/s)
  double accel_noise = 0.2;          ///< m/s^2 per sample
  double accel_bias_range = 0.05;    ///< initial bias uniform in +-range, m/s^2
  double accel_bias_walk = 2e-4;     ///< bias random walk, m/s^2/sqrt(s)
  double gyro_noise = 0.0023;        ///< rad/s per sample
  double gyro_bias_range = 0.01;     ///< rad/s
  /// rad/s/sqrt(s). ROSflight's simulator adds T_s * 1e-5 * N(0,1) per IMU sample (its
  /// gyro_bias_walk_stdev, scaled by the sample time), i.e. 1e-5 * sqrt(T_s) = 5e-7 per sqrt(s) at 400 Hz.
  double gyro_bias_walk = 5e-7;
  // magnetometer (ROSflight: 50 Hz; field of the default origin). ROSflight's error is a
  // Gauss-Markov process eta <- exp(-k_mag T_s) eta + T_s * mag_stdev * N(0,1) with mag_stdev 3 uT,
  // k_mag 7 /s and T_s 0.02 s, and no white part: steady sigma 3e-6 * 0.02 / sqrt(1 - exp(-0.28)).
  double mag_noise = 0.0;            ///< T per axis per sample (white part)
  double mag_gm_sigma = 1.2145e-7;   ///< Gauss-Markov error, steady-state sigma, T
  double mag_gm_tau = 1.0 / 7.0;     ///< Gauss-Markov time constant (1 / k_mag), s
  double mag_declination = 0.1857972802;  ///< rad (east of true north positive)
  double mag_inclination = 1.139436457;   ///< rad (down positive)
  double mag_intensity = 5.07163e-5;      ///< T
  // barometer (ROSflight: 100 Hz, 4 Pa)
  double baro_noise = 4.0;           ///< Pa
  double baro_bias_range = 500.0;    ///< Pa
  double baro_bias_walk = 1.0;       ///< Pa/sqrt(s)
  // differential pressure (ROSflight: 100 Hz, 1.15 Pa)
  double diff_noise = 1.15;          ///< Pa
  double diff_bias_range = 0.15;     ///< Pa
  double diff_bias_walk = 0.01;      ///< Pa/sqrt(s)
  // GNSS (book sec. 7.5: Gauss-Markov with 1/k = 1100 s; ROSflight: 10 Hz). ROSflight drives the
  // error with T_s * stdev * N(0,1) per 10 Hz fix (horizontal 0.21, vertical 0.40), i.e.
  // stdev * sqrt(T_s) per sqrt(s).
  double gnss_h_noise = 0.21 * 0.316227766;  ///< horizontal GM driving noise, m/sqrt(s)
  double gnss_v_noise = 0.40 * 0.316227766;  ///< vertical GM driving noise, m/sqrt(s)
  double gnss_k = 1.0 / 1100.0;      ///< GM rate, 1/s
  double gnss_vel_noise = 0.01;      ///< m/s per axis
  double gnss_h_acc = 0.21 * 3.0;    ///< reported horizontal accuracy, m
  double gnss_v_acc = 0.40 * 3.0;    ///< reported vertical accuracy, m
  double gnss_s_acc = 0.01;          ///< reported speed accuracy, m/s
  int gnss_num_sats = 12;
  // origin of the NED frame (ROSflight's default, Provo UT)
  double origin_lat = 40.2463724;    ///< deg
  double origin_lon = -111.6474138;  ///< deg
  double origin_alt = 1387.0;        ///< m above mean sea level (the ground, p_d = 0)
};

/// What the sensors see of the true aircraft at one instant.
struct Truth {
  StateVector x = StateVector::Zero();
  ForcesMoments fm;   ///< at x with the current inputs and wind
  double mass = 1.0;  ///< kg (for the specific force)
  double rho = 1.2682;
};

struct ImuSample { Eigen::Vector3d accel, gyro; double temperature = 288.15; };
struct MagSample { Eigen::Vector3d field; };
struct BaroSample { double pressure = 0, temperature = 288.15; };
struct DiffPressureSample { double pressure = 0, temperature = 288.15; };
struct GnssSample {
  bool fix = true;
  double lat = 0, lon = 0, alt = 0;               ///< deg, deg, m MSL
  Eigen::Vector3d vel_ned = Eigen::Vector3d::Zero();
  double h_acc = 0, v_acc = 0, s_acc = 0;
  int num_sats = 0;
};

/// 1976 standard atmosphere below 11 km: pressure (Pa) and temperature (K) at altitude h (m MSL).
double standard_pressure(double h);
double standard_temperature(double h);

/// NED position about an origin -> WGS-84 latitude, longitude (deg) and altitude (m above the
/// ellipsoid, reported as MSL: no geoid), and back; exact on the ellipsoid (local tangent plane
/// at the origin, as GeographicLib's LocalCartesian).
class GeoOrigin {
 public:
  GeoOrigin(double lat, double lon, double alt);
  ~GeoOrigin();
  GeoOrigin(const GeoOrigin&) = delete;
  GeoOrigin& operator=(const GeoOrigin&) = delete;
  void to_geodetic(const Eigen::Vector3d& ned, double& lat, double& lon, double& alt) const;
  Eigen::Vector3d to_ned(double lat, double lon, double alt) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The sensor error states and their draws. All functions advance error states by dt, the time
/// since that sensor's previous sample (s).
class Sensors {
 public:
  Sensors(const SensorParams& p, std::uint64_t seed);
  ~Sensors();
  const SensorParams& params() const { return p_; }
  /// Redraws the initial biases and clears the error states (same seed: same draws).
  void reset();

  ImuSample imu(const Truth& t, double dt);
  MagSample mag(const Truth& t, double dt);
  BaroSample baro(const Truth& t, double dt);
  DiffPressureSample diff_pressure(const Truth& t, double dt);
  GnssSample gnss(const Truth& t, double dt);

  const Eigen::Vector3d& gyro_bias() const { return gyro_bias_; }
  const Eigen::Vector3d& accel_bias() const { return accel_bias_; }
  const GeoOrigin& origin() const { return *origin_; }

 private:
  double gauss() { return n_(rng_); }
  Eigen::Vector3d gauss3() { const double a = gauss(), b = gauss(), c = gauss(); return {a, b, c}; }
  double uniform(double range) { return range * (2.0 * u_(rng_) - 1.0); }
  SensorParams p_;
  std::uint64_t seed_;
  std::mt19937_64 rng_;
  boost::random::normal_distribution<double> n_{0.0, 1.0};
  std::uniform_real_distribution<double> u_{0.0, 1.0};
  std::unique_ptr<GeoOrigin> origin_;
  Eigen::Vector3d accel_bias_, gyro_bias_, mag_gm_, gnss_gm_;
  double baro_bias_ = 0, diff_bias_ = 0;
};

/// When a sensor publishes: every `period` ns from 0, unless disabled or inside a drop-out
/// window [start, end) in ns.
struct SensorSchedule {
  std::int64_t period = 0;
  bool enabled = true;
  std::vector<std::pair<std::int64_t, std::int64_t>> dropouts;
  std::int64_t next_due = 0;
  std::int64_t last_sample = -1;  ///< time of the previous sample (-1: none)
  enum class Poll { idle, sample, dropped };
  /// At time t: `sample` when a sample is due and the sensor works, `dropped` when one is due
  /// but the sensor is off or in a drop-out window, `idle` otherwise. Advances the schedule.
  Poll poll(std::int64_t t);
  /// Seconds since the previous sample (one period for the first).
  double dt_since_last(std::int64_t t) const;
  bool dropped(std::int64_t t) const;
  void reset() { next_due = 0; last_sample = -1; }
};

}  // namespace tern::sim
