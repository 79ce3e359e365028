// core/src/preflight.hpp: the arming checks the phase machine runs in `preflight`, before the
// takeoff (as PX4's pre-arm checks and ArduPilot's arming checks: the estimator converged and
// consistent, a GNSS fix good enough to navigate, the aircraft at rest).
//
// Each check is named and has one threshold; a failing check gives one line that says what is
// wrong and by how much ("GNSS h_acc 4.2 m > 2.5 m"). The checks read the latest messages only;
// how long they must hold, and the time-out, are the phase machine's.
#pragma once

#include <string>
#include <vector>

#include "tern/msg/all.hpp"

namespace tern::core {

struct PreflightLimits {
  double max_tilt_sigma = 0.035;    ///< rad: roll/pitch 1-sigma from State.P_diag (2 deg)
  double max_yaw_sigma = 0.17;      ///< rad: yaw 1-sigma (10 deg)
  double max_position_sigma = 5.0;  ///< m: horizontal position 1-sigma
  double max_h_acc = 2.5;           ///< m: receiver-reported horizontal accuracy (PX4 EKF2_REQ_EPH 3 m)
  double max_v_acc = 5.0;           ///< m: receiver-reported vertical accuracy (PX4 EKF2_REQ_EPV 5 m)
  int min_sats = 6;                 ///< satellites in use (PX4 EKF2_REQ_NSATS 6)
  double max_ground_speed = 2.0;    ///< m/s: at rest, or drifting in the wind without brakes; not taxiing
};

/// The failing checks, one line each; empty when the aircraft may take off. `state` is required
/// (null: "no state"); `innovations` and `gnss` are checked when given (a config without them
/// has no such check). A State without covariance (P_diag all 0: a truth or test source) skips
/// the covariance checks.
std::vector<std::string> preflight_failures(const msg::State* state, const msg::Innovations* innovations,
                                            const msg::Gnss* gnss, const PreflightLimits& limits);

}  // namespace tern::core
