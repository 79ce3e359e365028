// tern/estimator_ekf/estimator.hpp: the full estimator around the EKF core: sensor checks,
// initialisation (GNSS origin, attitude from specific force and magnetometer, barometer
// calibration), measurement routing, time-outs, GNSS reset, and the msg::State output.
//
// Plain C++: it reads the SDK's sensor message structs (tern/msg/sensors.hpp) and writes
// msg::State, but knows nothing of plugins, ports or parameters, so tests, benchmarks and a
// replay tool can drive it directly. Not thread safe; never allocates after construction except
// when an event is queued (rare: origin set, time-outs, resets).
//
// Life of an estimate:
//   1. Before initialisation, IMU samples feed low-pass averages of accel, gyro and mag, and
//      barometer samples feed the ground calibration (the first baro_calibration_count samples).
//   2. The first GNSS solution with fix_type >= min_fix_type sets the origin (lat, lon, alt):
//      NED positions are those of tern::GeoOrigin (tern/geodesy.hpp) at the origin.
//   3. Initialisation needs the origin, init_min_imu_samples IMU samples and, if a magnetometer
//      is expected, a magnetometer sample (or mag_init_wait seconds since the origin was set).
//      At rest, roll and pitch come from the averaged specific force, yaw from the
//      tilt-compensated magnetometer. Moving (GNSS speed >= 0.5 m/s), the specific force is not
//      gravity: the attitude is the TRIAD solution of the mean specific force since the previous
//      fix (body) against the GNSS velocity difference minus gravity (NED), with the field as
//      the second vector; a moving aircraft therefore initialises at its second fix. Without a
//      magnetometer, yaw is the GNSS course when moving, else 0 with a 1-rad sigma. The gyro
//      bias comes from the averaged gyro when at rest; in flight the wind comes from the air
//      triangle w = v_gnss - Va_pitot R e1 (alpha = beta = 0), so that the first pitot and
//      sideslip updates do not have to pull yaw and wind apart from a zero wind.
//   4. Then each IMU sample propagates the filter; each other sensor sample is an update. Each
//      pitot sample also brings the aircraft-model updates (measurements.hpp): the side force
//      (body y) and the normal force (body z, the lift) from the accelerometer averaged since
//      the previous one, which measure the air velocity across the airframe.
// NaN/Inf or out-of-range samples are rejected and counted, never used. Each sample is fused at
// its time of validity (stamp - delay; GNSS: the receiver's epoch, time_of_validity) with the
// state history (history.hpp), so a fix 120 ms late corrects the state of its instant.
// Geometry: the GNSS models include the antenna lever arm; IMU samples are rotated by the mount
// and moved to the CG (imu_position). A sensor that was heard from and falls silent longer than
// its time-out raises a sensor_timeout event (sensor_recovered when it comes back); time-outs
// run on the caller's clock (check_timeouts), so a silent IMU is noticed within imu timeout.
// status(): invalid before initialisation, while the IMU is silent, or when the covariance says
// the tilt or position is lost; degraded (with the sensors' bits) when a sensor timed out or the
// GNSS position keeps being rejected. An IMU silent longer than imu_reinit_gap loses the attitude:
// the filter re-initialises in flight (origin and barometer calibration kept).
// Robust gating: after inflate_after consecutive rejections of the GNSS position (barometer) the
// position (barometer-bias) variance is inflated by NIS / gate and the sample fused again; GNSS
// positions still rejected for gnss_reset_time reset position and velocity, at most once per
// reset_min_interval unless the innovation exceeds gnss_fault_distance. After a GNSS time-out
// (dead reckoning on IMU, airspeed and wind) the filter takes the returning GNSS at once, but
// the published position blends the correction in: the jump goes into an output offset that
// decays with time constant gnss_recovery_time (the filter stays optimal, the controllers see
// no step).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tern/estimator_ekf/filter.hpp"
#include "tern/estimator_ekf/history.hpp"
#include "tern/estimator_ekf/measurements.hpp"
#include "tern/estimator_ekf/yaw_gsf.hpp"
#include "tern/geodesy.hpp"
#include "tern/magnetic_model.hpp"
#include "tern/msg/estimator.hpp"
#include "tern/msg/sensors.hpp"
#include "tern/msg/state.hpp"
#include "tern/math.hpp"

namespace tern::ekf {

enum class Sensor : std::uint8_t { imu = 0, gnss, baro, diff_pressure, mag };
inline constexpr int kSensorCount = 5;
const char* sensor_name(Sensor s);

/// Every figure of the estimator. Defaults: datasheets (ICM-20602, u-blox M8N, MS5611,
/// MS4525DO) and PX4 EKF2's defaults for the IMU noise in flight (filter.hpp), ROSplane 2.0's
/// estimator.yaml where a figure maps; the GNSS error's size comes from the receiver's reported
/// accuracy (use_gnss_accuracy). Sensor rates IMU 400 Hz, mag 50 Hz, baro 100 Hz, pitot
/// 100 Hz, GNSS 10 Hz.
struct EstimatorConfig {
  double gravity = kGravity;  ///< m/s^2
  double rho = 1.225;         ///< air density for the pitot, kg/m^3
  ProcessNoise process;       ///< IMU noise and random walks (filter.hpp)

  // geometry, measured on the aircraft (body FRD)
  Vec3 gnss_antenna = Vec3::Zero();  ///< GNSS antenna position from the CG, m
  Vec3 imu_position = Vec3::Zero();  ///< IMU position from the CG, m (accel compensated for
                                     ///< omega_dot x r + omega x (omega x r))
  Vec3 imu_mount = Vec3::Zero();     ///< IMU axes relative to the body axes: roll, pitch, yaw
                                     ///< (3-2-1), rad; v_body = R(imu_mount) v_imu
  /// How well imu_mount is known, 1 sigma per body axis, rad: a board mounted by hand against a
  /// square sits within about 1 deg on each axis; 0 for an installation measured better. No
  /// measurement in flight reveals it (the filter estimates the IMU's attitude), so it is added
  /// to the published attitude covariance (State.P_diag), not to the filter's; with
  /// accel_level_calibrated, roll and pitch go into the accelerometer offset's prior instead.
  Vec3 imu_mount_sigma = Vec3::Constant(0.0175);
  /// The FCU's accelerometer was calibrated level (ROSflight's calibrate_accel, sensors.cpp, as
  /// `tern fcu calibrate imu` asks: the aircraft level and still): the stored offset makes that
  /// reading (0, 0, -g), so the board's mounting tilt mu went into the offset. In flight the
  /// accelerometer then reads like a level-mounted one with an offset [mu]x (0, 0, -g) on x and y;
  /// only loads other than 1 g (turns, pull-ups) show it in the filter's b_a. The body's attitude
  /// is the filter's (the board's) turned back by that tilt: q (x) Exp(-mu),
  /// mu = (b_a,y / g, -b_a,x / g, 0) (body_attitude()), as uncertain as the filter's
  /// (dtheta - dmu) plus the floor's level (level_sigma). false: b_a is the sensor's own offset
  /// (an FCU calibrated on a tilted floor or not at all), the mount widens the attitude.
  bool accel_level_calibrated = true;
  /// How level the floor was for that calibration, 1 sigma, rad: a spirit level's +-0.3 deg taken
  /// as uniform (tolerance / sqrt(3) = 0.17 deg, as the IMU's tolerances in init_gyro_scale_sigma).
  double level_sigma = 0.0030;

