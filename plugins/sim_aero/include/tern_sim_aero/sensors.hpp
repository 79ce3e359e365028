// tern_sim_aero/sensors.hpp: sensor models of the simulator (Beard & McLain, ch. 7, with the
// defaults of the ROSflight simulator): IMU, magnetometer, barometer, differential pressure and
// GNSS. Noise is drawn from a seeded Rng (random.hpp) through Boost's ziggurat normal
// distribution (its output is fixed by Boost's code, where std::normal_distribution's differs
// between standard libraries, and it is 2.4x faster); biases start uniformly in +-range and
// wander as random walks; magnetometer and GNSS position errors are Gauss-Markov.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <boost/random/normal_distribution.hpp>

#include "tern/geodesy.hpp"
#include "tern/magnetic_model.hpp"
#include "tern/msg/sensors.hpp"
#include "tern_sim_aero/boot_calibration.hpp"
#include "tern_sim_aero/gnss_sky.hpp"
#include "tern/aero/model.hpp"
#include "tern_sim_aero/random.hpp"

namespace tern::sim {

/// Every noise, bias and error figure of the sensors (1-sigma values unless said otherwise). The
/// defaults are ROSflight's standalone simulator's raw sensors (the `rosflight` profile adds the
/// FCU's accelerometer calibration at power-up); sensor_profile() in
/// profiles.hpp gives the `realistic` (datasheet) and `ideal` (noise-free) sets. Per-seed errors
/// (turn-on biases, scale factors, cross-axis terms, hard/soft iron) are drawn uniformly in
/// +-range at reset(); fixed installation geometry (mounting rotation, lever arms) is given.
/// A mag_declination / _inclination / _intensity to take from the World Magnetic Model.
inline constexpr double kFromMagneticModel = std::numeric_limits<double>::quiet_NaN();

struct SensorParams {
  // IMU (ROSflight: 400 Hz, accel 0.2 m/s^2, gyro noise as the 0.0023 rad/s)
  double accel_noise = 0.2;        ///< m/s^2 per sample
  double accel_bias_range = 0.05;  ///< initial bias uniform in +-range, m/s^2
  double accel_bias_walk = 2e-4;   ///< bias random walk, m/s^2/sqrt(s)
  double gyro_noise = 0.0023;      ///< rad/s per sample
  double gyro_bias_range = 0.01;   ///< rad/s
  /// rad/s/sqrt(s). ROSflight's simulator adds T_s * 1e-5 * N(0,1) per IMU sample (its
  /// gyro_bias_walk_stdev, scaled by the sample time), i.e. 1e-5 * sqrt(T_s) = 5e-7 per sqrt(s) at 400 Hz.
  double gyro_bias_walk = 5e-7;
  double accel_scale_range = 0.0;     ///< per-axis scale-factor error, fraction, uniform in +-range
  double gyro_scale_range = 0.0;      ///< per-axis scale-factor error, fraction, uniform in +-range
  double imu_cross_axis_range = 0.0;  ///< each off-diagonal sensitivity, fraction, uniform in +-range
  /// Mounting rotation of the IMU axes relative to body FRD: roll, pitch, yaw (3-2-1), rad. A
  /// vector v in body axes reads R_mount^T v in IMU axes.
  Eigen::Vector3d imu_misalignment = Eigen::Vector3d::Zero();
  /// IMU position relative to the CG, body FRD, m: the accelerometer also sees the tangential
  /// (omega_dot x r) and centripetal (omega x (omega x r)) accelerations.
  Eigen::Vector3d imu_position = Eigen::Vector3d::Zero();
  /// The FCU's power-up calibrations (boot_calibration.hpp): the gyro mean over its first 1001
  /// samples and the pitot zero are subtracted from then on; the FCU arms once they are done.
  bool calibrate_at_boot = false;
  /// The FCU's stored accelerometer calibration (ROSflight src/sensors.cpp, Sensors::calibrate_accel,
  /// run on the ground before the flight): the mean of 1000 samples plus the firmware's gravity_
  /// (0, 0, 9.80665) (include/sensors.h) becomes PARAM_ACC_{X,Y,Z}_BIAS, subtracted from every sample
  /// (Sensors::correct_imu). The firmware takes the aircraft to be level, so the stored offset also
  /// absorbs at 1 g what the mounting rotation, the cross-axis and the scale errors do to gravity;
  /// accel_bias_range is then the drift since. A mean with |offset| >= 3 m/s^2 is refused ("large
  /// accel bias") and nothing is stored.
  bool accel_calibrated_level = false;
  /// That calibration was taken after this power-up, with this power-up's turn-on bias in its mean
  /// (ROSflight: `calibrate_imu` before the flight, which the firmware requires: it refuses to arm
  /// with ERROR_UNCALIBRATED_IMU, state_manager.cpp, while every ACC_ and GYRO_ bias parameter is 0);
  /// what is left is the mean's noise (accel_noise / sqrt(1000)), the floor's level and the bias walk
  /// since. false: it was stored in an earlier session and accel_bias_range is the drift since.
  bool accel_calibrated_at_power_up = false;
  /// Roll and pitch of the surface the aircraft stood on during that calibration, each uniform in
  /// +-range, rad: what was taken as level.
  double accel_calibration_tilt_range = 0.0;
  double accel_vibration = 0.0;  ///< motor vibration at full throttle, m/s^2 per axis, 1 sigma (scales with throttle)
  double gyro_vibration = 0.0;   ///< motor vibration at full throttle, rad/s per axis, 1 sigma (scales with throttle)
  // Resolution of each sensor's digital output (its LSB), applied to the raw reading before the
  // FCU's calibrations: a real sensor gives whole counts. 0: a continuous value (ROSflight's
  // simulator, whose profile this default is, draws continuous Gaussian noise).
  double accel_resolution = 0.0;             ///< m/s^2 per count
  double gyro_resolution = 0.0;              ///< rad/s per count
  double imu_temperature_resolution = 0.0;   ///< K per count
  double mag_resolution = 0.0;               ///< T per count
  double baro_resolution = 0.0;              ///< Pa per count (the temperature: baro_temperature_resolution)
  double baro_temperature_resolution = 0.0;  ///< K per count
  double diff_resolution = 0.0;              ///< Pa per count
  double diff_temperature_resolution = 0.0;  ///< K per count
  // magnetometer (ROSflight: 50 Hz; field of the default origin). ROSflight's error is a
  // Gauss-Markov process eta <- exp(-k_mag T_s) eta + T_s * mag_stdev * N(0,1) with mag_stdev 3 uT,
  // k_mag 7 /s and T_s 0.02 s, and no white part: steady sigma 3e-6 * 0.02 / sqrt(1 - exp(-0.28)).
  double mag_noise = 0.0;            ///< T per axis per sample (white part)
  double mag_gm_sigma = 1.2145e-7;   ///< Gauss-Markov error, steady-state sigma, T
  double mag_gm_tau = 1.0 / 7.0;     ///< Gauss-Markov time constant (1 / k_mag), s
  double mag_hard_iron_range = 0.0;  ///< residual hard iron after calibration, T per axis, uniform in +-range
  double mag_soft_iron_range = 0.0;  ///< residual soft iron, each element of (S - I), fraction, uniform in +-range
  /// Field of the motor current at full throttle, body FRD, T (scales with throttle).
  Eigen::Vector3d mag_motor_field = Eigen::Vector3d::Zero();
  /// The Earth's field at the origin (earth_field.hpp). NaN, the default: the World Magnetic
  /// Model's at origin_lat/lon/alt on `date`; a finite value overrides that component.
  double mag_declination = kFromMagneticModel;  ///< rad (east of true north positive)
  double mag_inclination = kFromMagneticModel;  ///< rad (down positive)
  double mag_intensity = kFromMagneticModel;    ///< T
  /// The world's date, decimal year (tern::decimal_year): the date of the magnetic model. Fixed, not
  /// the clock, so that a flight is the same whenever it is flown; 2025-07-01 lies in WMM2025's
  /// first year, where its secular variation has had least time to drift from the real field.
  double date = tern::decimal_year(2025, 7, 1);
  // barometer (ROSflight: 100 Hz, 4 Pa)
  double baro_noise = 4.0;         ///< Pa
  double baro_bias_range = 500.0;  ///< Pa
  double baro_bias_walk = 1.0;     ///< Pa/sqrt(s)
  /// Static-port position error: the port reads p + 0.5 rho (K_x u_r^2 + K_y v_r^2 + K_z w_r^2),
  /// (u_r, v_r, w_r) the relative wind in body FRD, each K a fraction of that component's dynamic
  /// pressure (PX4 EKF2's EKF2_PCOEF_XP/YP/YN/Z model, ArduPilot's BARO1_WCF_*): K_x =
  /// baro_static_error (flow from ahead), K_y = baro_static_error_yp for v_r > 0 (the relative wind
  /// from the right), baro_static_error_yn for v_r < 0, K_z = baro_static_error_z. With
  /// alpha = beta = 0 the error is baro_static_error times the dynamic pressure.
  double baro_static_error = 0.0;
  double baro_static_error_yp = 0.0;
  double baro_static_error_yn = 0.0;
  double baro_static_error_z = 0.0;
  // differential pressure (ROSflight: 100 Hz, 1.15 Pa)
  double diff_noise = 1.15;       ///< Pa
  double diff_bias_range = 0.15;  ///< Pa
  double diff_bias_walk = 0.01;   ///< Pa/sqrt(s)
  double diff_scale_range = 0.0;  ///< installation scale error, fraction, uniform in +-range
  // GNSS position error: first-order Gauss-Markov (book sec. 7.5). ROSflight drives it with
  // T_s * stdev * N(0,1) per 10 Hz fix (horizontal 0.21, vertical 0.40) with 1/k = 1100 s from
  // zero: steady-state sigma = stdev sqrt(T_s) / sqrt(2 k) = 1.557 m and 2.966 m.
  double gnss_h_sigma = 0.21 * 0.316227766 * 23.4520788;  ///< horizontal, per axis, steady state, m
  double gnss_v_sigma = 0.40 * 0.316227766 * 23.4520788;  ///< vertical, steady state, m
  double gnss_tau = 1100.0;                               ///< correlation time of the position error, s
  bool gnss_start_steady = false;                         ///< initial error drawn from the steady state (false: zero)
  double gnss_vel_noise = 0.01;                           ///< velocity error per axis, steady sigma, m/s
  double gnss_vel_tau = 0.0;                              ///< velocity error correlation time, s (0: white)
  /// Antenna position relative to the CG, body FRD, m (the fix is the antenna's position and
  /// velocity: p + R r, v + R (omega x r)).
  Eigen::Vector3d gnss_antenna_position = Eigen::Vector3d::Zero();
  double gnss_latency = 0.0;       ///< the fix is valid at t and delivered at t + latency, s
  double gnss_h_acc = 0.21 * 3.0;  ///< reported horizontal accuracy, m
  double gnss_v_acc = 0.40 * 3.0;  ///< reported vertical accuracy, m
  double gnss_s_acc = 0.01;        ///< reported speed accuracy, m/s
  int gnss_num_sats = 12;          ///< satellites in the solution (with gnss_sky: above the elevation mask)
  /// The antenna's view of the sky (gnss_sky.hpp): gnss_num_sats satellites above
  /// gnss_elevation_mask; those below gnss_antenna_cutoff above the antenna's plane (body up) are
  /// lost, and tracked again gnss_reacquisition after they return. The whole sky's solution keeps
  /// the errors above (gnss_h_sigma, gnss_vel_noise, the reported accuracies); fewer satellites
  /// move it and scale the reported accuracies by the dilution of precision; fewer than four: no fix.
  bool gnss_sky = false;
  double gnss_elevation_mask = 0.0;  ///< rad
  double gnss_antenna_cutoff = 0.0;  ///< rad above the antenna's plane
  double gnss_reacquisition = 0.0;   ///< s
  double gnss_pdop_mask = 0.0;       ///< no fix with a larger PDOP (u-blox UBX-CFG-NAV5 pDop; 0: no mask)
  /// The receiver's dynamic platform model (u-blox UBX-CFG-NAV5 dynModel): its velocity output
  /// follows accelerations up to gnss_max_acceleration (m/s^2; 0: every one); what is beyond lags,
  /// catching up with the time constant gnss_lag_tau (s).
  double gnss_max_acceleration = 0.0;
  double gnss_lag_tau = 0.0;
  // downward range finder (rangefinder.hpp; Garmin LIDAR-Lite v3's specifications in every
  // profile but `ideal`: ROSflight's simulator has none)
  double range_noise_near = 0.025;                           ///< m, 1 sigma below range_far_from
  double range_noise_far = 0.10;                             ///< m, 1 sigma at and beyond range_far_from
  double range_far_from = 5.0;                               ///< m
  double range_min = 0.05;                                   ///< m
  double range_max = 40.0;                                   ///< m
  Eigen::Vector3d range_position = Eigen::Vector3d::Zero();  ///< body FRD, m, from the CG
  // origin of the NED frame (ROSflight's default, Provo UT)
  double origin_lat = 40.2463724;    ///< deg
  double origin_lon = -111.6474138;  ///< deg
  double origin_alt = 1387.0;        ///< m above mean sea level (the ground, p_d = 0)
};

/// How often the world's installation and sky degraded the sensors since reset(): the figures a
/// bench shows beside the estimator's (if never, the effects were not there).
struct SensorEffects {
  int gnss_fixes = 0;                ///< GNSS samples taken
  int gnss_degraded = 0;             ///< of them, solutions from fewer than every satellite in the sky
  int gnss_lost = 0;                 ///< of them, no fix (fewer than four satellites)
  double gnss_velocity_lag_max = 0;  ///< m/s: the largest lag of the dynamic platform model
  double baro_static_error_max = 0;  ///< Pa: the largest |static-port error|
};

/// What the sensors see of the true aircraft at one instant.
struct Truth {
  StateVector x = StateVector::Zero();
  ForcesMoments fm;   ///< at x with the current inputs and wind
  double mass = 1.0;  ///< kg (for the specific force)
  double rho = 1.2682;
  Eigen::Vector3d omega_dot = Eigen::Vector3d::Zero();  ///< body angular acceleration, rad/s^2
  double throttle = 0.0;                                ///< actual motor setting 0..1 (vibration, motor-current field)
};

struct ImuSample {
  Eigen::Vector3d accel, gyro;
  double temperature = 288.15;
};
struct MagSample {
  Eigen::Vector3d field;
};
struct BaroSample {
  double pressure = 0, temperature = 288.15;
};
struct DiffPressureSample {
  double pressure = 0, temperature = 288.15;
};
struct GnssSample {
  bool fix = true;
  double lat = 0, lon = 0, alt = 0;  ///< deg, deg, m MSL
  Eigen::Vector3d vel_ned = Eigen::Vector3d::Zero();
  double h_acc = 0, v_acc = 0, s_acc = 0;
  int num_sats = 0;
  double hdop = 0, vdop = 0;  ///< of the satellites used (0: the sky is not modelled)
};

/// The receiver's message for a sample (tern/msg/sensors.hpp), stamped `stamp` (its time of
/// validity too): a 3-D fix, or, where the sample has none (GnssSample::fix false: the antenna
/// sees too few satellites), a report without a fix that counts the satellites.
msg::Gnss gnss_message(const GnssSample& m, Nanos stamp);

/// 1976 standard atmosphere below 11 km: pressure (Pa) and temperature (K) at altitude h (m MSL).
double standard_pressure(double h);
double standard_temperature(double h);

/// The simulated world's geodesy: NED position about the simulator's origin <-> WGS-84 latitude,
/// longitude (deg) and altitude (m above the ellipsoid, reported as MSL: no geoid), exact on the
/// ellipsoid (through ECEF, the latitude iterated to convergence). The estimator and the host
/// convert with tern::GeoOrigin (tern/geodesy.hpp, GeographicLib's LocalCartesian), which gives
/// the same points to 3e-14 deg and 4e-9 m but not the same last bits: the world keeps this
/// arithmetic so that every flight stays bit-identical to the reference logs.
class WorldGeodesy {
 public:
  explicit WorldGeodesy(const GeoPoint& origin);
  GeoPoint to_geodetic(const Eigen::Vector3d& ned) const;
  Eigen::Vector3d to_ned(const GeoPoint& p) const;
  Eigen::Vector3d to_ned(double lat, double lon, double alt) const { return to_ned(GeoPoint{lat, lon, alt}); }

