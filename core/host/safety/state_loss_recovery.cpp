#include "safety/state_loss_recovery.hpp"

#include <algorithm>
#include <cmath>

namespace tern::core {

void StateLossRecovery::restart() {
  trim_.reset();
  trim_t_ = 0;
  phi0_ = b_x_ = phi_ = delta_a_ = 0;
  imu_t_ = -1;
  active_ = false;
}

void StateLossRecovery::observe(Nanos now, const msg::Actuators& a, const msg::State* s) {
  if (s != nullptr && s->valid) {
    phi0_ = s->phi;
    b_x_ = s->b_x;
  }
  if (!trim_) {
    trim_ = a;
    trim_t_ = now;
    return;
  }
  const double k = 1.0 - std::exp(-to_seconds(now - trim_t_) / gains_.trim_tau);  // exact for a held command
  trim_t_ = now;
  trim_->delta_a += k * (a.delta_a - trim_->delta_a);
  trim_->delta_e += k * (a.delta_e - trim_->delta_e);
  trim_->delta_r += k * (a.delta_r - trim_->delta_r);
  trim_->delta_t += k * (a.delta_t - trim_->delta_t);
}

void StateLossRecovery::begin(Nanos now) {
  active_ = true;
  phi_ = phi0_;
  imu_t_ = now;
  delta_a_ = trim_ ? trim_->delta_a : 0.0;
}

msg::Actuators StateLossRecovery::command(Nanos now, const msg::Imu* imu) {
  const msg::Actuators trim = trim_.value_or(msg::Actuators{});
  msg::Actuators a = trim;
  a.stamp = now;
  a.delta_t = std::min(1.0, trim.delta_t + gains_.throttle_up);
  if (imu != nullptr && imu->stamp > imu_t_) {
    const double p = imu->gyro.x() - b_x_;
    phi_ += p * to_seconds(imu->stamp - imu_t_);
    imu_t_ = imu->stamp;
    const double lim = gains_.max_deflection;
    delta_a_ = std::clamp(trim.delta_a - gains_.roll_kp * phi_ - gains_.roll_kd * p, -lim, lim);
  }
  a.delta_a = delta_a_;  // held between gyro samples, and while the IMU is silent
  return a;
}

}  // namespace tern::core