  // GNSS
  int min_fix_type = 3;           ///< minimum fix type used (3: 3-D fix)
  double gnss_pos_sigma_h = 0.1;  ///< white part of the GNSS position noise, m (without a reported accuracy: at least gnss_accuracy_floor)
  double gnss_pos_sigma_v = 0.2;  ///< m
  /// GNSS velocity noise per fix, m/s. Not the datasheet's 0.05 m/s: a receiver's velocity comes
  /// out of its own navigation filter, so its errors are correlated over seconds, and ten fixes a
  /// second fused as independent made the filter 2x overconfident (velocity NEES 3.7 per
  /// dimension). 0.3 m/s is PX4 EKF2's EKF2_GPS_V_NOISE and ArduPilot EKF3's EK3_VELNE_M_NSE.
  double gnss_vel_sigma_h = 0.3;
  double gnss_vel_sigma_v = 0.3;  ///< m/s, as gnss_vel_sigma_h
  /// The receiver's reported accuracies: h_acc and v_acc set the steady sigma of the GNSS error
  /// state (not below gnss_accuracy_floor; without them gnss_error_walk_* hold), s_acc the
  /// velocity noise where larger than gnss_vel_sigma_*.
  bool use_gnss_accuracy = true;
  /// The least steady GNSS error (m, 1 sigma) a reported accuracy is taken for: PX4 EKF2's
  /// EKF2_GPS_P_NOISE, 0.5 m, the lower limit it puts on a receiver's reported accuracy. A fix
  /// without a reported accuracy has at least this white noise (gnss_pos_sigma_* are a reporting
  /// receiver's fix-to-fix noise), as PX4 and ArduPilot EKF3 (EK3_POSNE_M_NSE, 0.5 m) take it.
  /// Replaying the ALFA flight (its receiver reports none): 92 % of the positions accepted at a
  /// mean NIS of 4.9 with 0.1/0.2 m, 100 % at 0.8 with the floor (roll and pitch against
  /// ArduPlane's own estimate 3.36/2.72 -> 3.39/2.81 deg RMS). A simulated receiver reports.
  double gnss_accuracy_floor = 0.5;
  /// GNSS noise grows with manoeuvring: a receiver's own filter lags the aircraft's acceleration.
  /// For a receiver that does not report its accuracy (h_acc, s_acc 0), each fix's velocity
  /// (position) noise is root-sum-square of the figure above and this times the
  /// low-passed magnitude of the NED acceleration (m/s per m/s^2; m per m/s^2): ArduPilot EKF3's
  /// gpsNEVelVarAccScale / gpsPosVarAccScale (0.05), as InertialNav's velErr/posErr (0.2 |a|). A
  /// reported accuracy already grows with the receiver's dynamics and is used as it is. Replaying
  /// the PX4 Zurich 2014 flight (no accuracies, 5 Hz, hand launch, turns of 1-4 g) without it
  /// accepted 77 % of the positions (93 % with it horizontally, at a mean NIS of 6.8; vertically
  /// too: mean NIS 5.8).
  double gnss_vel_accel_scale = 0.05;
  double gnss_pos_accel_scale = 0.05;
  double gnss_pos_gate = kChi2_999[3];
  double gnss_vel_gate = kChi2_999[3];
  /// Fuse the GNSS's down velocity. false: the receiver (or the log) has none (a sensor log's
  /// metadata sets it, docs/sensor-log.md): the north and east rows are fused (GnssVelocityNE,
  /// 2 dof, gate gnss_vel_gate scaled by the 2- over the 3-dof quantile) and the fix's vel_d is
  /// not used anywhere (resets and initialisation take the estimate's, or 0).
  bool use_gnss_vel_d = true;
  double gnss_reset_time = 5.0;     ///< s of continuous position rejection before a reset
  double gnss_recovery_time = 2.0;  ///< s: after a GNSS time-out, the position correction
                                    ///< reaches the output with this time constant
  // magnetometer: the Earth's field where the aircraft flies
  /// true: the World Magnetic Model's field (tern/magnetic_model.hpp) at the GNSS origin on
  /// mag_model_date, as PX4 and ArduPilot look it up; false: the fixed mag_declination,
  /// mag_inclination and mag_field_strength below (the plugin sets false when the mission sets any
  /// of those three explicitly: they are overrides).
  bool mag_field_from_model = true;
  /// Decimal year of the flight for the model (a replayed log's sensor_log.yaml `date` sets it;
  /// default 2025.4959 = 2025-07-01, sim_aero's default world date, so that the simulated world
  /// and the vehicle agree unless told otherwise; a receiver's UTC would be better, the sensor
  /// messages do not carry it).
  double mag_model_date = 2025.4958904109589;
  double mag_declination = 0.1857972802;   ///< rad, the override (Provo, UT: ROSflight's sim)
  double mag_inclination = 1.139436457;    ///< rad, the override
  double mag_field_strength = 5.07163e-5;  ///< T, the override
  /// T per axis, 1 sigma: PX4 EKF2's EKF2_MAG_NOISE (0.05 gauss). Not the sensor's white noise
  /// (HMC5883L: 0.2 uT) but what a 50-Hz stream cannot average out: local disturbances and the
  /// soft iron's heading-dependent error; the offset (residual hard iron, motor field) is a state,
  /// b_m. As a heading, sigma / (B cos I) = 5 uT / 21 uT = 0.24 rad at ROSflight's field.
  /// History (bench_estimation, realistic, 10 seeds, worst seed): as a heading, 3 uT against 7 uT
  /// gave yaw 1.09 against 1.35 deg (hourglass); as a 3-axis direction throughout, 5 uT against
  /// 3 uT gave a 30-s GNSS outage's drift (150-180 s) 26/24 against 32/30 m (hourglass/aggressive).
  double mag_sigma = 5e-6;
  double mag_gate = kChi2_999[3];          ///< 3-axis mode (3 dof)
  double mag_heading_gate = kChi2_999[1];  ///< heading mode (1 dof)
  /// Tilt-compensated heading always (true), or the field's 3-axis direction in the air and the
  /// heading on the ground (false: PX4 EKF2's automatic EKF2_MAG_TYPE; airborne()). The heading
  /// takes the estimated tilt as known: in a 45-deg bank a roll error of 0.7 deg is 1.5 deg of
  /// heading at an inclination of 65 deg, and in a GNSS outage the heading fusion turned that into
  /// 2.4 deg of yaw error and 29 m of drift (hourglass seed 8; the direction: 1.9 deg, 15 m). The
  /// direction also references roll and pitch to the field: worst roll and pitch 0.52/0.55 ->
  /// 0.51/0.48 deg (hourglass), 0.57/0.54 -> 0.52/0.48 (aggressive; 10 seeds).
  bool mag_heading_only = false;
  /// s: in the air, GNSS velocity rejected this long: velocity and position are reset to the fix;
  /// if the yaw is also further than gnss_yaw_sigma from the GNSS course, it is the likely cause
  /// (a magnetometer disturbed or miscalibrated, a hand launch turned the wrong way): yaw is reset
  /// to the course and the magnetometer is no longer fused that flight (PX4 EKF2's emergency yaw
  /// reset and mag_fault, after its EKF-GSF; here the course itself, the wind's crab angle within
  /// gnss_yaw_sigma). 0: never.
  double gnss_yaw_reset_time = 1.0;
  /// rad: the yaw uncertainty after such a reset from the course (the GSF not converged): the
  /// crab angle a wind of 5 m/s gives at 14 m/s; also the least yaw difference that counts.
  double gnss_yaw_sigma = 0.35;
  /// rad: the yaw GSF (yaw_gsf.hpp: IMU and GNSS velocity alone, PX4 EKF2's EKF-GSF) counts as
  /// converged below this 1 sigma; its yaw then replaces the course in the resets above. 0 (the
  /// default): the GSF does not run. Off by default: on a simulated aggressive flight (60-deg
  /// banks, turbulence, the realistic IMU) its converged yaw erred 11 deg RMS (24 deg at worst)
  /// while claiming 1-2 deg; a compass the filter follows wrongly is its use (gsf_disagree_time).
  double gsf_max_sigma = 0.0;
  /// s: in the air, the filter's yaw further than 3 sigma (at least gnss_yaw_sigma) from the
  /// converged GSF's this long is reset to it and the magnetometer is no longer fused (a compass
  /// the filter followed while the wind state absorbed the velocity: a compass turned 92 deg left
  /// yaw 38 deg and wind 11 m/s wrong with the GNSS velocity accepted). 0 (the default): never.
  /// Needs gsf_max_sigma. Off by default: in bench_estimation's aggressive mission (50-deg banks,
  /// turbulence) the GSF disagreed with a right yaw by 20-44 deg for 5 s on 4 of 20 flights.
  double gsf_disagree_time = 0.0;
  double mag_init_wait = 2.0;      ///< s to wait for a magnetometer at initialisation
  double mag_reset_time = 2.0;     ///< s of continuous heading rejection after which yaw is
                                   ///< reset to the magnetometer (and the wind re-derived)...
  double mag_reset_window = 30.0;  ///< ...if that happens within this long after initialising
                                   ///< (a filter started while manoeuvring can lock onto a
                                   ///< wrong yaw; later, a converged filter rejecting the
                                   ///< magnetometer more likely sees a disturbed field)
  // barometer
  double baro_sigma = 4.0;  ///< Pa
  double baro_gate = kChi2_999[1];
  int baro_calibration_count = 100;  ///< samples averaged for the ground calibration
  // pitot and sideslip
  double diff_pressure_sigma = 1.15;  ///< Pa
  double airspeed_gust_sigma = 1.0;   ///< m/s, gusts the wind state does not follow (pitot: along
                                      ///< body x; side force: across, its C_Y_beta sideslip)
  double diff_pressure_gate = kChi2_999[1];
  double min_airspeed = 8.0;  ///< m/s, below it neither pitot nor sideslip update
  bool use_sideslip = true;
  double sideslip_sigma = 2.0;  ///< m/s: turbulence makes v_r wander for seconds; a
                                ///< tighter figure at 100 Hz over-trusts it
  double sideslip_gate = kChi2_999[1];
  // side force (SideForce): replaces the zero-sideslip pseudo-measurement when use_side_force
  // and the aircraft's wing area, mass and C_Y_beta are known (the plugin reads them from the
  // mission's aircraft file)
  bool use_side_force = true;
  double wing_S = 0.0;                                                       ///< m^2 (0: unknown, side force off)
  double mass = 0.0;                                                         ///< kg (0: unknown, side force off)
  double C_Y_0 = 0.0, C_Y_beta = 0.0, C_Y_delta_a = 0.0, C_Y_delta_r = 0.0;  ///< per rad
  bool side_force_active() const { return use_side_force && wing_S > 0.0 && mass > 0.0 && C_Y_beta != 0.0; }
  double side_force_sigma = 0.3;  ///< m/s^2
  // normal force (NormalForce): the lift model measures the air's velocity along body z, when
  // use_normal_force and the aircraft's chord and C_L_alpha are known (from its file)
  bool use_normal_force = true;
  double wing_c = 0.0;                                                  ///< m, mean chord
  double C_L_0 = 0.0, C_L_alpha = 0.0, C_L_q = 0.0, C_L_delta_e = 0.0;  ///< per rad
  bool normal_force_active() const { return use_normal_force && wing_S > 0.0 && mass > 0.0 && C_L_alpha != 0.0; }
  /// m/s^2: the body-z accelerometer averaged between pitot samples (4 at 400/100 Hz) with the
  /// propeller's vibration (about 1.5 m/s^2 per sample at full throttle), plus the lift model's
  /// error (the drag's share, the stall's curvature)
  double normal_force_sigma = 1.0;
  /// rad: the side force and zero-sideslip models wait until roll and pitch are known to this, 1
  /// sigma (an initialisation in flight starts at 0.4; the GNSS velocity brings them under
  /// 0.1 within a second).
  double lateral_max_tilt_sigma = 0.1;
  double side_force_gate = kChi2_999[1];
  // initialisation
  int init_min_imu_samples = 40;
  /// rad/s: at initialisation the aircraft counts as at rest (gyro bias from the averaged rate, tight
  /// tilt) only if its mean rate and the rate's RMS deviation over the last second are both below
  /// this: above any MEMS gyro's turn-on bias (ICM-20602: +-1 deg/s) and its noise, below the slow
  /// turns of an aircraft held by hand before a hand launch. The PX4 Zurich 2014 flight, held and
  /// turned for 15 s before its launch, passed the former test (0.5 rad/s) and started with its
  /// hand's rate as gyro bias.
  double rest_rate_max = 0.05;
  double init_average_time = 0.25;     ///< s, time constant of the pre-init averages
  double init_tilt_sigma = 0.0707;     ///< rad (ROSplane phi/theta_initial_cov 0.005)
  double init_yaw_sigma = 0.2;         ///< rad, with a magnetometer (1 rad without)
  double init_gyro_bias_sigma = 0.01;  ///< rad/s (ROSplane bias_initial_cov 1e-4)
  /// m/s^2: what the FCU's level calibration (ROSflight calibrate_accel) leaves: the floor's
  /// level (a spirit level, 0.3 deg: 0.05 m/s^2) and the offset's temperature drift since (ICM-20602
  /// 0.5 mg/K on x and y over 10 K: 0.05 m/s^2), root-sum-square. 0.3 (the uncalibrated +-25 mg)
  /// let the side-force model's errors move the y bias, which in level flight is roll (1 deg per
  /// 0.17 m/s^2): bench_estimation's worst roll 1.2 deg.
  double init_accel_bias_sigma = 0.07;
  /// Gyro sensitivity error S_g at initialisation, 1 sigma: the ICM-20602's +-1 % sensitivity and
  /// +-2 % cross-axis tolerances (DS-000176, table 1) taken as uniform (tolerance / sqrt(3)).
  double init_gyro_scale_sigma = 0.0058;
  double init_gyro_cross_axis_sigma = 0.0115;
  /// Magnetometer offset b_m at initialisation, 1 sigma per axis, fraction of the field intensity:
  /// what a compass calibration leaves (1-2 uT of hard iron) and the motor current's field, 2 uT
  /// of ROSflight's 50.7 uT.
  double init_mag_bias_sigma = 0.04;
  /// Static-pressure error coefficient k_sp at initialisation, 1 sigma (fraction of the dynamic
  /// pressure): fuselage and pitot-static ports err by a few percent of it (Gracey, "Measurement
  /// of aircraft speed and altitude", NASA RP-1046, 1980); 0.05 is 0.7 m of altitude at 17 m/s.
  double init_static_error_sigma = 0.05;
  double init_wind_sigma = 5.0;          ///< m/s, without air data at initialisation
  double init_wind_sigma_airdata = 2.0;  ///< m/s, wind from GNSS velocity - pitot airspeed
  /// m: the barometer's offset from its calibration datum at initialisation, 1 sigma. The ground
  /// calibration averages baro_calibration_count samples (MS5611: 1.2 Pa = 0.1 m each, so 0.01 m
  /// over 100) against that datum, so the offset starts at centimetres plus the few centimetres
  /// between the baro and the GNSS antenna; what the datum itself is off by is the datum's
  /// variance (baro_datum_variance()), not this. 1 m let the filter take part of the GNSS
  /// altitude's wander for a baro offset it had not learnt yet (bench_estimation, realistic,
  /// 10 seeds, height above home median/worst: hourglass 0.46/1.31 -> 0.40/1.16 m, aggressive
  /// 0.55/1.17 -> 0.48/1.06; bench/altitude_oracle.py puts what the sensors allow near 1.4 m on
  /// the worst seed). What remains follows from b_baro's walk against the GNSS error's.
  double init_baro_bias_sigma = 0.1;
  double init_gnss_error_sigma = 0.5;  ///< m, GNSS position error at initialisation
  // sensor checks
  double accel_max = 160.0;  ///< m/s^2 per axis (16 g)
  double gyro_max = 35.0;    ///< rad/s per axis (2000 deg/s)
  double imu_max_dt = 0.05;  ///< s, longer IMU gaps are counted and clamped
  /// s: the covariance steps once per this long over the IMU samples since (filter.hpp; PX4
  /// EKF2's 10 ms filter period), the nominal state with every sample; 0: every sample.
  double covariance_period = 0.01;
  std::array<double, kSensorCount> timeout{0.02, 1.0, 0.5, 0.5, 0.5};  ///< s, per Sensor
  /// s, per Sensor: how long before its stamp a sample was valid (IMU: unused). The GNSS's
  /// time_of_validity, when the driver gives one, already says it: this is subtracted from it.
  std::array<double, kSensorCount> delay{0.0, 0.0, 0.0, 0.0, 0.0};
  // robust gating and health
  int inflate_after = 5;               ///< consecutive gate rejections of the GNSS position (or the
                                       ///< barometer) after which the variance of the position (the
                                       ///< barometer bias) is inflated
  double reset_min_interval = 60.0;    ///< s: at most one GNSS reset per this long...
  double gnss_fault_distance = 100.0;  ///< ...unless the innovation exceeds this, m (a lost position)
  double imu_reinit_gap = 0.5;         ///< s: after an IMU silence this long the attitude is lost:
                                       ///< re-initialise in flight (GNSS velocity and magnetometer)
  double max_position_sigma = 100.0;   ///< m: horizontal 1 sigma beyond which the state is invalid
  double max_tilt_sigma = 0.35;        ///< rad: roll/pitch 1 sigma beyond which the state is invalid

