// core/host/record/landing_report.hpp: how the aircraft touched down, measured on the simulator's
// truth (summary.json "landing", the console's landing line; the flight metrics feed it).
//
// The touchdown point is the land item's position (the mission's NED, m, about home) placed at the
// aircraft's true position at rest before the takeoff (home, in the truth's frame): the point a
// researcher would mark on the field, not the estimate's idea of it. The touchdown is the first
// truth sample in the flare or rollout whose CG height is within kContactMargin of its height at
// rest on the wheels (the gear compressed by its static deflection, ~2 cm); the sink rate at
// touchdown is the largest true sink rate in the kSinkWindow before it (the gear brakes the
// sink once the wheels touch). Along and across are in the runway's frame (the land item's
// heading): along > 0 long (beyond the touchdown point), across > 0 right of the centre line. The
// rollout length runs from the touchdown point to where the aircraft stopped (its true ground speed
// below kStoppedSpeed) or was at the end.
#pragma once

#include <cmath>
#include <deque>
#include <optional>
#include <utility>

#include <Eigen/Core>

#include "tern/msg/all.hpp"

namespace tern::core {

struct Touchdown {
  double t_s = std::nan("");
  double along_m = std::nan(""), across_m = std::nan("");
  double sink_rate_mps = std::nan(""), airspeed_mps = std::nan(""), ground_speed_mps = std::nan("");
  double roll_deg = std::nan(""), pitch_deg = std::nan("");
  double rollout_m = std::nan("");
  bool stopped = false;
};

class LandingReport {
 public:
  static constexpr double kContactMargin = 0.03;  ///< m above the CG's height at rest
  static constexpr double kSinkWindow = 0.3;      ///< s before the touchdown
  static constexpr double kStoppedSpeed = 0.5;    ///< m/s: the aircraft has stopped

  /// One truth sample at flight time `now` in `phase`; `wps`: the mission (its land item).
  void observe(Nanos now, msg::Phase phase, const msg::State& truth, const msg::WaypointList* wps);
  /// The touchdown, once there was one.
  const std::optional<Touchdown>& touchdown() const { return td_; }

 private:
  std::optional<Eigen::Vector3d> home_;  ///< truth position at rest before the takeoff
  std::optional<Touchdown> td_;
  Eigen::Vector2d td_point_ = Eigen::Vector2d::Zero();
  double heading_ = 0.0;
  std::deque<std::pair<Nanos, double>> sinks_;  ///< (time, true v_d) over the window before now
  bool have_target_ = false;
  Eigen::Vector2d target_ = Eigen::Vector2d::Zero();
};

}  // namespace tern::core
