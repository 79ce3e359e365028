// core/host/safety/state_loss_recovery.hpp: the phase router's built-in state-loss recovery: what flies
// the aircraft while the estimate is invalid (State.valid false) after the climb-out. Plain C++
// on the standard messages (no host types).
//
// No controller can fly on an invalid estimate, so the router publishes this command instead:
//   delta_e  the trim: the controllers' recent elevator (first-order average over `trim_tau` s
//            of the good commands), held fixed: the pitch the aircraft was trimmed for;
//   delta_t  the trim throttle plus `throttle_up` (at most 1): a gentle climb away from the ground;
//   delta_r  the trim rudder;
//   delta_a  wings level on the rate gyros (the raw `imu` topic, bias from the last valid estimate):
//            roll phi = phi at the loss + integral of p, delta_a = trim - roll_kp phi - roll_kd p;
//            while the IMU itself is silent: the trim aileron.
// Units: rad for surfaces, 0..1 throttle, s for times.
#pragma once

#include <optional>

#include "tern/msg/all.hpp"
#include "tern/time.hpp"

namespace tern::core {

struct RecoveryGains {
  /// s: the trim average spans several phugoid-free seconds of cruise, long against the 1-2 s
  /// corrections of a gust, short against a turn onto a new leg (the slc's course loop, 1.6 rad/s).
  double trim_tau = 2.0;
  /// Throttle added to the trim: the anaconda's cruise trim is 0.57 (configs/gains/anaconda.yaml
  /// trim_t); +0.2 climbs at about 1.5 m/s at a fixed elevator (a gentle climb, not a stall).
  double throttle_up = 0.2;
  /// rad of aileron per rad of roll, and per rad/s of roll rate. With the anaconda's roll model
  /// (a_phi1 25.7, a_phi2 137.9 1/s^2, configs/gains/anaconda.yaml) the loop's poles are real,
  /// the slower at 2 rad/s: wings level in about 2 s without overshoot on integrated gyros.
  double roll_kp = 0.5, roll_kd = 0.1;
  double max_deflection = 0.7;  ///< rad, the phase machine's max_deflection
};

class StateLossRecovery {
 public:
  void set_gains(const RecoveryGains& g) { gains_ = g; }
  /// A new flight: no trim yet, not recovering.
  void restart();
  /// A good command of the active controller at `now` (and the valid estimate beside it): the trim.
  void observe(Nanos now, const msg::Actuators& a, const msg::State* s);
  /// Starts recovering at `now` from the last valid estimate.
  void begin(Nanos now);
  bool active() const { return active_; }
  void end() { active_ = false; }
  /// The command at `now`; `imu`: the newest IMU sample when one arrived since the last call.
  msg::Actuators command(Nanos now, const msg::Imu* imu);

 private:
  RecoveryGains gains_;
  std::optional<msg::Actuators> trim_;
  Nanos trim_t_ = 0;
  double phi0_ = 0, b_x_ = 0;  // roll and gyro-x bias of the last valid estimate
  double phi_ = 0;             // rad, integrated from the gyros since the loss
  Nanos imu_t_ = -1;           // stamp of the last gyro sample integrated
  double delta_a_ = 0;         // rad, the aileron of the last gyro sample
  bool active_ = false;
};

}  // namespace tern::core