  /// Every figure above that a mission may set, as the plugin's parameters (declare_struct,
  /// tern/param_struct.hpp): name, unit, range, description; the member initialisers are the
  /// defaults (the plugin first takes rho, mass, wing_S and C_Y_* from the aircraft file).
  template <class V>
  static void describe(V& v) {
    describe_reals(v);
    describe_others(v);
  }
  template <class V>
  static void describe_reals(V& v) {
    using tern::ParamSpec;
    using C = EstimatorConfig;
    v(&C::gravity, "gravity", ParamSpec("m/s^2", 9.0, 10.5, "gravitational acceleration"));
    v(&C::rho, "rho", ParamSpec("kg/m^3", 0.3, 1.5, "air density for the differential pressure"));
    v(&C::process);  // ProcessNoise::describe (filter.hpp)
    v(&C::init_gnss_error_sigma, "init_gnss_error_sigma", ParamSpec("m", 1e-3, 100.0, "initial GNSS position-error uncertainty, 1 sigma"));
    v(&C::gnss_pos_sigma_h, "gnss_pos_noise_h", ParamSpec("m", 1e-3, 100.0, "white part of the GNSS horizontal position noise, 1 sigma"));
    v(&C::gnss_pos_sigma_v, "gnss_pos_noise_v", ParamSpec("m", 1e-3, 100.0, "white part of the GNSS altitude noise, 1 sigma"));
    v(&C::gnss_vel_sigma_h, "gnss_vel_noise_h", ParamSpec("m/s", 1e-4, 10.0, "GNSS horizontal velocity noise, 1 sigma"));
    v(&C::gnss_vel_sigma_v, "gnss_vel_noise_v", ParamSpec("m/s", 1e-4, 10.0, "GNSS vertical velocity noise, 1 sigma"));
    v(&C::gnss_vel_accel_scale, "gnss_vel_accel_scale",
      ParamSpec("s", 0.0, 1.0, "GNSS velocity noise added per m/s^2 of manoeuvring acceleration (root-sum-square)"));
    v(&C::gnss_pos_accel_scale, "gnss_pos_accel_scale",
      ParamSpec("s^2", 0.0, 1.0, "GNSS position noise added per m/s^2 of manoeuvring acceleration (root-sum-square)"));
    v(&C::gnss_pos_gate, "gnss_pos_gate", ParamSpec("", 0.0, 1e6, "chi-square gate of GNSS position (3 dof; 0: off)"));
    v(&C::gnss_vel_gate, "gnss_vel_gate", ParamSpec("", 0.0, 1e6, "chi-square gate of GNSS velocity (3 dof; 0: off)"));
    v(&C::use_gnss_vel_d, "use_gnss_vel_d",
      ParamSpec("", 0, 1, "fuse the GNSS down velocity (false: a receiver or log without one; north and east only)"));
    v(&C::gnss_reset_time, "gnss_reset_time",
      ParamSpec("s", 0.5, 600.0, "continuous GNSS position rejection after which the state is reset to GNSS"));
    v(&C::gnss_recovery_time, "gnss_recovery_time",
      ParamSpec("s", 0.0, 60.0, "after a GNSS time-out, the published position takes the correction with this time constant (0: at once)"));
    v(&C::mag_model_date, "mag_model_date",
      ParamSpec("year", 1900.0, 2100.0, "decimal year of the flight for the World Magnetic Model (2025.5: mid 2025)"));
    v(&C::mag_declination, "mag_declination",
      ParamSpec("rad", -tern::kPi, tern::kPi, "override: magnetic declination, east of true north (setting it turns the model off)"));
    v(&C::mag_inclination, "mag_inclination",
      ParamSpec("rad", -tern::kPi / 2, tern::kPi / 2, "override: magnetic inclination, down from horizontal (turns the model off)"));
    v(&C::mag_field_strength, "mag_field_strength",
      ParamSpec("T", 1e-6, 1e-3, "override: total magnetic field intensity (turns the model off)"));
    v(&C::mag_sigma, "mag_noise", ParamSpec("T", 1e-9, 1e-4, "magnetometer noise per axis, 1 sigma"));
    v(&C::mag_gate, "mag_gate", ParamSpec("", 0.0, 1e6, "chi-square gate of the 3-axis magnetometer update (3 dof; 0: off)"));
    v(&C::mag_heading_gate, "mag_heading_gate", ParamSpec("", 0.0, 1e6, "chi-square gate of the magnetic heading update (1 dof; 0: off)"));
    v(&C::gnss_yaw_reset_time, "gnss_yaw_reset_time",
      ParamSpec("s", 0.0, 60.0,
                "in the air, GNSS velocity rejected this long resets yaw to the GNSS course and stops the magnetometer (0: never)"));
    v(&C::gnss_yaw_sigma, "gnss_yaw_sigma", ParamSpec("rad", 0.01, 3.2, "yaw uncertainty after a yaw reset to the GNSS course, 1 sigma"));
    v(&C::gsf_max_sigma, "gsf_max_sigma",
      ParamSpec("rad", 0.0, 1.0, "the yaw GSF (IMU and GNSS velocity alone) counts as converged below this 1 sigma (0: it does not run)"));
    v(&C::gsf_disagree_time, "gsf_disagree_time",
      ParamSpec(
          "s", 0.0, 600.0,
          "in the air, the filter's yaw disagreeing with the converged yaw GSF this long resets it and stops the magnetometer (0: never)"));
    v(&C::mag_init_wait, "mag_init_wait",
      ParamSpec("s", 0.0, 60.0, "time to wait for a magnetometer sample after the origin is set before initialising without"));
    v(&C::mag_reset_time, "mag_reset_time",
      ParamSpec("s", 0.1, 600.0, "continuous magnetic-heading rejection after which yaw is reset to the magnetometer"));
    v(&C::mag_reset_window, "mag_reset_window",
      ParamSpec("s", 0.0, 1e6, "yaw resets to the magnetometer only within this long after initialisation (0: never)"));
    v(&C::baro_sigma, "baro_noise", ParamSpec("Pa", 1e-3, 1000.0, "static-pressure noise, 1 sigma"));
    v(&C::baro_gate, "baro_gate", ParamSpec("", 0.0, 1e6, "chi-square gate of the barometric altitude (1 dof; 0: off)"));
    v(&C::diff_pressure_sigma, "diff_pressure_noise", ParamSpec("Pa", 1e-3, 100.0, "differential-pressure noise, 1 sigma"));
    v(&C::airspeed_gust_sigma, "airspeed_gust_sigma",
      ParamSpec("m/s", 0.0, 20.0, "turbulence the wind state does not follow: pitot airspeed noise, and the side force's sideslip"));
    v(&C::diff_pressure_gate, "diff_pressure_gate",
      ParamSpec("", 0.0, 1e6, "chi-square gate of the differential pressure (1 dof; 0: off)"));
    v(&C::min_airspeed, "min_airspeed",
      ParamSpec("m/s", 0.0, 100.0, "airspeed below which the pitot and zero-sideslip updates are skipped"));
    v(&C::sideslip_sigma, "sideslip_noise", ParamSpec("m/s", 1e-3, 100.0, "zero-sideslip pseudo-measurement noise (body-y air velocity)"));
    v(&C::sideslip_gate, "sideslip_gate", ParamSpec("", 0.0, 1e6, "chi-square gate of the zero-sideslip update (1 dof; 0: off)"));
    v(&C::side_force_sigma, "side_force_noise",
      ParamSpec("m/s^2", 1e-3, 100.0,
                "side-force update noise: body-y accelerometer (averaged between pitot samples) against the aircraft's C_Y model"));
    v(&C::side_force_gate, "side_force_gate", ParamSpec("", 0.0, 1e6, "chi-square gate of the side-force update (1 dof; 0: off)"));
    v(&C::wing_S, "wing_S",
      ParamSpec("m^2", 0.0, 100.0, "wing area for the side-force model (default: the aircraft file's; 0: side force off)"));
    v(&C::mass, "mass", ParamSpec("kg", 0.0, 1000.0, "aircraft mass for the side-force model (default: the aircraft file's; 0: off)"));
    v(&C::C_Y_0, "C_Y_0", ParamSpec("", -10.0, 10.0, "side-force coefficient at zero sideslip (default: the aircraft file's)"));
    v(&C::C_Y_beta, "C_Y_beta",
      ParamSpec("1/rad", -20.0, 20.0, "side-force derivative in sideslip (default: the aircraft file's; 0: off)"));
    v(&C::C_Y_delta_a, "C_Y_delta_a", ParamSpec("1/rad", -10.0, 10.0, "side force per aileron deflection (default: the aircraft file's)"));
    v(&C::C_Y_delta_r, "C_Y_delta_r", ParamSpec("1/rad", -10.0, 10.0, "side force per rudder deflection (default: the aircraft file's)"));
    v(&C::use_normal_force, "use_normal_force",
      ParamSpec("", 0, 1, "apply the normal-force (lift) model: the body-z accelerometer against the aircraft's C_L"));
    v(&C::normal_force_sigma, "normal_force_noise",
      ParamSpec("m/s^2", 1e-3, 100.0,
                "normal-force update noise: body-z accelerometer (averaged between pitot samples) against the C_L model"));
    v(&C::wing_c, "wing_c", ParamSpec("m", 0.0, 100.0, "mean chord for the normal-force model (default: the aircraft file's)"));
    v(&C::C_L_0, "C_L_0", ParamSpec("", -10.0, 10.0, "lift coefficient at zero angle of attack (default: the aircraft file's)"));
    v(&C::C_L_alpha, "C_L_alpha", ParamSpec("1/rad", -50.0, 50.0, "lift-curve slope (default: the aircraft file's; 0: normal force off)"));
    v(&C::C_L_q, "C_L_q", ParamSpec("1/rad", -100.0, 100.0, "lift per normalised pitch rate (default: the aircraft file's)"));
    v(&C::C_L_delta_e, "C_L_delta_e", ParamSpec("1/rad", -10.0, 10.0, "lift per elevator deflection (default: the aircraft file's)"));
    v(&C::rest_rate_max, "rest_rate_max",
      ParamSpec("rad/s", 1e-4, 1.0,
                "at initialisation: mean rate and its RMS deviation over the last second below this count as at rest "
                "(gyro bias from the average); a hand-held aircraft is not"));
    v(&C::init_average_time, "init_average_time",
      ParamSpec("s", 0.0, 10.0, "time constant of the accel/gyro averages before initialisation"));
    v(&C::init_tilt_sigma, "init_tilt_sigma", ParamSpec("rad", 1e-4, 3.0, "initial roll/pitch uncertainty, 1 sigma"));
    v(&C::init_yaw_sigma, "init_yaw_sigma", ParamSpec("rad", 1e-4, 3.2, "initial yaw uncertainty with a magnetometer, 1 sigma"));
    v(&C::init_gyro_bias_sigma, "init_gyro_bias_sigma", ParamSpec("rad/s", 1e-6, 1.0, "initial gyro-bias uncertainty, 1 sigma"));
    v(&C::init_accel_bias_sigma, "init_accel_bias_sigma",
      ParamSpec("m/s^2", 1e-6, 10.0, "initial accelerometer-bias uncertainty, 1 sigma"));
    v(&C::init_gyro_scale_sigma, "init_gyro_scale_sigma",
      ParamSpec("", 1e-6, 0.5, "initial gyro scale-factor uncertainty (sensitivity error), 1 sigma"));
    v(&C::init_gyro_cross_axis_sigma, "init_gyro_cross_axis_sigma",
      ParamSpec("", 1e-6, 0.5, "initial gyro cross-axis sensitivity uncertainty, 1 sigma"));
    v(&C::init_mag_bias_sigma, "init_mag_bias_sigma",
      ParamSpec("", 1e-6, 1.0, "initial magnetometer-offset uncertainty per axis, fraction of the field intensity, 1 sigma"));
    v(&C::init_static_error_sigma, "init_static_error_sigma",
      ParamSpec("", 1e-6, 1.0, "initial static-pressure error coefficient uncertainty, fraction of the dynamic pressure, 1 sigma"));
    v(&C::init_wind_sigma_airdata, "init_wind_sigma_airdata",
      ParamSpec("m/s", 1e-3, 50.0, "initial wind uncertainty when initialised in flight from GNSS velocity and pitot airspeed"));
    v(&C::init_wind_sigma, "init_wind_sigma", ParamSpec("m/s", 1e-3, 50.0, "initial wind uncertainty without air data, 1 sigma"));
    v(&C::init_baro_bias_sigma, "init_baro_bias_sigma", ParamSpec("m", 1e-3, 1000.0, "initial barometer-bias uncertainty, 1 sigma"));
    v(&C::accel_max, "accel_max", ParamSpec("m/s^2", 1.0, 2000.0, "accelerometer samples beyond this (any axis) are rejected"));
    v(&C::gyro_max, "gyro_max", ParamSpec("rad/s", 0.1, 100.0, "gyro samples beyond this (any axis) are rejected"));
    v(&C::covariance_period, "covariance_period",
      ParamSpec("s", 0.0, 0.1, "covariance propagation period over the IMU samples (0: every sample; PX4 EKF2: 10 ms)"));
    v(&C::imu_max_dt, "imu_max_dt", ParamSpec("s", 1e-4, 1.0, "longest IMU interval propagated in one step (longer gaps are clamped)"));
    v([](C& c) -> double& { return c.timeout[0]; }, "imu_timeout", ParamSpec("s", 1e-3, 60.0, "IMU silence reported as a time-out"));
    v([](C& c) -> double& { return c.timeout[1]; }, "gnss_timeout",
      ParamSpec("s", 1e-3, 60.0, "GNSS silence (or no fix) reported as a time-out"));
    v([](C& c) -> double& { return c.timeout[2]; }, "baro_timeout", ParamSpec("s", 1e-3, 60.0, "barometer silence reported as a time-out"));
    v([](C& c) -> double& { return c.timeout[3]; }, "diff_pressure_timeout",
      ParamSpec("s", 1e-3, 60.0, "differential-pressure silence reported as a time-out"));
    v([](C& c) -> double& { return c.timeout[4]; }, "mag_timeout",
      ParamSpec("s", 1e-3, 60.0, "magnetometer silence reported as a time-out"));
    v([](C& c) -> double& { return c.delay[1]; }, "gnss_delay",
      ParamSpec("s", 0.0, 0.5,
                "GNSS delay subtracted from each fix's time of validity (0 when the driver gives the receiver's epoch, as "
                "sim_aero does; over ROSflight's link the receiver's output latency, ~0.1 s for a u-blox M8N at 10 Hz)"));
    v([](C& c) -> double& { return c.delay[2]; }, "baro_delay",
      ParamSpec("s", 0.0, 0.5, "barometer sample delay (its filter's group delay)"));
    v([](C& c) -> double& { return c.delay[3]; }, "diff_pressure_delay",
      ParamSpec("s", 0.0, 0.5, "differential-pressure sample delay (tubing and filter)"));
    v([](C& c) -> double& { return c.delay[4]; }, "mag_delay", ParamSpec("s", 0.0, 0.5, "magnetometer sample delay"));
    v(&C::reset_min_interval, "reset_min_interval",
      ParamSpec("s", 0.0, 3600.0, "at most one GNSS reset per this long (covariance inflation carries the rest)"));
    v(&C::gnss_fault_distance, "gnss_fault_distance",
      ParamSpec("m", 1.0, 1e6, "a GNSS innovation beyond this resets the position regardless of reset_min_interval"));
    v(&C::imu_reinit_gap, "imu_reinit_gap",
      ParamSpec("s", 0.05, 60.0, "IMU silence after which the attitude counts as lost and the filter re-initialises in flight"));
    v(&C::max_position_sigma, "max_position_sigma",
      ParamSpec("m", 1.0, 1e6, "horizontal position 1 sigma beyond which the state is invalid"));
    v(&C::max_tilt_sigma, "max_tilt_sigma", ParamSpec("rad", 0.01, 3.2, "roll/pitch 1 sigma beyond which the state is invalid"));
  }
  template <class V>
  static void describe_others(V& v) {
    using tern::ParamSpec;
    using C = EstimatorConfig;
    v(&C::min_fix_type, "min_gnss_fix_type", ParamSpec("", 2, 3, "minimum GNSS fix type used (2: 2-D, 3: 3-D)"));
    v(&C::baro_calibration_count, "baro_calibration_count",
      ParamSpec("", 1, 100000, "barometer samples averaged for the ground calibration"));
    v(&C::init_min_imu_samples, "init_min_imu_samples", ParamSpec("", 1, 100000, "IMU samples averaged before initialisation"));
    v(&C::inflate_after, "inflate_after",
      ParamSpec("", 1, 1000,
                "consecutive GNSS or baro rejections after which the covariance of the states "
                "they measure is inflated (instead of a reset)"));
    v(&C::gnss_antenna, "gnss_antenna_position",
      ParamSpec("m", -10.0, 10.0, "GNSS antenna position from the CG, body FRD (x forward, y right, z down), measured on the aircraft"));
    v(&C::imu_position, "imu_position", ParamSpec("m", -10.0, 10.0, "IMU position from the CG, body FRD, measured on the aircraft"));
    v(&C::imu_mount, "imu_mount",
      ParamSpec("rad", -tern::kPi, tern::kPi, "IMU axes relative to the body axes: roll, pitch, yaw (3-2-1); v_body = R(imu_mount) v_imu"));
    v(&C::imu_mount_sigma, "imu_mount_sigma",
      ParamSpec("rad", -1.0, 1.0, "uncertainty of imu_mount per body axis, 1 sigma: added to the published attitude covariance"));
    v(&C::accel_level_calibrated, "accel_level_calibrated",
      ParamSpec("", 0, 1,
                "the FCU's accelerometer was calibrated level: its offset holds the board's tilt, the body's attitude is corrected by it"));
    v(&C::level_sigma, "level_sigma", ParamSpec("rad", 0.0, 0.2, "how level the floor was for the accelerometer's calibration, 1 sigma"));
    v(&C::lateral_max_tilt_sigma, "lateral_max_tilt_sigma",
      ParamSpec("rad", 1e-3, 3.2, "the side force and zero-sideslip models wait until roll and pitch are known to this, 1 sigma"));
    v(&C::mag_field_from_model, "mag_field_from_model",
      ParamSpec("", 0, 1,
                "the Earth's field from the World Magnetic Model at the GNSS origin on mag_model_date (false: the fixed "
                "mag_declination/inclination/field_strength)"));
    v(&C::mag_heading_only, "mag_heading_only",
      ParamSpec("", 0, 1, "magnetometer as tilt-compensated heading always (true) or as 3-axis direction in the air (false)"));
    v(&C::use_gnss_accuracy, "use_gnss_accuracy",
      ParamSpec("", 0, 1,
                "use the receiver's reported h_acc/v_acc (steady sigma of the GNSS error, at least gnss_accuracy_floor) "
                "and s_acc (velocity noise, where larger than gnss_vel_noise_*)"));
    v(&C::gnss_accuracy_floor, "gnss_accuracy_floor",
      ParamSpec("m", 0.01, 100.0,
                "the least steady GNSS position error a reported accuracy is taken for, and the least white noise of a fix "
                "without one, 1 sigma"));
    v(&C::use_sideslip, "use_sideslip",
      ParamSpec("", 0, 1, "apply the zero-sideslip pseudo-measurement (when the side-force model is off)"));
    v(&C::use_side_force, "use_side_force",
      ParamSpec("", 0, 1,
                "measure sideslip from the body-y accelerometer and the aircraft's C_Y model "
                "(needs wing_S, mass, C_Y_beta; else zero-sideslip)"));
  }
};

/// Counters of one sensor.
struct SensorCounters {
  std::uint64_t received = 0;  ///< messages offered
  std::uint64_t invalid = 0;   ///< NaN/Inf, out of range or stamp going backwards
  std::uint64_t timeouts = 0;  ///< times it fell silent longer than its time-out
  bool timed_out = false;
  Nanos last_stamp = -1;  ///< stamp of the last valid message (-1: none yet)
};

enum class EventKind : std::uint8_t {
  origin_set,
  initialized,
  baro_calibrated,
  sensor_timeout,
  sensor_recovered,
  gnss_reset,
  imu_gap,
  filter_reset,
  first_invalid,
  mag_reset,
  inflated,
  imu_lost,
  too_old,
  gnss_yaw_reset,
  gnss_velocity_reset,
  gsf_yaw_reset
};

/// Something worth a log line. `value`: the gap for imu_gap and imu_lost, the innovation norm
/// for gnss_reset, the variance factor for inflated, the age (s) for too_old.
struct Event {
  Nanos stamp = 0;
  EventKind kind = EventKind::initialized;
  Sensor sensor = Sensor::imu;
  double value = 0.0;
};
/// One line describing the event, e.g. "gnss: no valid message for 1.2 s (time-out 1 s)".
std::string describe(const Event& e);

class Estimator {
 public:
  explicit Estimator(const EstimatorConfig& config = {});

