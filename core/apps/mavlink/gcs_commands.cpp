// core/apps/mavlink/gcs_commands.cpp: COMMAND_LONG / COMMAND_INT -> COMMAND_ACK (gcs_commands.hpp).
#include "mavlink/gcs_commands.hpp"

#include <cmath>
#include <cstdio>

#include "flight/host.hpp"
#include "mavlink/component_metadata.hpp"
#include "mavlink/mission_items.hpp"

namespace tern::core::mavlink {
namespace {

constexpr std::uint16_t kDisarm = 0, kArm = 1;  // ARM_DISARM param1
constexpr double kE7 = 1e7;                     // degE7 per degree

std::string phase_text(const FlightView& v) { return v.has_phase ? std::string(msg::phase_name(v.phase)) : "unknown"; }

std::string fixed(double v, int digits) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

}  // namespace

AutopilotVersion autopilot_version(std::uint8_t system_id) {
  AutopilotVersion a;
  a.capabilities = MAV_PROTOCOL_CAPABILITY_MISSION_INT | MAV_PROTOCOL_CAPABILITY_PARAM_FLOAT | MAV_PROTOCOL_CAPABILITY_COMMAND_INT |
                   MAV_PROTOCOL_CAPABILITY_MAVLINK2 | MAV_PROTOCOL_CAPABILITY_MISSION_FENCE | MAV_PROTOCOL_CAPABILITY_MISSION_RALLY;
  a.uid = system_id;
  return a;
}

GcsCommands::GcsCommands(Host& host, const FlightWatch& flight, MissionProtocol& mission, Outbox out, std::uint8_t system_id)
    : host_(host), flight_(flight), mission_(mission), out_(std::move(out)), system_id_(system_id) {}

bool GcsCommands::on_frame(const Frame& f) {
  Command c;
  std::uint8_t sys = 0, comp = 0;
  if (f.msgid == CommandLong::kId) {
    const auto m = decode<CommandLong>(f);
    sys = m.target_system, comp = m.target_component;
    c.id = m.command;
    c.param = {m.param1, m.param2, m.param3, m.param4};
    c.has_position = std::isfinite(m.param5) && std::isfinite(m.param6) && !(m.param5 == 0.0f && m.param6 == 0.0f);
    c.lat = m.param5, c.lon = m.param6, c.alt = m.param7;  // COMMAND_LONG: degrees, m MSL
  } else if (f.msgid == CommandInt::kId) {
    const auto m = decode<CommandInt>(f);
    sys = m.target_system, comp = m.target_component;
    c.id = m.command;
    c.param = {m.param1, m.param2, m.param3, m.param4};
    c.has_position = !(m.x == 0 && m.y == 0) && m.x != INT32_MAX && m.y != INT32_MAX;
    c.lat = m.x / kE7, c.lon = m.y / kE7;
    const bool rel = m.frame == MAV_FRAME_GLOBAL_RELATIVE_ALT || m.frame == MAV_FRAME_GLOBAL_RELATIVE_ALT_INT;
    const FlightView v = flight_.view();
    c.alt = rel ? v.origin.alt + m.z : m.z;
  } else {
    return false;
  }
  if (!((sys == 0 || sys == system_id_) && (comp == 0 || comp == MAV_COMP_ID_AUTOPILOT1))) return true;
  const Result r = run(c);
  if (!r.why.empty()) out_.say(r.result == MAV_RESULT_ACCEPTED ? MAV_SEVERITY_INFO : MAV_SEVERITY_WARNING, r.why);
  CommandAck ack;
  ack.command = c.id;
  ack.result = r.result;
  ack.target_system = f.sysid;
  ack.target_component = f.compid;
  out_.send(CommandAck::kId, encode(ack));
  return true;
}

GcsCommands::Result GcsCommands::run(const Command& c) {
  const FlightView v = flight_.view();
  switch (c.id) {
    case MAV_CMD_COMPONENT_ARM_DISARM: return arm_disarm(c, v);
    case MAV_CMD_NAV_RETURN_TO_LAUNCH: return return_home(v);
    case MAV_CMD_DO_REPOSITION: return loiter_at(c, v, "fly here");
    case MAV_CMD_NAV_LOITER_UNLIM: return loiter_at(c, v, "loiter");
    case MAV_CMD_NAV_LAND:
    case MAV_CMD_DO_LAND_START: return land(v);
    case MAV_CMD_DO_GO_AROUND: try { host_.go_around("mavlink");
      } catch (const std::exception& e) {
        return {MAV_RESULT_DENIED, e.what()};
      }
      return {MAV_RESULT_ACCEPTED, "go-around asked: the phase machine takes it on the approach or in the flare"};
    case MAV_CMD_DO_SET_MODE: return set_mode(c, v);
    case MAV_CMD_MISSION_START: {
      // param1 the first item, param2 the last (0: to the end): item numbers, or the command is
      // refused before the mission is touched (a NaN is no item: it must not restart the mission)
      for (std::size_t k = 0; k < 2; ++k)
        if (!(c.param[k] >= 0.0f && c.param[k] <= 65535.0f && c.param[k] == std::floor(c.param[k])))
          return {MAV_RESULT_DENIED, "mission start refused: param" + std::to_string(k + 1) + " (" + (k == 0 ? "first" : "last") +
                                         " item) " + fixed(c.param[k], 2) + " is not an item number 0..65535"};
      const std::string why = mission_.fly_from(static_cast<std::uint16_t>(c.param[0]));
      if (!why.empty()) return {MAV_RESULT_DENIED, "mission start refused: " + why};
      return {MAV_RESULT_ACCEPTED, ""};
    }
    case MAV_CMD_REQUEST_MESSAGE:
      return request_message(std::isfinite(c.param[0]) && c.param[0] >= 0.0f ? static_cast<std::uint32_t>(c.param[0]) : UINT32_MAX, v);
    case MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES: return request_message(AutopilotVersion::kId, v);
    case MAV_CMD_SET_MESSAGE_INTERVAL:
      return {MAV_RESULT_DENIED, "message intervals are fixed (docs/ground-station.md): message " + fixed(c.param[0], 0) + " unchanged"};
    default: return {MAV_RESULT_UNSUPPORTED, ""};
  }
}

GcsCommands::Result GcsCommands::arm_disarm(const Command& c, const FlightView& v) {
  const bool arm = c.param[0] == kArm;
  if (!arm && c.param[0] != kDisarm) return {MAV_RESULT_DENIED, "arm/disarm: param1 " + fixed(c.param[0], 2) + " is neither 1 nor 0"};
  if (v.airborne())
    return {MAV_RESULT_DENIED, std::string(arm ? "arm" : "disarm") + " refused in flight (phase " + phase_text(v) +
                                   "): tern is armed from takeoff until it stops"};
  if (arm && !v.flying) return {MAV_RESULT_DENIED, "arm refused: no flight running (start one: tern fly, or tern serve's fly)"};
  if (arm) return {MAV_RESULT_ACCEPTED, "preflight: the takeoff follows once the arming checks pass"};
  if (!v.flying) return {MAV_RESULT_ACCEPTED, ""};  // disarmed already
  host_.abort_flight();
  return {MAV_RESULT_ACCEPTED, "disarmed on the ground (phase " + phase_text(v) + "): the flight ends"};
}

GcsCommands::Result GcsCommands::edit(const msg::MissionEdit& e, const std::string& done) {
  try {
    host_.edit_mission(e);
  } catch (const std::exception& err) {
    return {MAV_RESULT_DENIED, err.what()};
  }
  return {MAV_RESULT_ACCEPTED, done};
}

GcsCommands::Result GcsCommands::loiter_at(const Command& c, const FlightView& v, const std::string& what) {
  if (!v.flying || !v.has_state) return {MAV_RESULT_TEMPORARILY_REJECTED, what + " refused: no flight with a position estimate"};
  const GeoOrigin home(v.origin);
  Eigen::Vector3d ned = v.p_ned;
  if (c.has_position) {
    if (!(std::fabs(c.lat) <= 90.0 && std::fabs(c.lon) <= 180.0))
      return {MAV_RESULT_DENIED, what + " refused: latitude " + fixed(c.lat, 7) + ", longitude " + fixed(c.lon, 7) + " out of range"};
    ned = home.to_ned(c.lat, c.lon, std::isfinite(c.alt) ? c.alt : v.origin.alt - v.p_ned.z());
    if (!std::isfinite(c.alt)) ned.z() = v.p_ned.z();
  } else if (std::isfinite(c.alt)) {
    ned.z() = v.origin.alt - c.alt;
  }
  const double radius = std::isfinite(c.param[2]) ? c.param[2] : 0.0;
  msg::MissionEdit e;
  e.id = mission_.next_edit_id();
  e.op = msg::MissionEdit::add;
  e.set_current_wp = true;
  e.waypoint.type = msg::Waypoint::loiter;
  e.waypoint.w = ned;
  e.waypoint.loiter_radius = std::fabs(radius);
  e.waypoint.loiter_direction = std::signbit(radius) ? -1 : 1;
  if (c.id == MAV_CMD_DO_REPOSITION && std::isfinite(c.param[0]) && c.param[0] > 0.0f) e.waypoint.Va_d = c.param[0];
  mission_.keep_mission();
  return edit(e, what + ": loiter at " + fixed(ned.x(), 0) + " m N, " + fixed(ned.y(), 0) + " m E, " + fixed(-ned.z(), 0) + " m up");
}

GcsCommands::Result GcsCommands::return_home(const FlightView& v) {
  if (!v.flying || !v.has_state) return {MAV_RESULT_TEMPORARILY_REJECTED, "return refused: no flight with a position estimate"};
  msg::MissionEdit e;
  e.id = mission_.next_edit_id();
  e.op = msg::MissionEdit::add;
  e.set_current_wp = true;
  e.waypoint.type = msg::Waypoint::return_home;
  e.waypoint.w = Eigen::Vector3d(0.0, 0.0, v.p_ned.z());
  const FailsafeStation::Geometry g = host_.fence_geometry();
  if (const auto i = nearest_rally(g.rally, g.zones, v.p_ned.head<2>())) {  // the nearest rally point, as the failsafes return
    const Eigen::Vector3d& r = g.rally[*i];
    e.waypoint.type = msg::Waypoint::loiter;
    e.waypoint.w = Eigen::Vector3d(r.x(), r.y(), -r.z());
    mission_.keep_mission();
    return edit(e, "return to rally point " + std::to_string(*i) + " at " + fixed(r.z(), 0) + " m (nearer than home)");
  }
  mission_.keep_mission();
  return edit(e, "return to launch at " + fixed(-v.p_ned.z(), 0) + " m");
}

GcsCommands::Result GcsCommands::land(const FlightView& v) {
  if (!v.flying) return {MAV_RESULT_TEMPORARILY_REJECTED, "land refused: no flight running"};
  const std::vector<MissionItemInt> items = mission_.items();
  for (const MissionItemInt& it : items)
    if (it.command == MAV_CMD_NAV_LAND) {
      const std::string why = mission_.fly_from(it.seq);
      if (!why.empty()) return {MAV_RESULT_DENIED, "land refused: " + why};
      return {MAV_RESULT_ACCEPTED, "landing: mission item " + std::to_string(it.seq) + " flown next"};
    }
  return {MAV_RESULT_DENIED, "land refused: the mission has no land item (upload one with NAV_LAND)"};
}

GcsCommands::Result GcsCommands::set_mode(const Command& c, const FlightView& v) {
  const auto base = static_cast<std::uint32_t>(std::isfinite(c.param[0]) ? c.param[0] : 0.0f);
  if ((base & MAV_MODE_FLAG_CUSTOM_MODE_ENABLED) == 0)
    return {MAV_RESULT_DENIED, "set mode refused: tern's modes are custom modes (HEARTBEAT custom_mode: the phase)"};
  const float custom = c.param[1];
  if (v.has_phase && custom == static_cast<float>(static_cast<int>(v.phase))) return {MAV_RESULT_ACCEPTED, ""};
  if (custom == static_cast<float>(static_cast<int>(msg::Phase::loiter)))
    return loiter_at(Command{MAV_CMD_NAV_LOITER_UNLIM, {}, false, 0, 0, NAN}, v, "loiter");
  if (custom == static_cast<float>(static_cast<int>(msg::Phase::landing))) return land(v);
  if (custom == static_cast<float>(static_cast<int>(msg::Phase::cruise))) {
    const std::string why = mission_.fly_from(mission_.current_seq().value_or(0));
    if (!why.empty()) return {MAV_RESULT_DENIED, "set mode cruise refused: " + why};
    return {MAV_RESULT_ACCEPTED, "cruise: the mission flown again"};
  }
  return {MAV_RESULT_DENIED, "set mode " + fixed(custom, 0) + " refused: the phase machine enters that phase itself"};
}

GcsCommands::Result GcsCommands::request_message(std::uint32_t id, const FlightView& v) {
  if (id == AutopilotVersion::kId) {
    out_.send(AutopilotVersion::kId, encode(autopilot_version(system_id_)));
    return {MAV_RESULT_ACCEPTED, ""};
  }
  if (id == HomePosition::kId) {
    if (!v.has_state) return {MAV_RESULT_TEMPORARILY_REJECTED, "no home yet: the estimate has no origin"};
    HomePosition h;
    h.latitude = static_cast<std::int32_t>(std::llround(v.origin.lat * kE7));
    h.longitude = static_cast<std::int32_t>(std::llround(v.origin.lon * kE7));
    h.altitude = static_cast<std::int32_t>(std::llround(v.origin.alt * 1000.0));
    h.q = {1, 0, 0, 0};  // identity (w, x, y, z)
    out_.send(HomePosition::kId, encode(h));
    return {MAV_RESULT_ACCEPTED, ""};
  }
  if (id == ComponentMetadata::kId) {  // QGroundControl's parameter metadata (component_metadata.hpp)
    ComponentMetadata m;
    m.uri = tern::mavlink::to_chars<100>(kGeneralMetadataUri);  // file_crc 0: generated at start, not cached
    out_.send(ComponentMetadata::kId, encode(m));
    return {MAV_RESULT_ACCEPTED, ""};
  }
  if (id == ComponentInformation::kId) {  // the same, as QGroundControl before 4.3 asks
    ComponentInformation m;
    m.general_metadata_uri = tern::mavlink::to_chars<100>(kGeneralMetadataUri);
    out_.send(ComponentInformation::kId, encode(m));
    return {MAV_RESULT_ACCEPTED, ""};
  }
  return {MAV_RESULT_UNSUPPORTED, ""};
}

}  // namespace tern::core::mavlink
