// core/apps/mavlink/gcs_commands.hpp: MAVLink's command protocol on the vehicle's side
// (https://mavlink.io/en/services/command.html): COMMAND_LONG and COMMAND_INT, each answered with
// one COMMAND_ACK (MAV_RESULT) and, for a refusal, one STATUSTEXT saying why. Every command goes
// through the host's own APIs (Host::edit_mission, Host::go_around, Host::abort_flight), never
// into the simulated world. The mapping (docs/ground-station.md, "Commands"):
//   COMPONENT_ARM_DISARM (400)  tern is armed from takeoff to the stop (HEARTBEAT's SAFETY_ARMED):
//                               refused in the air (DENIED); arm in preflight: ACCEPTED (the arming
//                               checks take off once they pass); disarm on the ground: the flight
//                               ends (Host::abort_flight); no flight running: arm DENIED.
//   NAV_RETURN_TO_LAUNCH (20)   return_home at the current altitude (as the link-loss failsafe), or a loiter at
//                               the nearest rally point at its altitude when one is nearer than home.
//   DO_REPOSITION (192)         "fly here": loiter at (x, y, z) (z NaN: the current altitude;
//                               no position: here), radius |param3| (< 0 counter-clockwise; 0 or
//                               NaN: the path manager's turn radius), param1 > 0: airspeed m/s.
//   NAV_LOITER_UNLIM (17)       loiter at its position (none: here), radius param3.
//   NAV_LAND (21), DO_LAND_START (189)  the mission's land item flown next (none: DENIED).
//   DO_GO_AROUND (191)          Host::go_around: the phase machine takes it on the approach or flare.
//   DO_SET_MODE (176)           param1 with CUSTOM_MODE_ENABLED, param2 a custom mode = tern's phase
//                               (HEARTBEAT custom_mode): loiter (4) -> loiter here, cruise (2) ->
//                               the mission from its current item, landing (3) -> NAV_LAND, the
//                               phase flown now -> nothing to do; others are the phase machine's.
//   MISSION_START (300)         the mission (the upload, or the one a command replaced) from item param1.
//   REQUEST_MESSAGE (512)       AUTOPILOT_VERSION (148), HOME_POSITION (242); others UNSUPPORTED.
//   REQUEST_AUTOPILOT_CAPABILITIES (520)  AUTOPILOT_VERSION.
//   SET_MESSAGE_INTERVAL (511)  DENIED: the telemetry rates are fixed (gcs_link.hpp).
//   anything else               UNSUPPORTED.
// Commands that replace the mission (return, "fly here", loiter) keep it first
// (MissionProtocol::keep_mission) for MISSION_START.
//
// Errors: none thrown out of on_frame (a host refusal becomes the ACK's result and a STATUSTEXT).
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "mavlink/flight_view.hpp"
#include "mavlink/mission_protocol.hpp"
#include "tern/msg/mission.hpp"

namespace tern::core {

class Host;

namespace mavlink {

/// AUTOPILOT_VERSION's capabilities: MISSION_INT, PARAM_FLOAT, COMMAND_INT, MAVLINK2 (what
/// QGroundControl reads before it uses the _INT mission and command messages), MISSION_FENCE and
/// MISSION_RALLY (its geofence and rally point editors).
AutopilotVersion autopilot_version(std::uint8_t system_id);

class GcsCommands {
 public:
  GcsCommands(Host& host, const FlightWatch& flight, MissionProtocol& mission, Outbox out, std::uint8_t system_id);

  /// Takes a COMMAND_LONG or COMMAND_INT frame (any other id: false, untouched).
  bool on_frame(const Frame& f);

 private:
  /// A command from either message: params 1-4, and a position when it has one.
  struct Command {
    std::uint16_t id = 0;
    std::array<float, 4> param{};
    bool has_position = false;
    double lat = 0, lon = 0;  ///< deg
    double alt = 0;           ///< m MSL (NaN: not given)
  };
  struct Result {
    std::uint8_t result;
    std::string why;  ///< a refusal's reason (STATUSTEXT), or a note on an accepted command
  };
  Result run(const Command& c);
  Result arm_disarm(const Command& c, const FlightView& v);
  Result loiter_at(const Command& c, const FlightView& v, const std::string& what);
  Result return_home(const FlightView& v);
  Result land(const FlightView& v);
  Result set_mode(const Command& c, const FlightView& v);
  Result request_message(std::uint32_t id, const FlightView& v);
  Result edit(const msg::MissionEdit& e, const std::string& done);

  Host& host_;
  const FlightWatch& flight_;
  MissionProtocol& mission_;
  Outbox out_;
  std::uint8_t system_id_;
  std::uint32_t edits_ = 0;
};

}  // namespace mavlink
}  // namespace tern::core