  /// New figures (keeps the state; noise and gates apply from the next sample).
  void set_config(const EstimatorConfig& config);
  const EstimatorConfig& config() const { return cfg_; }
  /// Whether to wait (up to mag_init_wait) for a magnetometer before initialising.
  void expect_mag(bool expected) { expect_mag_ = expected; }
  /// Whether a sensor is wired (default: every one): an expected sensor that never delivers a
  /// valid sample times out counted from the first check_timeouts() (the start), as one that
  /// stops does from its last sample.
  void expect(Sensor s, bool expected) { expected_[static_cast<int>(s)] = expected; }
  /// A new flight: the estimator as constructed with the current configuration and sensor
  /// wiring (expect(), expect_mag()): no origin, no calibration, counters and events cleared.
  /// Every member is per-flight state except those three, so the whole object is replaced.
  void reset();

  /// One IMU sample: propagates (after initialisation) to its stamp. Returns false if rejected.
  bool add_imu(const msg::Imu& m);
  bool add_gnss(const msg::Gnss& m);
  bool add_baro(const msg::Baro& m);
  bool add_diff_pressure(const msg::DiffPressure& m);
  bool add_mag(const msg::Mag& m);
  /// The current aileron, elevator and rudder deflections (rad), for the side- and normal-force models.
  void set_controls(double delta_a, double delta_e, double delta_r) {
    side_force_.delta_a = delta_a;
    side_force_.delta_r = delta_r;
    normal_force_.delta_e = delta_e;
  }
  /// Raises time-out events for sensors silent for longer than their time-out at `now`. Call it
  /// on a clock, not on IMU samples: a silent IMU is noticed only this way.
  void check_timeouts(Nanos now);
  /// Health of the estimate (health.cpp): invalid before initialisation, when the IMU timed out
  /// or the covariance says the tilt or position is lost; degraded when an expected sensor timed
  /// out or its measurements keep being rejected (bits: msg::sensor_bit).
  msg::StateStatus status(std::uint8_t* degraded_sensors = nullptr) const;
  /// The largest test ratio (NIS / gate) of each measurement since the last call.
  msg::Innovations take_innovations(Nanos stamp);