 private:
  Eigen::Vector3d ecef0_;
  Eigen::Matrix3d R_;  // ECEF -> NED at the origin
};

/// The sensor error states and their draws. All functions advance error states by dt, the time
/// since that sensor's previous sample (s).
class Sensors {
 public:
  Sensors(const SensorParams& p, std::uint64_t seed);
  ~Sensors();
  const SensorParams& params() const { return p_; }
  /// Redraws the per-seed errors (turn-on biases, scale and cross-axis terms, hard/soft iron,
  /// pitot scale) and restarts the error states: at zero, or drawn from their steady state when
  /// gnss_start_steady (same seed: same draws).
  void reset();

  /// With calibrate_at_boot: the FCU calibrated before the start, on the ground at rest (an air
  /// start): its gyro bias and pitot zero are the true ones plus the noise of their windows'
  /// means. Call once after construction or reset().
  void calibrated_before_start();

  ImuSample imu(const Truth& t, double dt);
  MagSample mag(const Truth& t, double dt);
  BaroSample baro(const Truth& t, double dt);
  DiffPressureSample diff_pressure(const Truth& t, double dt);
  GnssSample gnss(const Truth& t, double dt);

  /// The true turn-on gyro bias (before any calibration), rad/s.
  const Eigen::Vector3d& gyro_bias() const { return gyro_bias_; }
  /// The FCU's power-up calibrations; null when calibrate_at_boot is off.
  const BootCalibration* boot_calibration() const { return p_.calibrate_at_boot ? &boot_ : nullptr; }
  const Eigen::Vector3d& accel_bias() const { return accel_bias_; }
  /// The stored accelerometer offset subtracted from every sample (accel_calibrated_level), m/s^2;
  /// zero without it or when the firmware refused it.
  const Eigen::Vector3d& accel_calibration() const { return accel_cal_; }
  const SensorEffects& effects() const { return effects_; }
  /// Current GNSS position error of the antenna fix (the Gauss-Markov state), NED, m.
  const Eigen::Vector3d& gnss_error() const { return gnss_gm_; }
  const WorldGeodesy& origin() const { return *origin_; }
  /// The Earth's field the magnetometer sees (earth_field.hpp), fixed at construction.
  const tern::MagneticField& earth_field() const { return earth_field_; }

