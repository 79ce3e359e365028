// core/host/safety/failsafe.hpp: the failsafes a fixed-wing user expects (PX4's NAV_DLL_ACT, GF_ACTION,
// GPS-loss failsafe; ArduPilot Plane's FS_*/FENCE_*/AFS_*): when must the aircraft stop flying
// its mission, and what does it fly instead? Plain C++ on the standard messages (no host types),
// tested alone (tests/test_failsafe.cpp). The host (failsafe_station.hpp) feeds check() once a
// tick and turns each engagement into a mission edit for the path planner, so the usual plugins
// fly it.
//
// Positions are NED (m) relative to home = the origin of the estimate; altitudes are m above
// home (h = -p_d). Times are flight time. Each failsafe engages once, then waits until its cause
// clears (GNSS back, link heard, inside the fence) before it can engage again. Only in the air
// (`airborne`: msg::airborne(), the phase machine's climb, cruise, loiter, landing, approach or flare).
//
//   gnss_loss   no valid GNSS fix (fix_3d, finite lat/lon) on topic `gnss` for `timeout` s, or the
//               estimate has said "degraded: gnss" for `timeout` s, after a first fix was seen
//               -> loiter at the estimate's position at that moment (dead-reckoned), at its
//               altitude. GNSS back (a fresh fix and no degraded flag): logged, and the aircraft
//               keeps loitering (decision: the estimate drifted during the outage; an operator
//               resumes the mission with a mission edit, as after PX4's Hold).
//   link_loss   a ground station was heard (any request through the DDS bridge or a heartbeat:
//               Host::ground_link_heard()) and has been silent for `timeout` s -> return home
//               (loiter at home at `altitude`, default the altitude at that moment; or at the
//               nearest rally point, at its altitude, when one is nearer than home). Heard
//               again: logged; the aircraft keeps loitering at home. With terminate_after, a
//               link still lost that long after the engagement terminates the flight.
//   geofence    the estimate is farther than max_distance from home (horizontally), above
//               max_altitude, below min_altitude (once it has been above it in the air, and not
//               since the final approach or the flare, which descend through the floor by design,
//               as PX4's geofence leaves the landing out: after a go-around, once above it again)
//               or outside the zones (inside_zones: its polygons and circles, the config's or a
//               ground station's) -> by `action`: return_home (default): return inside, loiter at
//               the nearest rally point or home (nearest_rally) at the altitude clamped into
//               [min_altitude + altitude_margin, max_altitude - altitude_margin]; loiter: there,
//               at that altitude; report: the event alone. Back inside: logged; the aircraft
//               keeps loitering.
//   terminate   (link_loss.terminate_after) flight termination, PX4's and ArduPilot AFS's last
//               resort: the motor off and the surfaces set by the action:
//                 glide  delta_t 0, surfaces neutral (PX4: PWM_MAIN_FAILn at their trims)
//                 spin   delta_t 0, full up elevator, full aileron and rudder (ArduPlane's
//                        aerodynamic termination, ArduPlane/afs_plane.cpp terminate_vehicle())
//               The termination holds for the rest of the flight.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "config/failsafe_config.hpp"
#include "tern/msg/all.hpp"
#include "tern/time.hpp"

namespace tern::core {

/// What the host saw by the end of a tick.
struct FailsafeInputs {
  Nanos now = 0;
  bool airborne = false;
  const msg::State* state = nullptr;  ///< the estimate (nullptr: none yet)
  std::optional<Nanos> last_fix;      ///< when the last valid GNSS fix arrived (none: never, or no `gnss` topic)
  std::optional<Nanos> link_heard;    ///< when the ground station was last heard (none: never)
  bool landing = false;               ///< on the final approach or in the flare: min_altitude disarmed
};

/// An engagement (action loiter, return_home or terminate) or the end of a cause (action none).
struct FailsafeEvent {
  Nanos t = 0;
  std::string cause;                                 ///< gnss_loss, gnss_back, link_loss, link_back, geofence, geofence_inside, terminate
  std::string action;                                ///< loiter, return_home, terminate, report (a geofence breach reported only), none
  std::string detail;                                ///< one line for the log and summary.json
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< loiter/return_home: orbit centre NED, m
  double radius = 0.0;                               ///< m (0: the path manager's turn radius)
  TerminateAction terminate = TerminateAction::glide;
};

/// The termination command of `action` (max_deflection: rad, the surfaces' stop).
msg::Actuators termination_command(TerminateAction action, double max_deflection);

class FailsafeMonitor {
 public:
  void set_config(const FailsafeConfig& c) { config_ = c; }
  const FailsafeConfig& config() const { return config_; }
  /// The geofence is breached now (engaged, not yet back inside).
  bool fence_breached() const { return fence_breached_at_.has_value(); }
  /// A new flight: nothing engaged, nothing seen.
  void restart();
  /// The events of this tick, in the order gnss, link, geofence.
  std::vector<FailsafeEvent> check(const FailsafeInputs& in);

 private:
  void gnss(const FailsafeInputs& in, std::vector<FailsafeEvent>& out);
  void link(const FailsafeInputs& in, std::vector<FailsafeEvent>& out);
  void geofence(const FailsafeInputs& in, std::vector<FailsafeEvent>& out);
  enum class Breach { none, max_distance, max_altitude, min_altitude, zone };
  /// The first fence limit the estimate is beyond (checked every tick: no formatting).
  Breach fence_breach(const msg::State& s) const;
  /// Where a return from (n, e) `from` goes: the nearest rally point (its altitude through
  /// `clamp_h`) or home (at `home_h`), and those words for the event.
  struct Return {
    Eigen::Vector3d centre;  // NED m
    std::string detail;
  };
  Return return_point(const Eigen::Vector2d& from, double home_h, const std::function<double(double)>& clamp_h) const;
  /// `b` in words with the estimate's figures, for the event.
  std::string describe(Breach b, const msg::State& s) const;

  FailsafeConfig config_;
  std::optional<Eigen::Vector3d> last_position_;  // the last valid estimate, NED m
  std::optional<Nanos> gnss_lost_at_, degraded_since_;
  std::optional<Nanos> link_lost_at_;
  bool terminated_ = false;
  std::optional<Nanos> fence_breached_at_;
  bool floor_armed_ = false;  // above min_altitude in the air once (since the last landing)
};

}  // namespace tern::core
