// core/host/config/failsafe_config.hpp: the mission config's `failsafes:` section (failsafe.hpp says
// what each failsafe does). Every key is optional; units: s, m (altitudes above home, NED (n, e)
// polygon vertices relative to home).
//
//   failsafes:
//     gnss_loss: {enabled: true, timeout: 5, radius: 0}
//     link_loss: {enabled: true, timeout: 10, altitude: 80, radius: 0,
//                 terminate: {after: 120, action: glide}}        # action: glide | spin
//     geofence:  {max_distance: 500, min_altitude: 20, max_altitude: 150,
//                 polygon: [[600, -400], [600, 400], [-600, 400], [-600, -400]],
//                 altitude_margin: 10, radius: 0, action: return_home}  # report | loiter | return_home
//     rally: [[300, 200, 80]]       # (n, e, altitude above home) m: returns go to the nearest or home
//
// Defaults (FailsafeConfig): gnss_loss on (5 s), link_loss on (10 s; it only acts once a ground
// station has been heard), no termination, no geofence (a `geofence:` section turns it on;
// enabled: false turns it off again). A radius of 0 leaves the orbit radius to the path manager.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace YAML {
class Node;
}

namespace tern::core {

struct GnssLossConfig {
  bool enabled = true;
  /// s: PX4's COM_POS_FS_DELAY is 1 s; 5 s lets a few lost fixes of a 5-10 Hz receiver (and the
  /// estimator's own gnss_timeout) pass without leaving the mission.
  double timeout = 5.0;
  double radius = 0.0;  ///< m of the loiter, >= 0 (0: the path manager's turn radius)
};

enum class TerminateAction { glide, spin };

struct LinkLossConfig {
  /// on when the config gives the section (PX4's NAV_DLL_ACT and ArduPlane's FS_GCS_ENABL ship
  /// off: a `tern param get` followed by silence must not send the aircraft home); then only
  /// once a ground station has been heard
  bool enabled = false;
  double timeout = 10.0;                  ///< s: PX4's COM_DL_LOSS_T default
  std::optional<double> altitude;         ///< m above home of the loiter at home (none: the altitude at the loss)
  double radius = 0.0;                    ///< m of the loiter, >= 0 (0: the path manager's turn radius)
  std::optional<double> terminate_after;  ///< s after the engagement, link still lost (none: never)
  TerminateAction terminate_action = TerminateAction::glide;
};

/// One zone of the geofence: a polygon or a circle, (n, e) m about home, that the aircraft must stay
/// inside (inclusion) or outside (exclusion). MAVLink's FENCE items
/// (https://mavlink.io/en/services/geofence.html: MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION /
/// _EXCLUSION, MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION / _EXCLUSION) upload them; the config's
/// `polygon:` is one inclusion polygon of group 0.
struct FenceZone {
  bool inclusion = true;
  std::uint32_t group = 0;                           ///< inclusion group (common.xml: inside all zones of one group)
  std::vector<Eigen::Vector2d> polygon;              ///< (n, e) m vertices in order, >= 3; empty: the circle below
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< a circle's centre (n, e) m
  double radius = 0.0;                               ///< a circle's radius, m > 0
  bool contains(const Eigen::Vector2d& p) const;
};

/// Whether (n, e) is allowed by `zones`, common.xml's rule for FENCE items: inside every inclusion
/// zone of at least one group (when there is an inclusion zone at all) and inside no exclusion zone.
bool inside_zones(const std::vector<FenceZone>& zones, const Eigen::Vector2d& p);

/// What a breach does (PX4's GF_ACTION, ArduPlane's FENCE_ACTION): report (a warning, the mission
/// goes on), loiter where the breach was, or return_home (to the nearest rally point or home).
enum class FenceAction { report, loiter, return_home };

struct GeofenceConfig {
  bool enabled = false;                              ///< on when the config gives the section, or a ground station uploads zones
  std::optional<double> max_distance;                ///< m from home, horizontal
  std::optional<double> min_altitude, max_altitude;  ///< m above home
  std::vector<FenceZone> zones;                      ///< polygons and circles (the config's `polygon`, a ground station's FENCE)
  double altitude_margin = 10.0;                     ///< m inside the altitude limits for the loiter at home
  double radius = 0.0;                               ///< m of the loiter, >= 0 (0: the path manager's turn radius)
  FenceAction action = FenceAction::return_home;
  /// Any limit at all (a distance, an altitude, a zone).
  bool limits() const { return max_distance || min_altitude || max_altitude || !zones.empty(); }
};

/// Whether (n, e) lies inside the polygon (ray casting; a point on an edge may go either way).
bool inside_polygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p);

struct FailsafeConfig {
  GnssLossConfig gnss_loss;
  LinkLossConfig link_loss;
  GeofenceConfig geofence;
  /// Rally points (n, e, altitude above home; m): a return (link loss, geofence, a ground
  /// station's RTL) flies to the nearest of them and home, as ArduPlane's RALLY_INCL_HOME and
  /// PX4's RTL_TYPE 0 do. The config's `failsafes.rally`, or a ground station's RALLY items.
  std::vector<Eigen::Vector3d> rally;
};

/// The rally point a return from (n, e) flies to: the nearest (horizontally) of `rally` that the
/// fence allows (inside_zones), unless home is nearer or as near; nullopt: home.
std::optional<std::size_t> nearest_rally(const std::vector<Eigen::Vector3d>& rally, const std::vector<FenceZone>& zones,
                                         const Eigen::Vector2d& from);

/// Reads `section` (null: the defaults) of config `file`. Throws ConfigError, one line naming
/// file:line:col, the field (e.g. "failsafes.geofence.max_distance") and the bad value; also for
/// a geofence that leaves home outside (a polygon around home, max_distance > 0, min < max).
FailsafeConfig parse_failsafes(const YAML::Node& section, const std::filesystem::path& file);

}  // namespace tern::core