 private:
  double gauss() { return n_(rng_); }
  Eigen::Vector3d gauss3() {
    const double a = gauss(), b = gauss(), c = gauss();
    return {a, b, c};
  }
  double uniform(double range) { return range * (2.0 * u_(rng_) - 1.0); }
  Eigen::Vector3d uniform3(double range);
  Eigen::Matrix3d draw_sensor_matrix(double scale_range, double cross_range);
  Eigen::Matrix3d draw_soft_iron(double range);
  Eigen::Vector3d draw_gnss_start(const Eigen::Vector3d& sigma);
  Eigen::Vector3d gnss_sigma() const;
  Eigen::Vector3d draw_accel_calibration();
  Eigen::Vector3d white_and_vibration(double sigma, double vibration_full, double throttle);
  void step_gnss_errors(double dt);
  double static_port_error(const Truth& t) const;
  void count_effects(const GnssSkyFix& sky);
  SensorParams p_;
  std::uint64_t seed_;
  Rng rng_;
  boost::random::normal_distribution<double> n_{0.0, 1.0};
  std::uniform_real_distribution<double> u_{0.0, 1.0};
  std::unique_ptr<WorldGeodesy> origin_;
  tern::MagneticField earth_field_;
  Eigen::Matrix3d mount_T_;           ///< R_mount^T: body -> IMU axes (fixed)
  Eigen::Matrix3d accel_M_, gyro_M_;  ///< I + scale and cross-axis terms (per seed)
  Eigen::Matrix3d mag_soft_;          ///< soft iron S = I + E (per seed)
  Eigen::Vector3d mag_hard_;          ///< hard iron, T (per seed)
  double diff_scale_ = 1.0;           ///< pitot installation scale (per seed)
  Eigen::Vector3d accel_bias_, gyro_bias_, mag_gm_, gnss_gm_, gnss_vel_gm_;
  GnssSky gnss_sky_;
  double gnss_time_ = 0.0;  ///< s since reset, the sum of the fixes' dt (the sky's clock)
  SensorEffects effects_;
  Eigen::Vector3d accel_cal_ = Eigen::Vector3d::Zero();  ///< stored accelerometer offset (per seed)
  double baro_bias_ = 0, diff_bias_ = 0;
  BootCalibration boot_;
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
  void reset() {
    next_due = 0;
    last_sample = -1;
  }
};

}  // namespace tern::sim
