// core/apps/mavlink/telemetry.hpp: what the MAVLink endpoint shows a ground station, as pure
// functions of a snapshot of the host's topics (gcs_link.hpp copies it on the flight thread).
//
// Sources: every field comes from the vehicle's side (the estimate on `state`, never truth; the
// commands on `controller_command` / `controller_internals`, the path on `current_path` and
// `waypoints`, the phase on `flight_phase`). The mapping of each message's fields, and what tern
// does not send: docs/ground-station.md. Message definitions: common.xml (mavlink_messages.hpp).
//
// Frames and units are MAVLink's: NED, degrees where the message says deg, degE7, mm, cm/s.
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <string>

#include <Eigen/Core>

#include "flight/flight_topics.hpp"
#include "mavlink/mavlink_codec.hpp"
#include "mavlink/mavlink_messages.hpp"
#include "tern/geodesy.hpp"
#include "tern/msg/all.hpp"

namespace tern::core::mavlink {

/// The latest of what the GCS is shown: the watched topics (flight/flight_topics.hpp), copied on the flight thread.
struct Snapshot : FlightTopics {
  bool any = false;  ///< a flight has ticked since the link started (t: MAVLink's "time since boot")
  /// The mission: items on `waypoints` (nullopt: none published since the link started; a served
  /// host's last list between flights), and the waypoint current_path flies to
  /// (path.waypoint_index), as published (NED, or lat/lon/alt when lla).
  std::optional<std::uint32_t> mission_items;
  std::optional<msg::Waypoint> target;
  /// The geofence: on with a limit, and breached now (Host::fence_status()).
  bool fence_enabled = false, fence_breached = false;
};

/// HEARTBEAT: MAV_TYPE_FIXED_WING; custom_mode is tern's Phase code (tern/msg/phase.hpp); armed
/// in a flight's airborne phases (not preflight, not stopped); manual input when the RC override
/// switch is on; CRITICAL in an RC failsafe. `flying`: Host::flying().
Heartbeat heartbeat(const Snapshot& s, bool flying);
/// SYS_STATUS: the sensors present (topics with a producer: `topics`), unhealthy when the
/// estimator reports them degraded; the geofence (MAV_SYS_STATUS_GEOFENCE) present and enabled
/// when on, unhealthy while breached; link drops from `link` (bad datagrams / all seen).
SysStatus sys_status(const Snapshot& s, const std::set<std::string>& topics, const Counters& link);
Attitude attitude(const Snapshot& s);
/// GLOBAL_POSITION_INT: the estimate's NED position about its origin, through `origin` (a cache
/// of the GeographicLib projection, replaced when the origin moves).
GlobalPositionInt global_position(const Snapshot& s, std::optional<GeoOrigin>& origin);
VfrHud vfr_hud(const Snapshot& s);
GpsRawInt gps_raw(const Snapshot& s);
HomePosition home(const Snapshot& s);
/// NAV_CONTROLLER_OUTPUT (62): nav_roll / nav_pitch the inner loops' phi_c / theta_c (deg),
/// nav_bearing the course command chi_c (deg), alt_error h_c - h and aspd_error Va_c - Va (the
/// commands less the estimate), xtrack_error the lateral path error (uavbook section 10.1: e_py
/// on a line, distance to the orbit's circle on an orbit; m, positive right of the path / outside
/// the orbit), target_bearing and wp_dist to the waypoint flown to (deg, m; 0 when none).
/// nullopt before the follower and the controller have published.
std::optional<NavControllerOutput> nav_controller(const Snapshot& s, std::optional<GeoOrigin>& origin);
/// MISSION_CURRENT (42): seq the waypoint flown to, total the mission's items; mission_state
/// NO_MISSION (no items), NOT_STARTED (preflight), COMPLETE (stopped), else ACTIVE; mission_mode
/// 1 (in mission) or 2 (suspended: the pilot's RC override). nullopt when nothing publishes
/// `waypoints`.
std::optional<MissionCurrent> mission_current(const Snapshot& s);
/// WIND_COV (231): the estimate's wind (north, east; down NaN: tern's filter does not estimate
/// it), horiz_accuracy sqrt(var_n + var_e) from the filter's covariance (0 when it has none).
std::optional<WindCov> wind_cov(const Snapshot& s);
/// EXTENDED_SYS_STATE (245): landed_state from the phase: preflight and stopped ON_GROUND,
/// takeoff TAKEOFF, approach / flare / rollout / landing LANDING, else IN_AIR.
std::optional<ExtendedSysState> extended_sys_state(const Snapshot& s);

}  // namespace tern::core::mavlink