  bool initialized() const { return initialized_; }
  bool origin_valid() const { return origin_.has_value(); }
  /// The estimate as a message (valid = status() is ok or degraded). stamp: that of the last
  /// IMU sample.
  msg::State state() const;
  /// The same into an existing message (allocation free).
  void fill_state(msg::State& s) const;
  /// The body's attitude: the filter's, turned back by the board's tilt the level calibration
  /// put into the accelerometer offset (accel_level_calibrated; otherwise the filter's).
  Eigen::Quaterniond body_attitude() const;
  /// Variance of the published attitude error (body frame, rad^2): the filter's, with the tilt
  /// correction's and the level's or the mount's uncertainty.
  Vec3 body_attitude_variance() const;

  const Filter& filter() const { return filter_; }
  const SensorCounters& counters(Sensor s) const { return counters_[static_cast<int>(s)]; }
  const GnssPosition& gnss_position_model() const { return gnss_pos_; }
  const GnssVelocity& gnss_velocity_model() const { return gnss_vel_; }
  /// The counters of the GNSS velocity model in use (3-D, or north-east without use_gnss_vel_d).
  const UpdateStats& gnss_velocity_stats() const { return cfg_.use_gnss_vel_d ? gnss_vel_.stats : gnss_vel_ne_.stats; }
  UpdateStats& gnss_velocity_stats() { return cfg_.use_gnss_vel_d ? gnss_vel_.stats : gnss_vel_ne_.stats; }
  const Magnetometer& mag_model() const { return mag_; }
  const MagHeading& mag_heading_model() const { return mag_heading_; }
  const BaroAltitude& baro_model() const { return baro_; }
  /// Variance of the barometer's calibration datum (the altitude it was calibrated against), m^2.
  double baro_datum_variance() const { return baro_datum_var_; }
  const PitotAirspeed& diff_pressure_model() const { return pitot_; }
  const ZeroSideslip& sideslip_model() const { return sideslip_; }
  const SideForce& side_force_model() const { return side_force_; }
  const NormalForce& normal_force_model() const { return normal_force_; }
  std::uint64_t gnss_resets() const { return gnss_resets_; }
  std::uint64_t inflations() const { return inflations_; }
  std::uint64_t mag_resets() const { return mag_resets_; }
  /// The Earth's field the magnetometer is compared with: the model's at the origin once it is
  /// set (mag_field_from_model), else the configured one.
  const tern::MagneticField& earth_field() const { return field_; }
  /// Yaw resets to the GNSS course in flight (the magnetometer is then no longer fused).
  std::uint64_t gnss_yaw_resets() const { return gnss_yaw_resets_; }
  std::uint64_t filter_resets() const { return filter_resets_; }

