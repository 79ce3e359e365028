// tern/estimator_ekf/estimator_config.hpp: the estimator's sensors (Sensor) and its configuration
// (EstimatorConfig): every setting of estimator.hpp's Estimator, with its unit, range and source.
// The plugin's parameters (src/estimator_ekf_plugin.hpp) fill it.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>

#include "tern/estimator_ekf/filter.hpp"
#include "tern/estimator_ekf/gnss_checks.hpp"
#include "tern/estimator_ekf/measurements.hpp"
#include "tern/estimator_ekf/yaw_gsf.hpp"
#include "tern/math.hpp"
#include "tern/atmosphere.hpp"

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
  double gravity = kGravity;         ///< m/s^2
  double rho = kIsaSeaLevelDensity;  ///< air density for the pitot, kg/m^3
  ProcessNoise process;              ///< IMU noise and random walks (filter.hpp)

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
  int min_fix_type = 3;  ///< minimum fix type used (3: 3-D fix)
  /// The start-up checks a fix passes before it is used (the first as the origin and the
  /// barometer's datum) and that must hold before the estimate is valid on the ground
  /// (gnss_checks.hpp: PX4 EKF2_GPS_CHECK, EKF2_REQ_*, held EKF2_REQ_GPS_H).
  GnssCheckConfig gnss_checks;
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
  /// A fix from other satellites than the last (its num_sats or hdop changed: the antenna turned
  /// from part of the sky, a satellite rose or set) is another solution, its error a jump from the
  /// last one's: the GNSS error state's variance grows by the change of the reported accuracy
  /// squared, and stays within the new accuracy squared, before the fix is fused. false: the
  /// error only wanders.
  bool gnss_constellation_jumps = true;
  double gnss_pos_accel_scale = 0.05;
  double gnss_pos_gate = kChi2_999[3];
  /// Chi-square gate of the GNSS velocity's three axes; a fix that fails it is fused in north and
  /// east alone (GnssVelocityNE, this gate at 2 dof), as PX4 EKF2 gates the horizontal velocity and
  /// the vertical apart: a receiver's down velocity lags most in a pull (estimator_gnss.cpp).
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
  /// s: the least time between two fused magnetometer samples; the ones in between count for the
  /// time-out but are not fused. mag_sigma is an error that lasts far longer than a sample (the
  /// iron's heading-dependent error, disturbances): every fused sample adds the same information,
  /// so a 100-Hz compass fused whole weighs twice the 50-Hz stream mag_sigma was set for, against
  /// the GNSS velocity's view of the yaw. ArduPilot's EKF2 and EKF3 fuse any non-IMU sensor at most
  /// every 50 ms (sensorIntervalMin_ms). One sample per slot of this length, the slots following
  /// each other (not the samples), so a faster stream of any rate averages this rate; a sample up to
  /// a quarter of it early takes its slot (a 50-Hz stream's jitter keeps every sample). 0: every sample.
  /// PX4 Zurich 2014 (compass at 100 Hz): course 3.63 -> 3.03 deg RMS, horizontal velocity 1.18 ->
  /// 1.01 m/s against the fixes (bench_real_flights; the log thinned to 20-67 Hz: 2.93-3.01 deg), with one
  /// velocity reset more (71.4 s, the end of a 4-g pull-up whose speed the estimate lost 4 m/s of
  /// against both the fixes and PX4's own estimate; fusing every sample, that gap stayed 2 s unreset).
  double mag_fusion_interval = 0.02;
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
  /// to the course and the magnetometer is not fused until its heading agrees again
  /// (mag_resume_time; PX4 EKF2's emergency yaw reset and mag_fault, after its EKF-GSF; here the
  /// course itself, the wind's crab angle within gnss_yaw_sigma, its lag within gnss_course_lag).
  /// 0: never.
  double gnss_yaw_reset_time = 1.0;
  /// rad: the first yaw alignment in flight, for a launch or takeoff with a yaw the magnetometer
  /// gave on the ground (a miscalibrated compass, a hangar's or a car's iron): until a GNSS
  /// velocity in motion (fix and filter at >= 5 m/s horizontally, pitch within 45 deg; PX4's
  /// fixed-wing land detector leaves "landed" above the same 5 m/s, LNDFW_VEL_XY_MAX: the pitot's
  /// min_airspeed comes later on a hand launch) is accepted with its
  /// course within this of the filter's velocity course, a rejected one further off turns the yaw
  /// by the difference at once (the launch threw the aircraft along its nose: the difference is the
  /// yaw's error, whatever the wind), resets velocity and position to the fix and stops the
  /// magnetometer until it agrees (mag_resume_time). PX4 ecl's realignYawGPS for a fixed wing in
  /// the air (0.5 rad course error with the velocity innovation test failed; its first alignment
  /// adds the course error to the yaw), ArduPilot EKF2's alignYawGPS at its first in-flight yaw
  /// alignment (firstMagYawInit). Without it the yaw waits gnss_yaw_reset_time (1 s, PX4's
  /// EKFGSF_reset_delay) of rejection: on the PX4 Zurich 2014 hand launch, with the compass's yaw
  /// 34 deg off, six fixes were 37-44 deg off the course; with it the yaw is aligned at 17.55 s
  /// instead of 18.34 s: course 4.90 -> 3.63 deg RMS, velocity 1.216 -> 1.182 m/s over the
  /// flight (bench_real_flights), no other reset. Waiting for the pitot's min_airspeed (8 m/s,
  /// reached at 17.44 s there) instead of the 5 m/s of motion left the first fix of the airborne
  /// window (17.55 s, valid at 17.34) 39 deg off; aligned at the first fix at 5 m/s (17.16 s):
  /// course 3.62 -> 3.18 deg, velocity 1.09 -> 0.99 m/s. 0: no such alignment (the former rules).
  double launch_course_error = 0.5;
  /// rad: the yaw uncertainty after such a reset from the course (the GSF not converged): the
  /// crab angle a wind of 5 m/s gives at 14 m/s; also the least yaw difference that counts.
  double gnss_yaw_sigma = 0.35;
  /// rad: the yaw GSF (yaw_gsf.hpp: IMU and GNSS velocity alone, PX4 EKF2's EKF-GSF) counts as
  /// converged below this 1 sigma; its yaw then replaces the course in the resets above. 0 (the
  /// default): the GSF does not run. Off by default: on a simulated aggressive flight (60-deg
  /// banks, turbulence, the realistic IMU) its converged yaw erred 11 deg RMS (24 deg at worst)
  /// while claiming 1-2 deg; a compass the filter follows wrongly is its use (gsf_disagree_time).
  /// Not in aerobatics: its models' tilt (a complementary filter for coordinated flight) comes
  /// out of a loop wrong (bench_aerobatics --gsf: yaw resets 87-163 deg wrong, up to 8 a flight).
  double gsf_max_sigma = 0.0;
  /// s: in the air, the filter's yaw further than 3 sigma (at least gnss_yaw_sigma) from the
  /// converged GSF's this long is reset to it and the magnetometer is not fused until it agrees (a compass
  /// the filter followed while the wind state absorbed the velocity: a compass turned 92 deg left
  /// yaw 38 deg and wind 11 m/s wrong with the GNSS velocity accepted). 0 (the default): never.
  /// Needs gsf_max_sigma. Off by default: in bench_estimation's aggressive mission (50-deg banks,
  /// turbulence) the GSF disagreed with a right yaw by 20-44 deg for 5 s on 4 of 20 flights.
  double gsf_disagree_time = 0.0;
  /// After a yaw reset to the GNSS (gnss_yaw_reset_time, gsf_disagree_time) the magnetometer is
  /// not fused but still tested: its tilt-compensated heading against the filter's yaw, as PX4
  /// EKF2's checkMagHeadingConsistency (mag_control.cpp) keeps testing a stopped magnetometer and
  /// lets heading fusion start again once the heading innovation is inside EKF2_HEAD_NOISE while
  /// the yaw is observable. Here: every sample's heading innovation within mag_resume_error, with
  /// the filter's yaw 1 sigma below mag_resume_yaw_sigma (the GNSS velocity has observed the yaw
  /// since the reset), for mag_resume_time: fusion resumes (event mag_resumed). Samples with the
  /// pitch beyond 60 deg (the Euler yaw and the tilt-compensated heading ill-conditioned: loops)
  /// neither pass nor fail. A compass the reset was right to drop (turned, disturbed) stays off;
  /// one that agreed throughout (the reset blamed the yaw for a manoeuvre) comes back. PX4's
  /// emergency reset itself keeps mag_fault until the sensor's calibration changes (its source
  /// leaves clearing it on a good 3-axis field as an open question); issue 61 asks for the resume.
  /// s; 0: never resume (the magnetometer off for the rest of the flight, the former behaviour).
  double mag_resume_time = 5.0;
  /// rad: PX4 EKF2_HEAD_NOISE's default (0.3 rad), the bound PX4 puts on the heading innovation
  /// of a consistent magnetometer; 3 x mag_resume_yaw_sigma.
  double mag_resume_error = 0.3;
  /// rad: the filter's yaw must be known this well (1 sigma) for the test to count: just after a
  /// reset to the course (gnss_yaw_sigma 0.35 rad) agreement says little.
  double mag_resume_yaw_sigma = 0.1;
  /// s: the GNSS course lags the aircraft by the receiver's delay, known only to within this
  /// (a log's assumed gnss_delay against the receiver's true one: issue 61's aerobatic flight
  /// behaved differently at 0 and 0.33 s; a u-blox M8N at 10 Hz is 0.1-0.2 s late). The yaw is
  /// blamed for rejected GNSS velocity (gnss_yaw_reset_time) only when it is further from the
  /// course than gnss_yaw_sigma plus this times the largest course rate over the rejection, and
  /// never while the course cannot be the heading (a fix's horizontal speed under 5 m/s, the
  /// pitch beyond 45 deg in that time: loops, vertical flight); and the velocity and position
  /// are reset only when the velocity innovation exceeds this times the manoeuvring acceleration
  /// (accel_nav_: within it the lagged fix is the one off). 0: the course compared as it is and
  /// every such rejection reset (the former rules). bench_aerobatics, a receiver 0.3 s late
  /// unaccounted: 30 velocity resets and 2 yaw resets per flight before, <= 6 and 0 with 0.35 s.
  double gnss_course_lag = 0.35;
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
  /// The static port's cross-flow coefficients (PX4 EKF2_PCOEF_YP/YN/Z), unknown: 1 sigma, as a
  /// fraction of the cross-flow's dynamic pressure (BaroAltitude): a coefficient anywhere in PX4's
  /// range for them, +-0.5, uniformly: 0.5 / sqrt(3) = 0.29.
  double baro_cross_flow_sigma = 0.29;
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
    v(&C::gnss_vel_gate, "gnss_vel_gate",
      ParamSpec("", 0.0, 1e6, "chi-square gate of GNSS velocity (3 dof, then north and east at 2 dof; 0: off)"));
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
    v(&C::mag_fusion_interval, "mag_fusion_interval",
      ParamSpec("s", 0.0, 1.0, "least time between fused magnetometer samples (mag_noise is set for a 50-Hz stream; 0: every sample)"));
    v(&C::mag_gate, "mag_gate", ParamSpec("", 0.0, 1e6, "chi-square gate of the 3-axis magnetometer update (3 dof; 0: off)"));
    v(&C::mag_heading_gate, "mag_heading_gate", ParamSpec("", 0.0, 1e6, "chi-square gate of the magnetic heading update (1 dof; 0: off)"));
    v(&C::gnss_yaw_reset_time, "gnss_yaw_reset_time",
      ParamSpec("s", 0.0, 60.0,
                "in the air, GNSS velocity rejected this long resets yaw to the GNSS course and stops the magnetometer (0: never)"));
    v(&C::launch_course_error, "launch_course_error",
      ParamSpec("rad", 0.0, 3.2,
                "first yaw alignment in motion: a rejected GNSS velocity (fix and filter at >= 5 m/s) whose course is off the filter's by "
                "more turns the yaw by the difference, until a fix confirms the yaw (PX4 ecl realignYawGPS; 0: off)"));
    v(&C::gnss_yaw_sigma, "gnss_yaw_sigma", ParamSpec("rad", 0.01, 3.2, "yaw uncertainty after a yaw reset to the GNSS course, 1 sigma"));
    v(&C::gsf_max_sigma, "gsf_max_sigma",
      ParamSpec("rad", 0.0, 1.0, "the yaw GSF (IMU and GNSS velocity alone) counts as converged below this 1 sigma (0: it does not run)"));
    v(&C::gsf_disagree_time, "gsf_disagree_time",
      ParamSpec(
          "s", 0.0, 600.0,
          "in the air, the filter's yaw disagreeing with the converged yaw GSF this long resets it and stops the magnetometer (0: never)"));
    v(&C::mag_resume_time, "mag_resume_time",
      ParamSpec("s", 0.0, 600.0,
                "after a yaw reset to GNSS, the magnetometer's heading consistent with the yaw this long resumes its fusion (0: never)"));
    v(&C::mag_resume_error, "mag_resume_error",
      ParamSpec("rad", 0.01, 3.2,
                "largest heading innovation a stopped magnetometer may show to count as consistent (PX4 EKF2_HEAD_NOISE)"));
    v(&C::mag_resume_yaw_sigma, "mag_resume_yaw_sigma",
      ParamSpec("rad", 0.001, 3.2, "the filter's yaw 1 sigma below which a stopped magnetometer's consistency counts"));
    v(&C::gnss_course_lag, "gnss_course_lag",
      ParamSpec("s", 0.0, 2.0,
                "uncertainty of the GNSS delay: the course's lag allowed before the yaw is blamed for rejected velocity (0: the course as "
                "it is)"));
    v(&C::mag_init_wait, "mag_init_wait",
      ParamSpec("s", 0.0, 60.0, "time to wait for a magnetometer sample after the origin is set before initialising without"));
    v(&C::mag_reset_time, "mag_reset_time",
      ParamSpec("s", 0.1, 600.0, "continuous magnetic-heading rejection after which yaw is reset to the magnetometer"));
    v(&C::mag_reset_window, "mag_reset_window",
      ParamSpec("s", 0.0, 1e6, "yaw resets to the magnetometer only within this long after initialisation (0: never)"));
    v(&C::baro_sigma, "baro_noise", ParamSpec("Pa", 1e-3, 1000.0, "static-pressure noise, 1 sigma"));
    v(&C::baro_cross_flow_sigma, "baro_cross_flow_sigma",
      ParamSpec("", 0.0, 2.0,
                "uncertainty of the static port's unmodelled cross-flow coefficients (PX4 EKF2_PCOEF_Y*/Z), 1 sigma: the barometer's "
                "noise grows with the body's sideslip and angle-of-attack flow"));
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
    v(&C::gnss_checks);  // GnssCheckConfig::describe (gnss_checks.hpp)
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
    v(&C::gnss_constellation_jumps, "gnss_constellation_jumps",
      ParamSpec("", 0, 1,
                "a fix from other satellites (num_sats or hdop changed) jumps: the GNSS error state's variance grows by "
                "the change of the reported accuracy squared"));
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

}  // namespace tern::ekf
