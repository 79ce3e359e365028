// Named sensor profiles (see profiles.hpp).
#include "tern_sim_aero/profiles.hpp"

#include <cmath>
#include <stdexcept>

#include "tern/math.hpp"

namespace tern::sim {

namespace {
constexpr double kG0 = tern::kStandardGravity;  // datasheet g to m/s^2

// Every error zero; the field model, the origin and the GNSS satellite count stay.
SensorParams ideal() {
  SensorParams p;
  p.accel_noise = p.accel_bias_range = p.accel_bias_walk = 0.0;
  p.gyro_noise = p.gyro_bias_range = p.gyro_bias_walk = 0.0;
  p.accel_scale_range = p.gyro_scale_range = p.imu_cross_axis_range = 0.0;
  p.imu_misalignment.setZero();
  p.imu_position.setZero();
  p.accel_vibration = p.gyro_vibration = 0.0;
  p.mag_noise = p.mag_gm_sigma = 0.0;
  p.mag_hard_iron_range = p.mag_soft_iron_range = 0.0;
  p.mag_motor_field.setZero();
  p.baro_noise = p.baro_bias_range = p.baro_bias_walk = p.baro_static_error = 0.0;
  p.diff_noise = p.diff_bias_range = p.diff_bias_walk = p.diff_scale_range = 0.0;
  p.gnss_h_sigma = p.gnss_v_sigma = 0.0;
  p.gnss_start_steady = false;
  p.gnss_vel_noise = 0.0;
  p.gnss_antenna_position.setZero();
  p.gnss_latency = 0.0;
  p.range_noise_near = p.range_noise_far = 0.0;
  p.gnss_h_acc = p.gnss_v_acc = p.gnss_s_acc = 0.01;  // small but positive (an estimator divides by them)
  return p;
}

// ROSflight's standalone simulator (SensorParams' defaults) as a ROSflight user flies it: the
// firmware refuses to arm until the IMU is calibrated ("Unable to arm: IMU not calibrated",
// state_manager.cpp), so calibrate_imu has put this power-up's accelerometer offset into
// ACC_{X,Y,Z}_BIAS before the flight, with the aircraft at rest on this world's flat ground (the
// gear's wheels at one height: it rests level, so the floor adds no tilt). Left: the mean's noise
// 0.2 / sqrt(1000) = 0.006 m/s^2 (0.04 deg) and the bias walk since.
SensorParams rosflight() {
  SensorParams p;
  p.accel_calibrated_level = true;
  p.accel_calibrated_at_power_up = true;
  return p;
}

// TDK InvenSense ICM-20602 (DS-000176). Per-sample sigma = density * sqrt(ENBW), ENBW = 1.57 x the
// ~100 Hz DLPF bandwidth = 157 Hz (first-order filter: pi/2 f_3dB), sqrt(157) = 12.53.
void realistic_imu(SensorParams& p) {
  const double sqrt_enbw = std::sqrt(1.57 * 100.0);
  p.gyro_noise = 0.004 * kRadPerDeg * sqrt_enbw;  // 4 mdps/sqrt(Hz) -> 0.050 dps = 8.7e-4 rad/s
  p.accel_noise = 100e-6 * kG0 * sqrt_enbw;       // 100 ug/sqrt(Hz) -> 1.25 mg = 0.0123 m/s^2
  // Raw turn-on gyro bias: the +-1 dps initial ZRO tolerance; the FCU's boot calibration
  // (calibrate_at_boot, boot_calibration.hpp) removes it while the aircraft sits still. The
  // accelerometer's +-25 mg offset is removed by the ground calibration stored in the FCU's
  // parameters (`tern fcu calibrate imu`, ROSflight's calibrate_accel), done with the aircraft on
  // a floor checked with a spirit level (+-0.3 deg); what is left is its temperature drift since.
  p.calibrate_at_boot = true;
  p.accel_calibrated_level = true;
  p.accel_calibration_tilt_range = 0.3 * kRadPerDeg;
  p.gyro_bias_range = 1.0 * kRadPerDeg;                               // rad/s: +-1 dps = 0.0175 rad/s
  p.accel_bias_range = 0.05;                                          // m/s^2 residual of the stored calibration
  p.gyro_bias_walk = 3e-5;                                            // bias instability ~5 deg/h, as a walk in rad/s/sqrt(s)
  p.accel_bias_walk = 1e-3;                                           // m/s^2/sqrt(s): temperature drift in flight
  p.gyro_scale_range = 0.01;                                          // sensitivity error +-1 % (datasheet)
  p.accel_scale_range = 0.01;                                         // sensitivity error +-1 %
  p.imu_cross_axis_range = 0.02;                                      // cross-axis sensitivity +-2 % (datasheet)
  p.imu_misalignment = Eigen::Vector3d(0.5, -0.5, 1.0) * kRadPerDeg;  // a hand-mounted flight controller
  p.imu_position = Eigen::Vector3d(0.05, 0.0, 0.02);                  // m from the CG, body FRD
  // Full-throttle vibration of a soft-mounted FCU on an electric aircraft (PX4's vibration guidance).
  p.accel_vibration = 1.5;  // m/s^2
  p.gyro_vibration = 0.01;  // rad/s
  // Output resolution at the full-scale ranges a fixed-wing FCU sets (+-16 g, +-2000 dps):
  // 2048 LSB/g, 16.4 LSB/dps, temperature 326.8 LSB/degC (DS-000176, tables 1-3).
  p.accel_resolution = kG0 / 2048.0;           // 4.79e-3 m/s^2
  p.gyro_resolution = kRadPerDeg / 16.4;       // 1.06e-3 rad/s
  p.imu_temperature_resolution = 1.0 / 326.8;  // K
}

// HMC5883L / IST8310 class (the ROSflight boards); residuals after a compass calibration.
void realistic_mag(SensorParams& p) {
  p.mag_noise = 0.3e-6;                                      // T white = 3 mG (HMC5883L noise floor 2 mG, plus margin)
  p.mag_gm_sigma = 0.3e-6;                                   // T: slow local disturbances ...
  p.mag_gm_tau = 30.0;                                       // ... with a 30 s correlation time
  p.mag_hard_iron_range = 1e-6;                              // T per axis residual hard iron
  p.mag_soft_iron_range = 0.02;                              // +-2 % residual soft iron
  p.mag_motor_field = Eigen::Vector3d(0.0, 0.5e-6, 1.5e-6);  // T at full throttle (motor current)
  p.mag_resolution = 1e-4 / 1090.0;                          // T: HMC5883L at +-1.3 Ga, 1090 LSB/Ga (0.92 mG)
}

// The static port's position error (sensors.hpp, PX4 EKF2's EKF2_PCOEF_* model). No fixed-wing set
// is published; the one tuned set we have is PX4 PR #19507's, from a multicopter's flight log with
// its tuning script: XP -0.314, XN -0.284, YP -0.753, YN -0.598. Along x, 5 % of the dynamic
// pressure, inside the certification limit for the whole pitot-static system (FAR 23.1325(e):
// 30 ft per 100 kt, 6.8 % of q at 100 kt). Across the body, the tuned set's side coefficients (a
// flow across the fuselage, as across the multicopter's body); along z, which it does not tune,
// the size of its x coefficients.
void realistic_static_port(SensorParams& p) {
  p.baro_static_error = 0.05;
  p.baro_static_error_yp = -0.753;
  p.baro_static_error_yn = -0.598;
  p.baro_static_error_z = -0.3;
}

// TE MS5611-01BA03 barometer.
void realistic_baro(SensorParams& p) {
  p.baro_noise = 1.2;         // Pa: resolution RMS 0.012 mbar at OSR 4096
  p.baro_bias_range = 150.0;  // Pa: absolute accuracy +-1.5 mbar (25 C, 750..1100 mbar)
  p.baro_bias_walk = 0.5;     // Pa/sqrt(s): thermal drift in flight
  realistic_static_port(p);
  p.baro_resolution = 1.0;               // Pa: the compensated pressure P in 0.01 mbar
  p.baro_temperature_resolution = 0.01;  // K: TEMP in 0.01 degC
}

// TE MS4525DO-DS5AI001DP (001PD: +-1 psi, 14 bit over 10..90 % of the counts: 13790 Pa / 13107
// counts = 1.05 Pa per count).
void realistic_pitot(SensorParams& p) {
  p.diff_noise = 1.5;                              // Pa: ~1.4 counts RMS
  p.diff_bias_range = 2.0;                         // Pa: offset since the last zero (the boot calibration removes it)
  p.diff_bias_walk = 0.05;                         // Pa/sqrt(s): thermal drift of the offset
  p.diff_scale_range = 0.05;                       // +-5 %: installation (probe position, pitot/static tubes)
  p.diff_resolution = 13789.5 / 13107.0;           // Pa per count (1.05)
  p.diff_temperature_resolution = 200.0 / 2047.0;  // K: 11 bits over -50..150 degC
}

// The antenna's sky (gnss_sky.hpp) and the receiver's platform model. The 12 satellites lie above
// u-blox's default elevation mask (UBX-CFG-NAV5 minElev, 5 deg). A patch antenna's gain at its own
// horizon is already 10-15 dB below its zenith's; below its plane the ground plane and the airframe
// shade it: the cutoff is the antenna's plane. A satellite back in view is tracked after the M8's
// hot-start time (1 s; its ephemeris is still held). No fix is output beyond the default PDOP
// mask (UBX-CFG-NAV5 pDop, 25.0). The dynamic platform model is u-blox's
// "Airborne <2g" (dynModel 7, "recommended for typical airborne environments"; Paparazzi's
// gps_ubx_ucenter default): its velocity output follows up to 2 g (our reading of the model's
// bound). u-blox publishes no filter bandwidth; the time constant the change beyond the bound takes
// to catch up is the largest the shipped real flight does not contradict: the PX4 Zurich 2014
// flight's fixes (turns of 1-4 g) against PX4's own estimate, each fix's velocity less that
// estimate's passed through this model, 0.815 m/s RMS horizontally for 0.01-0.2 s, 0.825 for 0.5 s.
void realistic_gnss_sky(SensorParams& p) {
  p.gnss_sky = true;
  p.gnss_elevation_mask = 5.0 * kRadPerDeg;
  p.gnss_antenna_cutoff = 0.0;
  p.gnss_reacquisition = 1.0;
  p.gnss_pdop_mask = 25.0;
  p.gnss_max_acceleration = 2.0 * kG0;
  p.gnss_lag_tau = 0.2;
}

// u-blox NEO-M8N. Datasheet: 2.5 m CEP horizontal (24 h static, open sky; per-axis sigma
// CEP / 1.18 = 2.1 m) and 0.05 m/s velocity; the team's 1.2 m per axis is the hAcc a receiver
// reports in flight with 12 satellites, and the reported accuracies equal the true sigmas.
void realistic_gnss(SensorParams& p) {
  p.gnss_h_sigma = 1.2;                                         // m per axis, steady state
  p.gnss_v_sigma = 2.5;                                         // m: vertical ~2 x horizontal (geometry)
  p.gnss_tau = 180.0;                                           // s: slow drift of the position error (atmosphere, multipath)
  p.gnss_start_steady = true;                                   // the first fix already carries the steady error
  p.gnss_vel_noise = 0.05;                                      // m/s: velocity accuracy 0.05 m/s (datasheet)
  p.gnss_vel_tau = 2.0;                                         // s: the receiver's velocity filter
  p.gnss_latency = 0.12;                                        // s: navigation solution to UART output
  p.gnss_antenna_position = Eigen::Vector3d(-0.1, 0.0, -0.08);  // m, body FRD: behind and above the CG
  p.gnss_h_acc = 1.2;                                           // reported = true statistics
  p.gnss_v_acc = 2.5;
  p.gnss_s_acc = 0.05;
  p.gnss_num_sats = 12;
  realistic_gnss_sky(p);
}

SensorParams realistic() {
  SensorParams p;
  realistic_imu(p);
  realistic_mag(p);
  realistic_baro(p);
  realistic_pitot(p);
  realistic_gnss(p);
  return p;
}
}  // namespace

const std::vector<std::string>& sensor_profile_names() {
  static const std::vector<std::string> names{"rosflight", "realistic", "ideal"};
  return names;
}

SensorParams sensor_profile(std::string_view name) {
  if (name == "rosflight") return rosflight();
  if (name == "realistic") return realistic();
  if (name == "ideal") return ideal();
  std::string valid;
  for (const std::string& n : sensor_profile_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown sensor profile '" + std::string(name) + "' (valid: " + valid + ")");
}

}  // namespace tern::sim