  /// Events since the last call (the caller logs them).
  std::vector<Event> take_events();
  bool has_events() const { return !events_.empty(); }

  /// NED position (m) of a geodetic point relative to the origin (origin must be set).
  Vec3 ned_from_geodetic(double lat_deg, double lon_deg, double alt_m) const;
  /// Rotation body -> NED from a specific force (body, at rest: -R^T g e3) and a magnetic field
  /// (body) given the field's declination (rad); yaw from the tilt-compensated field.
  static Eigen::Quaterniond attitude_from_accel_mag(const Vec3& f_body, const Vec3& m_body, double declination);
  /// The same without a magnetometer: roll and pitch from the specific force, yaw given.
  static Eigen::Quaterniond attitude_from_accel(const Vec3& f_body, double psi);
  /// Rotation body -> NED from two vector pairs, TRIAD (Black 1964; Markley & Crassidis,
  /// "Fundamentals of Spacecraft Attitude Determination and Control", sec. 5.2.1): the primary
  /// pair (here the specific force: f_ned = a_ned - g e3, a_ned from GNSS velocity) is matched
  /// exactly, the secondary (the magnetic field direction) fixes the rotation about it. In level
  /// unaccelerated flight this is attitude_from_accel_mag(); in a turn, a push-over or a
  /// deceleration it is not misled by the non-gravitational acceleration.
  /// Throws std::invalid_argument if a vector is zero or the two pairs are parallel.
  static Eigen::Quaterniond attitude_triad(const Vec3& f_body, const Vec3& f_ned, const Vec3& m_body, const Vec3& m_ned);

