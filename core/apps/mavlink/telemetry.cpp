// core/apps/mavlink/telemetry.cpp: the messages a ground station is shown (telemetry.hpp).
#include "mavlink/telemetry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tern/math.hpp"

namespace tern::core::mavlink {
namespace {

std::int32_t deg_e7(double deg) { return static_cast<std::int32_t>(std::llround(deg * 1e7)); }
std::int32_t mm(double m) { return static_cast<std::int32_t>(std::llround(m * 1000.0)); }
std::int16_t cm_s(double v) { return static_cast<std::int16_t>(std::clamp(std::lround(v * 100.0), -32767L, 32767L)); }
/// An angle in rad as centidegrees [0, 36000).
std::uint16_t cdeg(double rad) { return static_cast<std::uint16_t>(std::lround(wrap_2pi(rad) * kDegPerRad * 100.0) % 36000); }
/// An angle in rad as whole degrees [0, 360).
std::int16_t deg(double rad) { return static_cast<std::int16_t>(cdeg(rad) / 100); }
std::uint32_t boot_ms(const Snapshot& s) { return static_cast<std::uint32_t>(s.t / 1'000'000); }

bool airborne_phase(msg::Phase p) { return p != msg::Phase::preflight && p != msg::Phase::stopped; }

/// The waypoint's NED position about the estimate's origin (lat/lon/alt ones through `origin`).
std::optional<Eigen::Vector3d> target_ned(const Snapshot& s, std::optional<GeoOrigin>& origin) {
  if (!s.target) return std::nullopt;
  const msg::Waypoint& w = *s.target;
  if (w.type == msg::Waypoint::return_home) return Eigen::Vector3d(0.0, 0.0, w.lla ? 0.0 : w.w.z());
  if (!w.lla) return w.w;
  if (!s.state.origin_valid) return std::nullopt;
  const GeoPoint o{s.state.origin_lat, s.state.origin_lon, s.state.origin_alt};
  if (!origin || origin->origin() != o) origin.emplace(o);
  return origin->to_ned(w.w.x(), w.w.y(), w.w.z());
}

/// Lateral error from the current path, m (uavbook section 10.1 for a line: e_py, positive right
/// of the line's direction; an orbit: distance from its circle, positive outside).
double xtrack(const msg::CurrentPath& path, const msg::State& x) {
  const Eigen::Vector2d p(x.p_n, x.p_e);
  if (path.path_type == msg::CurrentPath::orbit) return (p - path.c.head<2>()).norm() - path.rho;
  const double chi_q = std::atan2(path.q.y(), path.q.x());
  const Eigen::Vector2d d = p - path.r.head<2>();
  return -std::sin(chi_q) * d.x() + std::cos(chi_q) * d.y();
}

}  // namespace

Heartbeat heartbeat(const Snapshot& s, bool flying) {
  Heartbeat h;
  h.type = MAV_TYPE_FIXED_WING;
  h.autopilot = MAV_AUTOPILOT_GENERIC;
  if (!s.any || !s.has_phase) {
    h.system_status = s.any && flying ? MAV_STATE_BOOT : MAV_STATE_STANDBY;
    return h;
  }
  h.custom_mode = static_cast<std::uint32_t>(s.phase.phase);  // tern's Phase code (tern/msg/phase.hpp)
  h.base_mode = MAV_MODE_FLAG_CUSTOM_MODE_ENABLED;
  const bool armed = flying && airborne_phase(s.phase.phase);
  if (armed) {
    h.base_mode |= MAV_MODE_FLAG_SAFETY_ARMED;
    if (s.has_rc && s.rc.rc_override)
      h.base_mode |= MAV_MODE_FLAG_MANUAL_INPUT_ENABLED;
    else
      h.base_mode |= MAV_MODE_FLAG_STABILIZE_ENABLED | MAV_MODE_FLAG_GUIDED_ENABLED | MAV_MODE_FLAG_AUTO_ENABLED;
  }
  h.system_status = !armed ? MAV_STATE_STANDBY : (s.has_rc && s.rc.failsafe) ? MAV_STATE_CRITICAL : MAV_STATE_ACTIVE;
  return h;
}

SysStatus sys_status(const Snapshot& s, const std::set<std::string>& topics, const Counters& link) {
  SysStatus m;
  const auto has = [&topics](const char* t) { return topics.count(t) != 0; };
  std::uint32_t present = 0, unhealthy = 0;
  const std::uint8_t degraded = s.has_state ? s.state.degraded_sensors : 0;
  const auto sensor = [&](const char* topic, std::uint32_t bits, std::uint8_t sensor_bit) {
    if (!has(topic)) return;
    present |= bits;
    if ((degraded & sensor_bit) != 0) unhealthy |= bits;
  };
  sensor("imu", MAV_SYS_STATUS_SENSOR_3D_GYRO | MAV_SYS_STATUS_SENSOR_3D_ACCEL, msg::sensor_bit::imu);
  sensor("mag", MAV_SYS_STATUS_SENSOR_3D_MAG, msg::sensor_bit::mag);
  sensor("baro", MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE, msg::sensor_bit::baro);
  sensor("diff_pressure", MAV_SYS_STATUS_SENSOR_DIFFERENTIAL_PRESSURE, msg::sensor_bit::diff_pressure);
  sensor("gnss", MAV_SYS_STATUS_SENSOR_GPS, msg::sensor_bit::gnss);
  if (has("state")) {
    present |= MAV_SYS_STATUS_AHRS;
    if (!s.has_state || !s.state.valid) unhealthy |= MAV_SYS_STATUS_AHRS;
  }
  if (has("actuators"))
    present |= MAV_SYS_STATUS_SENSOR_ANGULAR_RATE_CONTROL | MAV_SYS_STATUS_SENSOR_ATTITUDE_STABILIZATION |
               MAV_SYS_STATUS_SENSOR_YAW_POSITION | MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL | MAV_SYS_STATUS_SENSOR_XY_POSITION_CONTROL;
  if (has("rc")) {
    present |= MAV_SYS_STATUS_SENSOR_RC_RECEIVER;
    if (s.has_rc && s.rc.failsafe) unhealthy |= MAV_SYS_STATUS_SENSOR_RC_RECEIVER;
  }
  if (s.fence_enabled) {
    present |= MAV_SYS_STATUS_GEOFENCE;
    if (s.fence_breached) unhealthy |= MAV_SYS_STATUS_GEOFENCE;
  }
  m.onboard_control_sensors_present = present;
  m.onboard_control_sensors_enabled = present;
  m.onboard_control_sensors_health = present & ~unhealthy;
  m.voltage_battery = UINT16_MAX;  // no battery: the XML's invalid values
  m.current_battery = -1;
  m.battery_remaining = -1;
  const std::uint64_t seen = link.frames + link.dropped();
  m.drop_rate_comm = seen == 0 ? 0 : static_cast<std::uint16_t>(std::min<std::uint64_t>(10000, link.dropped() * 10000 / seen));
  m.errors_comm = static_cast<std::uint16_t>(std::min<std::uint64_t>(UINT16_MAX, link.dropped()));
  return m;
}

Attitude attitude(const Snapshot& s) {
  const auto& x = s.state;
  return {boot_ms(s),
          static_cast<float>(x.phi),
          static_cast<float>(x.theta),
          static_cast<float>(x.psi),
          static_cast<float>(x.p),
          static_cast<float>(x.q),
          static_cast<float>(x.r)};
}

GlobalPositionInt global_position(const Snapshot& s, std::optional<GeoOrigin>& origin) {
  const auto& x = s.state;
  const GeoPoint o{x.origin_lat, x.origin_lon, x.origin_alt};
  if (!origin || origin->origin() != o) origin.emplace(o);
  const GeoPoint g = origin->to_geodetic(Eigen::Vector3d(x.p_n, x.p_e, x.p_d));
  GlobalPositionInt m;
  m.time_boot_ms = boot_ms(s);
  m.lat = deg_e7(g.lat);
  m.lon = deg_e7(g.lon);
  m.alt = mm(g.alt);
  m.relative_alt = mm(-x.p_d);  // home is the estimate's origin
  m.vx = cm_s(x.v_n);
  m.vy = cm_s(x.v_e);
  m.vz = cm_s(x.v_d);
  m.hdg = cdeg(x.psi);
  return m;
}

VfrHud vfr_hud(const Snapshot& s) {
  const auto& x = s.state;
  VfrHud m;
  m.airspeed = static_cast<float>(x.Va);
  m.groundspeed = static_cast<float>(x.Vg);
  m.alt = static_cast<float>(x.origin_alt - x.p_d);
  m.climb = static_cast<float>(-x.v_d);
  m.heading = deg(x.psi);
  m.throttle = s.has_actuators ? static_cast<std::uint16_t>(std::lround(std::clamp(s.actuators.delta_t, 0.0, 1.0) * 100.0)) : 0;
  return m;
}

GpsRawInt gps_raw(const Snapshot& s) {
  const auto& g = s.gnss;
  GpsRawInt m;
  m.time_usec = static_cast<std::uint64_t>(g.stamp / 1000);
  switch (g.fix_type) {
    case msg::FixType::none:
    case msg::FixType::dead_reckoning: m.fix_type = GPS_FIX_TYPE_NO_FIX; break;
    case msg::FixType::fix_2d: m.fix_type = GPS_FIX_TYPE_2D_FIX; break;
    case msg::FixType::fix_3d: m.fix_type = GPS_FIX_TYPE_3D_FIX; break;
  }
  m.lat = deg_e7(g.lat);
  m.lon = deg_e7(g.lon);
  m.alt = mm(g.alt);
  const double v = std::hypot(g.vel.x(), g.vel.y());
  m.vel = static_cast<std::uint16_t>(std::min(65534L, std::lround(v * 100.0)));
  m.cog = v > 0.5 ? cdeg(std::atan2(g.vel.y(), g.vel.x())) : UINT16_MAX;  // below 0.5 m/s the course is noise
  m.satellites_visible = g.num_sats;
  const auto dop = [](double d) {  // GPS_RAW_INT's eph/epv: the DOP x 100, UINT16_MAX when unknown
    return d > 0.0 && std::isfinite(d) ? static_cast<std::uint16_t>(std::min(65534L, std::lround(d * 100.0))) : std::uint16_t{UINT16_MAX};
  };
  m.eph = dop(g.hdop);
  m.epv = dop(g.vdop);
  return m;
}

HomePosition home(const Snapshot& s) {
  HomePosition m;
  m.latitude = deg_e7(s.state.origin_lat);
  m.longitude = deg_e7(s.state.origin_lon);
  m.altitude = mm(s.state.origin_alt);
  m.q = {1, 0, 0, 0};  // identity (w, x, y, z)
  return m;            // x y z 0: home is the local frame's origin; no approach vector
}

std::optional<NavControllerOutput> nav_controller(const Snapshot& s, std::optional<GeoOrigin>& origin) {
  if (!s.has_state || !s.has_command || !s.has_internals) return std::nullopt;
  const auto& x = s.state;
  const auto& c = s.command;
  NavControllerOutput m;
  m.nav_roll = static_cast<float>((c.override_phi ? c.phi_c : s.internals.phi_c) * kDegPerRad);
  m.nav_pitch = static_cast<float>((c.override_theta ? c.theta_c : s.internals.theta_c) * kDegPerRad);
  m.nav_bearing = deg(c.chi_c);
  m.alt_error = static_cast<float>(c.h_c - x.altitude());
  m.aspd_error = static_cast<float>(c.Va_c - x.Va);
  if (s.has_path) m.xtrack_error = static_cast<float>(xtrack(s.path, x));
  if (const auto w = target_ned(s, origin)) {
    const Eigen::Vector2d d = w->head<2>() - Eigen::Vector2d(x.p_n, x.p_e);
    m.target_bearing = deg(std::atan2(d.y(), d.x()));
    m.wp_dist = static_cast<std::uint16_t>(std::min(65535L, std::lround(d.norm())));
  }
  return m;
}

std::optional<MissionCurrent> mission_current(const Snapshot& s) {
  if (!s.mission_items) return std::nullopt;
  MissionCurrent m;
  m.total = static_cast<std::uint16_t>(std::min<std::uint32_t>(*s.mission_items, UINT16_MAX - 1));
  if (s.has_path && s.path.waypoint_index >= 0)
    m.seq = static_cast<std::uint16_t>(std::min<std::int32_t>(s.path.waypoint_index, UINT16_MAX));
  if (*s.mission_items == 0)
    m.mission_state = MISSION_STATE_NO_MISSION;
  else if (!s.has_phase)
    m.mission_state = MISSION_STATE_UNKNOWN;
  else if (s.phase.phase == msg::Phase::preflight)
    m.mission_state = MISSION_STATE_NOT_STARTED;
  else if (s.phase.phase == msg::Phase::stopped)
    m.mission_state = MISSION_STATE_COMPLETE;
  else
    m.mission_state = MISSION_STATE_ACTIVE;
  m.mission_mode = s.has_rc && s.rc.rc_override ? 2 : 1;
  return m;
}

std::optional<WindCov> wind_cov(const Snapshot& s) {
  if (!s.has_state || !s.state.valid) return std::nullopt;
  const auto& x = s.state;
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  constexpr std::size_t wind_n = msg::State::P_wind, wind_e = msg::State::P_wind + 1;
  WindCov m;
  m.time_usec = static_cast<std::uint64_t>(s.t / 1000);
  m.wind_x = static_cast<float>(x.w_n);
  m.wind_y = static_cast<float>(x.w_e);
  m.wind_z = nan;
  m.var_horiz = nan;
  m.var_vert = nan;
  m.wind_alt = static_cast<float>(x.origin_alt - x.p_d);
  m.horiz_accuracy = static_cast<float>(std::sqrt(std::max(0.0, x.P_diag[wind_n] + x.P_diag[wind_e])));
  return m;
}

std::optional<ExtendedSysState> extended_sys_state(const Snapshot& s) {
  if (!s.has_phase) return std::nullopt;
  ExtendedSysState m;
  switch (s.phase.phase) {
    case msg::Phase::preflight:
    case msg::Phase::stopped: m.landed_state = MAV_LANDED_STATE_ON_GROUND; break;
    case msg::Phase::takeoff: m.landed_state = MAV_LANDED_STATE_TAKEOFF; break;
    case msg::Phase::landing:
    case msg::Phase::approach:
    case msg::Phase::flare:
    case msg::Phase::rollout: m.landed_state = MAV_LANDED_STATE_LANDING; break;
    case msg::Phase::climb:
    case msg::Phase::cruise:
    case msg::Phase::loiter: m.landed_state = MAV_LANDED_STATE_IN_AIR; break;
  }
  return m;
}

}  // namespace tern::core::mavlink
