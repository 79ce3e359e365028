// tern_sim_aero/boot_calibration.hpp: the flight-control unit's calibrations at power-up, as the
// ROSflight firmware runs them (rosflight/rosflight_firmware src/sensors.cpp), so that the
// simulated sensors reach the estimator as the FCU's do: raw turn-on biases first, calibrated
// values once the aircraft has sat still long enough.
//
// - Gyro (Sensors::calibrate_gyro, with ARM_CAL_GYRO as state_manager.cpp runs it before arming):
//   the mean of the first 1001 samples becomes the bias subtracted from every later sample;
//   a mean of 1 rad/s or more ("Too much movement for gyro cal") restarts the window.
// - Differential pressure (Sensors::calibrate_diff_pressure): a cycle every > 20 ms of samples,
//   128 cycles ignored, then the mean of 127 becomes the offset subtracted from every later
//   sample; a variance of 100 Pa^2 or more ("Too much movement for diff pressure cal") restarts.
//   The wind blowing into the pitot during the window goes into the offset, as on a real field.
// - Barometer (Sensors::calibrate_baro): same cycles, variance below 25 Pa^2; the firmware only
//   records the ground pressure (BARO_BIAS, GROUND_LEVEL) and leaves the pressure it sends
//   unchanged, so does this model: the estimator takes its own ground reference.
// The simulator's fcu_status reports disarmed until they are done: the firmware refuses to arm
// while it calibrates the gyro (state_manager.cpp, FSM_STATE_CALIBRATING), and the simulated pilot
// arms after the pressure calibrations' "successful" messages, as default_fcu.yaml's RC script
// does (a switched-off sensor has none to wait for).
//
// Time: the caller passes the time since its previous sample (s); the 20-ms cycle rule uses the
// firmware's millisecond clock (floor of the accumulated time).
#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace tern::sim {

/// One pressure calibration of the firmware (baro or pitot): Welford mean and variance over
/// the cycles after the ignored ones.
struct PressureCalibration {
  explicit PressureCalibration(double max_variance_pa2) : max_variance(max_variance_pa2) {}
  double max_variance;  ///< Pa^2: larger restarts the calibration
  bool done = false;
  double offset = 0;  ///< Pa: the mean once done
  int restarts = 0;   ///< windows refused for movement
  /// Feeds one sample at the firmware clock `ms`; true when this sample completed it.
  bool add(double pressure, std::int64_t ms);

 private:
  int count_ = 0;
  double mean_ = 0, var_ = 0;
  std::int64_t last_ms_ = 0;  ///< the firmware's last_*_cal_iter_ms_ starts at 0
};

class BootCalibration {
 public:
  static constexpr int kGyroSamples = 1001;          ///< calibrate_gyro: done when count > 1000
  static constexpr double kGyroMaxBias = 1.0;        ///< rad/s: larger is "too much movement"
  static constexpr int kDelayCycles = 128;           ///< SENSOR_CAL_DELAY_CYCLES
  static constexpr int kCycles = 127;                ///< SENSOR_CAL_CYCLES
  static constexpr double kBaroMaxVariance = 25.0;   ///< Pa^2, BARO_MAX_CALIBRATION_VARIANCE
  static constexpr double kDiffMaxVariance = 100.0;  ///< Pa^2, DIFF_PRESSURE_MAX_CALIBRATION_VARIANCE

  /// The calibrated gyro rate: raw minus the bias (raw until the calibration is done).
  Eigen::Vector3d gyro(const Eigen::Vector3d& raw);
  /// The calibrated differential pressure, Pa (raw until done); dt: s since the previous sample.
  double diff_pressure(double raw, double dt);
  /// The barometer pressure, unchanged (see the file comment); feeds the ground calibration.
  double baro(double raw, double dt);

  /// Calibrations done before the simulation starts (an air start: the FCU calibrated on the
  /// ground before the launch) with these results.
  void set_done(const Eigen::Vector3d& gyro_bias, double diff_offset, double ground_pressure);

  bool done() const { return gyro_done_ && diff_.done && baro_.done; }
  bool gyro_done() const { return gyro_done_; }
  const Eigen::Vector3d& gyro_bias() const { return gyro_bias_; }
  const PressureCalibration& diff() const { return diff_; }
  const PressureCalibration& baro_ground() const { return baro_; }
  int gyro_restarts() const { return gyro_restarts_; }

 private:
  /// The firmware's integer millisecond clock (1 ns of slack against sums of dt that land just short).
  static std::int64_t millis(double t) { return static_cast<std::int64_t>(t * 1000.0 + 1e-6); }
  bool gyro_done_ = false;
  int gyro_count_ = 0, gyro_restarts_ = 0;
  Eigen::Vector3d gyro_sum_ = Eigen::Vector3d::Zero(), gyro_bias_ = Eigen::Vector3d::Zero();
  PressureCalibration diff_{kDiffMaxVariance}, baro_{kBaroMaxVariance};
  double diff_clock_ = -1, baro_clock_ = -1;  ///< s since power-up, per sensor (-1: no sample yet)
};

}  // namespace tern::sim