 private:
  bool accept(Sensor s, Nanos stamp, bool ok);
  void push(Nanos stamp, EventKind kind, Sensor s, double value = 0.0);
  void try_initialize(const msg::Gnss& m, const Vec3& p_ned, Nanos t_valid);
  void apply_models_config();
  void lose_attitude(Nanos stamp, double gap);
  Vec3 imu_to_cg(const Vec3& accel_body, const Vec3& gyro_body, double dt);
  /// Time of validity of a sample of sensor s stamped `stamp` (stamp - delay).
  Nanos valid_at(Sensor s, Nanos stamp) const;
  /// Filter::update at the time of validity t_v: with the history's state when t_v is before the
  /// last IMU sample (invalid, counted, when older than the whole history).
  template <class Model>
  UpdateResult fuse(Model& model, const typename Model::Vec& z, Nanos t_v);
  /// fuse() without the dead-reckoning smoothing of the published position.
  template <class Model>
  UpdateResult fuse_now_or_then(Model& model, const typename Model::Vec& z, Nanos t_v);
  /// fuse() that, after inflate_after consecutive rejections, inflates the variances of the
  /// states [first, first + n) by the NIS over the gate (Filter::inflate) and fuses again.
  template <class Model>
  UpdateResult fuse_robust(Sensor s, Model& model, const typename Model::Vec& z, Nanos t_v, int first, int n);
  bool gnss_reset_allowed(Nanos stamp, double innovation) const;
  /// The GNSS velocity's north and east (m/s, NED) through GnssVelocityNE (use_gnss_vel_d false).
  UpdateResult fuse_gnss_velocity_ne(const Vec3& vel, Nanos t_v);
  void use_reported_accuracy(const msg::Gnss& m);
  Vec3 gnss_error_variance() const;
  void reset_to_gnss(Nanos stamp, const Vec3& p, const Vec3& vel, Nanos t_v);
  /// Sets the sensor states of a re-initialisation (x, P0) to the filter's before it: gyro and
  /// accelerometer biases, S_g, b_m, k_sp with their covariance among themselves.
  void keep_calibration(NominalState& x, Cov& P0) const;
  /// The dynamic pressure q_bar the static port sees (BaroAltitude), Pa: the pitot's last sample,
  /// or 0.5 rho u_r^2 from the estimate while the pitot is silent.
  double dynamic_pressure() const;
  /// In the air: the pitot measured at least min_airspeed within the last 0.5 s.
  bool airborne(Nanos stamp) const;

