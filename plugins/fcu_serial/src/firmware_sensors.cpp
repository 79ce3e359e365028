// firmware_sensors.cpp: sensor calibration and correction of the emulated firmware, after
// src/sensors.cpp (Sensors::init_imu, start_*_calibration, calibrate_gyro, calibrate_accel,
// calibrate_baro, calibrate_diff_pressure, correct_imu, correct_diff_pressure). See firmware.hpp.
#include <algorithm>
#include <cmath>

#include "tern_fcu_serial/firmware.hpp"
#include "tern/atmosphere.hpp"

namespace tern::fcu::firmware {

namespace {
constexpr int kCalDelayCycles = 128;   // Sensors::SENSOR_CAL_DELAY_CYCLES
constexpr int kCalCycles = 127;        // Sensors::SENSOR_CAL_CYCLES
constexpr double kBaroMaxVar = 25.0;   // Sensors::BARO_MAX_CALIBRATION_VARIANCE, Pa^2
constexpr double kDiffMaxVar = 100.0;  // Sensors::DIFF_PRESSURE_MAX_CALIBRATION_VARIANCE, Pa^2
constexpr int kImuCalSamples = 1000;   // calibrate_gyro / calibrate_accel: done after more than this
// The firmware's own gravity (include/sensors.h, Sensors::gravity_; added to the accelerometer sum in
// src/sensors.cpp, Sensors::calibrate_accel), not the SDK's kGravity: emulated as it is.
constexpr double kFirmwareGravity = 9.80665;
const char* kAcc[] = {"ACC_X_BIAS", "ACC_Y_BIAS", "ACC_Z_BIAS"};
const char* kGyro[] = {"GYRO_X_BIAS", "GYRO_Y_BIAS", "GYRO_Z_BIAS"};

/// One step of the firmware's boot-time ground calibration (calibrate_baro /
/// calibrate_diff_pressure): a cycle every > 20 ms of samples, 128 cycles ignored, then the
/// mean and variance of 127; true when the window is complete (cal.var then decides).
bool calibration_step(auto& cal, double x, std::int64_t now) {
  const std::int64_t ms = now / 1'000'000;
  if (ms <= cal.last + 20) return false;
  cal.last = ms;
  ++cal.count;
  if (cal.count > kCalDelayCycles + kCalCycles) return true;
  if (cal.count > kCalDelayCycles) {
    const double delta = x - cal.mean;
    cal.mean += delta / (cal.count - kCalDelayCycles);
    cal.var += delta * (x - cal.mean) / (kCalCycles - 1);
  }
  return false;
}
}  // namespace

float pressure_altitude(float pressure) { return static_cast<float>(tern::rosflight::pressure_altitude(pressure)); }

// Sensors::init_imu: every stored accelerometer and gyro bias 0 -> ERROR_UNCALIBRATED_IMU.
void Firmware::check_imu_calibrated() {
  bool zero = true;
  for (int i = 0; i < 3; ++i) zero = zero && params_.get_float(kAcc[i]) == 0.0f && params_.get_float(kGyro[i]) == 0.0f;
  if (zero) set_error(kErrorUncalibratedImu);
}

bool Firmware::start_gyro_calibration() {
  gyro_cal_ = true;
  gyro_cal_count_ = 0;
  gyro_sum_ = {};
  for (const char* n : kGyro) params_.set_float(n, 0.0f);
  return true;
}

bool Firmware::start_imu_calibration() {
  start_gyro_calibration();
  acc_cal_ = true;
  imu_cal_count_ = 0;
  acc_sum_ = {};
  acc_max_.fill(-1000.0);
  acc_min_.fill(1000.0);
  for (const char* n : kAcc) params_.set_float(n, 0.0f);
  return true;
}

bool Firmware::start_baro_calibration() {
  baro_cal_ = Cal{};
  baro_calibrated_ = false;
  params_.set_float("BARO_BIAS", 0.0f);
  return true;
}

bool Firmware::start_airspeed_calibration() {
  diff_cal_ = Cal{};
  diff_calibrated_ = false;
  params_.set_float("DIFF_PRESS_BIAS", 0.0f);
  return true;
}

// calibrate_gyro: the mean rate of > 1000 samples (kept if its norm < 1 rad/s).
// calibrate_accel: the mean of accel + (0, 0, g); refused if the samples spread by more than
// 1 m/s^2 (moved), kept if its norm < 3 m/s^2; then ERROR_UNCALIBRATED_IMU is cleared.
void Firmware::calibrate_imu(const std::array<float, 3>& a, const std::array<float, 3>& g) {
  if (gyro_cal_) {
    for (std::size_t i = 0; i < 3; ++i) gyro_sum_[i] += g[i];
    if (++gyro_cal_count_ > kImuCalSamples) {
      std::array<double, 3> b{};
      for (std::size_t i = 0; i < 3; ++i) b[i] = gyro_sum_[i] / gyro_cal_count_;
      const bool ok = std::hypot(b[0], b[1], b[2]) < 1.0;
      if (ok)
        for (std::size_t i = 0; i < 3; ++i) params_.set_float(kGyro[i], static_cast<float>(b[i]));
      else
        log(3, "Too much movement for gyro cal");
      if (fsm_ == Fsm::calibrating) set_event(ok ? Event::cal_done : Event::cal_failed, 0);
      gyro_cal_ = false;
    }
  }
  if (!acc_cal_) return;
  const double grav[3] = {0.0, 0.0, kFirmwareGravity};
  for (std::size_t i = 0; i < 3; ++i) {
    acc_sum_[i] += a[i] + grav[i];
    acc_max_[i] = std::max<double>(acc_max_[i], a[i]);
    acc_min_[i] = std::min<double>(acc_min_[i], a[i]);
  }
  if (++imu_cal_count_ <= kImuCalSamples) return;
  acc_cal_ = false;
  std::array<double, 3> b{};
  for (std::size_t i = 0; i < 3; ++i) b[i] = acc_sum_[i] / imu_cal_count_;
  if (std::hypot(acc_max_[0] - acc_min_[0], acc_max_[1] - acc_min_[1], acc_max_[2] - acc_min_[2]) > 1.0) {
    log(3, "Too much movement for IMU cal");
  } else if (std::hypot(b[0], b[1], b[2]) < 3.0) {
    for (std::size_t i = 0; i < 3; ++i) params_.set_float(kAcc[i], static_cast<float>(b[i]));
    log(6, "IMU offsets captured");
    clear_error(kErrorUncalibratedImu);
  } else {  // "%d.%d" of the norm's integer part and thousandths, unpadded, as the firmware prints it
    const double norm = std::hypot(b[0], b[1], b[2]);
    log(3, "large accel bias: norm = " + std::to_string(static_cast<std::uint32_t>(norm)) + "." +
               std::to_string(static_cast<std::uint32_t>(norm * 1000) % 1000));
  }
}

// Sensors::run for the IMU, then the loop body of ROSflight::run: command_manager (failsafe
// takes effect every loop) and Mixer::mix_output. The first sample after boot only starts the
// clock (ROSflight::check_time_going_forwards): no mixing, the outputs stay 0.
void Firmware::imu(std::array<float, 3>& a, std::array<float, 3>& g, std::int64_t now) {
  clear_error(kErrorImuNotResponding);
  if (gyro_cal_ || acc_cal_) calibrate_imu(a, g);
  for (std::size_t i = 0; i < 3; ++i) {  // correct_imu (temperature compensation: not emulated)
    a[i] -= params_.get_float(kAcc[i]);
    g[i] -= params_.get_float(kGyro[i]);
  }
  if (!imu_seen_) {
    imu_seen_ = true;
    return;
  }
  command_run(false, now);
  mix_output();
}

// correct_baro: calibrates until done (BARO_BIAS = mean pressure, GROUND_LEVEL its altitude);
// the SMALL_BARO pressure itself is not corrected.
void Firmware::baro(float pressure, std::int64_t now) {
  if (baro_calibrated_ || !calibration_step(baro_cal_, pressure, now)) return;
  if (baro_cal_.var < kBaroMaxVar) {
    params_.set_float("BARO_BIAS", static_cast<float>(baro_cal_.mean));
    params_.set_float("GROUND_LEVEL", pressure_altitude(params_.get_float("BARO_BIAS")));
    baro_calibrated_ = true;
    log(6, "Baro ground pressure cal successful!");
  } else {
    log(3, "Too much movement for barometer ground pressure cal");
  }
  baro_cal_ = Cal{0, 0, 0, baro_cal_.last};
}

// correct_diff_pressure: calibrates until done (DIFF_PRESS_BIAS = mean), then every reading
// has DIFF_PRESS_BIAS subtracted: in wind at boot, the airspeed reads 0 afterwards.
float Firmware::diff_pressure(float pressure, std::int64_t now) {
  if (!diff_calibrated_ && calibration_step(diff_cal_, pressure, now)) {
    if (diff_cal_.var < kDiffMaxVar) {
      params_.set_float("DIFF_PRESS_BIAS", static_cast<float>(diff_cal_.mean));
      diff_calibrated_ = true;
      log(6, "Airspeed Cal Successful!");
    } else {
      log(3, "Too much movement for diff pressure cal");
    }
    diff_cal_ = Cal{0, 0, 0, diff_cal_.last};
  }
  return pressure - params_.get_float("DIFF_PRESS_BIAS");
}

// The param_change_callback listeners that matter here: Mixer (PRIMARY_MIXER, SECONDARY_MIXER,
// RC_F_AXIS -> init_mixing); RC (a switch's channel or direction -> init_switches); Sensors
// (IMU_* orientation -> init_imu: not emulated); CommandManager (FIXED_WING, FAILSAFE_THR ->
// init_failsafe).
void Firmware::param_changed(std::string_view name) {
  if (name == "PRIMARY_MIXER" || name == "SECONDARY_MIXER" || name == "RC_F_AXIS") init_mixing();
  if (name == "FIXED_WING" || name == "FAILSAFE_THR") init_failsafe();
  if (name == "RC_ATT_OVRD_CHN" || name == "RC_THR_OVRD_CHN" || name == "RC_ATT_CTRL_CHN" || name == "RC_ARM_CHN" ||
      name.rfind("SWITCH_", 0) == 0)
    log_switches();
}

}  // namespace tern::fcu::firmware
