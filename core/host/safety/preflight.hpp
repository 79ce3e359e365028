// core/host/safety/preflight.hpp: the arming checks the phase machine runs in `preflight`, before the
// takeoff (as PX4's pre-arm checks and ArduPilot's arming checks: the FCU armed and error-free,
// the estimator converged and consistent with every sensor alive, a GNSS fix good enough to
// navigate, the aircraft at rest, the pilot's transmitter heard when required).
//
// Each check is named and has one threshold; a failing check gives one line that says what is
// wrong and by how much ("GNSS h_acc 4.2 m > 2.5 m"). The checks read the latest messages only;
// how long they must hold, and the time-out, are the phase machine's.
//
// Sensors: the estimator times out a silent sensor, and counts a non-finite sample as none
// (estimator_ekf health.cpp), so a dead or NaN sensor shows as a State that is not ok, named
// by State.degraded_sensors.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "tern/msg/all.hpp"

namespace tern::core {

struct PreflightLimits {
  /// rad: roll/pitch 1-sigma from State.P_diag (2.3 deg): 2 deg of alignment, root-sum-square with
  /// the 1-deg mounting uncertainty an estimator publishes on top (estimator_ekf's imu_mount_sigma)
  double max_tilt_sigma = 0.04;
  double max_yaw_sigma = 0.17;  ///< rad: yaw 1-sigma (10 deg)
  /// rad/s: gyro-bias 1-sigma per axis (0.29 deg/s: 10 s of takeoff at this error turn the
  /// attitude by 3 deg; the FCU's boot calibration and a few seconds at rest get below it)
  double max_gyro_bias_sigma = 0.005;
  double max_position_sigma = 5.0;  ///< m: horizontal position 1-sigma
  double max_h_acc = 2.5;           ///< m: receiver-reported horizontal accuracy (PX4 EKF2_REQ_EPH 3 m)
  double max_v_acc = 5.0;           ///< m: receiver-reported vertical accuracy (PX4 EKF2_REQ_EPV 5 m)
  int min_sats = 6;                 ///< satellites in use (PX4 EKF2_REQ_NSATS 6)
  double max_ground_speed = 2.0;    ///< m/s: at rest, or drifting in the wind without brakes; not taxiing
  bool require_rc = false;          ///< the pilot's transmitter must be heard (a safety pilot's flight)
  double max_rc_age = 0.5;          ///< s: the newest RC frame at most this old (rosflight RC_LOSS is 100 ms)
  /// m/s: the wind the vehicle can see at rest (the pitot's airspeed: the headwind; the
  /// estimate's wind) above this is beyond the aircraft's takeoff limits. 10 m/s: 60 % of the
  /// Anaconda's 17 m/s cruise, the upper end of the winds the shipped campaigns fly in. A tailwind
  /// or a crosswind at rest is not seen by a pitot (and barely by the estimate): the check can
  /// only say what the vehicle measures. Checked on an estimator's state (one with a covariance).
  double max_wind = 10.0;
};

/// The latest messages the checks read; null (or nullopt) where none has arrived or the config
/// has no such topic. `state` is required ("no state"); `fcu` and `rc_age` are checked when the
/// config has an FCU status or requires RC; `innovations` and `gnss` when given.
struct PreflightInputs {
  const msg::State* state = nullptr;
  const msg::Innovations* innovations = nullptr;
  const msg::Gnss* gnss = nullptr;
  const msg::FcuStatus* fcu = nullptr;
  std::optional<double> rc_age;  ///< s since the newest RC frame (nullopt: none yet)
};

/// The failing checks, one line each; empty when the aircraft may take off. A State without
/// covariance (P_diag all 0: a truth or test source) skips the covariance checks.
std::vector<std::string> preflight_failures(const PreflightInputs& in, const PreflightLimits& limits);

/// The FCU's part of the checks alone (armed, no error), for the wait after a disarm in flight.
std::optional<std::string> fcu_not_ready(const msg::FcuStatus& fcu);

}  // namespace tern::core