  EstimatorConfig cfg_;
  Filter filter_;
  GnssPosition gnss_pos_;
  GnssVelocity gnss_vel_;
  GnssVelocityNE gnss_vel_ne_;  ///< gnss_vel_'s north and east rows, without use_gnss_vel_d
  Magnetometer mag_;
  MagHeading mag_heading_;
  BaroAltitude baro_;
  PitotAirspeed pitot_;
  ZeroSideslip sideslip_;
  SideForce side_force_;
  NormalForce normal_force_;
  Vec3 accel_sum_ = Vec3::Zero();  // body specific force summed since the previous pitot sample
  int accel_n_ = 0;                // (the side- and normal-force updates' measurement)
  /// body_attitude()'s Exp(-mu) for the b_a and gravity it was formed with: b_a moves only in
  /// updates, the attitude is published with every IMU sample.
  struct LevelTilt {
    Vec3 b_a = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
    double gravity = 0.0;
    Eigen::Quaterniond exp_minus_mu = Eigen::Quaterniond::Identity();
  };
  mutable LevelTilt level_tilt_;

  bool initialized_ = false;
  bool keep_calibration_ = false;  ///< the next initialisation keeps the sensor states (after an IMU loss)
  bool expect_mag_ = true;
  std::array<bool, kSensorCount> expected_{true, true, true, true, true};
  Nanos first_check_ = -1;  ///< the first check_timeouts() call: when the silence of a never-heard sensor starts
  std::optional<tern::GeoOrigin> origin_;
  double origin_lat_ = 0.0, origin_lon_ = 0.0, origin_alt_ = 0.0;
  Nanos origin_stamp_ = 0;

  // pre-initialisation averages
  Vec3 accel_avg_ = Vec3::Zero(), gyro_avg_ = Vec3::Zero(), mag_avg_ = Vec3::Zero();
  // before initialisation: the specific force of the last second, by IMU stamp, and the previous
  // fix's velocity and time of validity. The mean specific force between two fixes' times of
  // validity against their velocity difference gives an in-flight initialisation's attitude
  // (by time of validity: a fix arrives its latency late, after IMU samples of later motion).
  struct ImuRecord {
    Nanos stamp;
    Vec3 accel;  ///< specific force at the CG, body axes
    Vec3 gyro;   ///< angular rate, body axes
  };
  std::deque<ImuRecord> pre_init_imu_;
  Vec3 prev_fix_vel_ = Vec3::Zero();
  Nanos prev_fix_tv_ = -1;
  /// Held still over the last second of pre_init_imu_: the mean angular rate and the rate's RMS
  /// deviation from it both below rest_rate_max (a hand-held aircraft before a launch is not).
  bool still() const;
  /// Mean specific force of pre_init_imu_ over (t0, t1]; nullopt when no sample lies there.
  std::optional<Vec3> mean_specific_force(Nanos t0, Nanos t1) const;
  std::int64_t imu_samples_ = 0, mag_samples_ = 0;
  // barometer calibration: altitude offset = mean(tern::isa_pressure_altitude(p) - altitude estimate)
  int baro_cal_count_ = 0;
  double baro_cal_sum_ = 0.0;
  double baro_cal_q_sum_ = 0.0;  // dynamic pressure over the calibration, Pa (BaroAltitude::q_datum)
  double baro_offset_ = 0.0;
  bool baro_calibrated_ = false;
  /// Variance of the altitude the barometer was calibrated against (the origin's: a GNSS fix's),
  /// m^2. The filter's altitude is the height above that datum; in the frame it adds this.
  double baro_datum_var_ = 0.0;

  double last_diff_pressure_ = 0.0;  // last valid differential pressure, Pa
  Nanos last_diff_stamp_ = -1;
  Nanos imu_stamp_ = -1;
  Vec3 rate_ = Vec3::Zero();       // last bias-removed gyro, body
  Vec3 gyro_body_ = Vec3::Zero();  // last measured gyro in body axes (bias not removed)
  Vec3 omega_dot_ = Vec3::Zero();  // low-passed angular acceleration, body, rad/s^2
  Mat3 R_bi_ = Mat3::Identity();   // IMU axes -> body axes (cfg_.imu_mount)
  StateHistory history_;
  ProcessNoise process_;  // cfg_.process with the GNSS error walks from the reported accuracy
  std::uint64_t inflations_ = 0;
  Nanos last_gnss_reset_ = -1;
  Nanos gnss_reject_since_ = -1;
  Vec3 output_offset_ = Vec3::Zero();  // published position = filter position + this (decays)
  std::uint64_t gnss_resets_ = 0, filter_resets_ = 0, mag_resets_ = 0;
  Nanos mag_reject_since_ = -1;
  Nanos init_stamp_ = -1;
  double last_Va_ = 0.0;  // airspeed of the last applicable pitot sample, m/s (0: none)
  Nanos last_Va_stamp_ = -1;
  /// Yaw to psi (roll and pitch kept) with yaw sigma `sigma`, the wind re-derived from the air
  /// triangle when airborne (wider by the yaw's sigma unless the yaw came from the magnetometer);
  /// `why` (mag_reset, gnss_yaw_reset or gsf_yaw_reset) is the event and the counter.
  void reset_yaw(Nanos stamp, double psi, double sigma, EventKind why);
  /// Yaw from the GNSS (gnss_yaw(): the converged GSF's, else the course), velocity and position
  /// to the fix, the magnetometer no longer fused (mag_inhibited_); `why` as for reset_yaw.
  void reset_yaw_to_gnss(Nanos stamp, const Vec3& p, const msg::Gnss& m, Nanos t_v, EventKind why);
  /// The field at the origin (mag_field_from_model) or the configured one; sets the models.
  void set_earth_field(const tern::MagneticField& f);
  tern::MagneticField field_;
  Nanos gnss_vel_reject_since_ = -1;
  YawGsf gsf_;                     ///< the yaw from IMU and GNSS velocity alone (yaw_gsf.hpp)
  Nanos gsf_disagree_since_ = -1;  ///< the filter's yaw and the GSF's disagree since
  /// The GSF's yaw and sigma when it has converged, else the GNSS course and gnss_yaw_sigma.
  std::pair<double, double> gnss_yaw(const msg::Gnss& m) const;
  bool gsf_converged() const;
  /// After the fix's velocity update `rv`: in the air, velocities rejected for gnss_yaw_reset_time
  /// reset velocity and position to the fix, and the yaw too if it is off. True after a reset.
  bool recover_velocity(UpdateResult rv, const msg::Gnss& m, const Vec3& p, Nanos t_v);
  /// Feeds the fix's velocity to the GSF in the air (stops it on the ground); resets the yaw to it
  /// when the filter's yaw keeps disagreeing with the converged GSF. Returns true after a reset.
  bool check_yaw_with_gsf(const msg::Gnss& m, const Vec3& p, Nanos t_v);
  double accel_nav_ = 0.0;                                  ///< low-passed |NED acceleration|, m/s^2 (GNSS noise in manoeuvres)
  double gnss_vel_sigma_h_ = 0.0, gnss_vel_sigma_v_ = 0.0;  ///< before the manoeuvre term
  bool reported_h_acc_ = false, reported_s_acc_ = false;    ///< the last fix reported h_acc / s_acc
  /// The GNSS noise of the next fix: the receiver's (or the configured) plus the manoeuvre term.
  void set_gnss_noise();
  std::uint64_t gnss_yaw_resets_ = 0;
  bool mag_inhibited_ = false;  ///< after a yaw reset to GNSS: the magnetometer disagreed with it
  std::array<SensorCounters, kSensorCount> counters_{};
  std::vector<Event> events_;
};

}  // namespace tern::ekf
