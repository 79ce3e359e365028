// The FCU's power-up calibrations (see boot_calibration.hpp).
#include "tern_sim_aero/boot_calibration.hpp"

namespace tern::sim {

namespace {
/// Seconds since power-up at this sample: 0 at the first, then += dt.
double advance(double& clock, double dt) {
  clock = clock < 0 ? 0.0 : clock + dt;
  return clock;
}
}  // namespace

// Sensors::calibrate_baro / calibrate_diff_pressure: one cycle per sample more than 20 ms after
// the previous cycle; the first kDelayCycles are ignored, the next kCycles averaged (Welford);
// the cycle after them finishes (or restarts) the calibration.
bool PressureCalibration::add(double pressure, std::int64_t ms) {
  if (done || ms <= last_ms_ + 20) return false;
  last_ms_ = ms;
  ++count_;
  constexpr int D = BootCalibration::kDelayCycles, C = BootCalibration::kCycles;
  if (count_ > D + C) {
    if (var_ < max_variance) {
      done = true;
      offset = mean_;
    } else {
      ++restarts;
    }
    count_ = 0;
    mean_ = var_ = 0.0;
    return done;
  }
  if (count_ > D) {
    const double delta = pressure - mean_;
    mean_ += delta / (count_ - D);
    var_ += delta * (pressure - mean_) / (C - 1);
  }
  return false;
}

// Sensors::calibrate_gyro: the mean of the window is the bias unless its norm is 1 rad/s or more.
Eigen::Vector3d BootCalibration::gyro(const Eigen::Vector3d& raw) {
  if (!gyro_done_) {
    gyro_sum_ += raw;
    if (++gyro_count_ >= kGyroSamples) {
      const Eigen::Vector3d mean = gyro_sum_ / gyro_count_;
      if (mean.norm() < kGyroMaxBias) {
        gyro_bias_ = mean;
        gyro_done_ = true;
      } else {
        ++gyro_restarts_;
      }
      gyro_count_ = 0;
      gyro_sum_.setZero();
    }
  }
  return raw - gyro_bias_;
}

void BootCalibration::set_done(const Eigen::Vector3d& gyro_bias, double diff_offset, double ground_pressure) {
  gyro_bias_ = gyro_bias;
  gyro_done_ = diff_.done = baro_.done = true;
  diff_.offset = diff_offset;
  baro_.offset = ground_pressure;
}

// Sensors::correct_diff_pressure: the offset (DIFF_PRESS_BIAS) is subtracted once known.
double BootCalibration::diff_pressure(double raw, double dt) {
  diff_.add(raw, millis(advance(diff_clock_, dt)));
  return raw - diff_.offset;
}

double BootCalibration::baro(double raw, double dt) {
  baro_.add(raw, millis(advance(baro_clock_, dt)));
  return raw;
}

}  // namespace tern::sim
