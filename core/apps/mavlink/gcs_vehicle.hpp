// core/apps/mavlink/gcs_vehicle.hpp: one vehicle behind the ground-station endpoint (gcs_link.hpp):
// a MAVLink system of its own (system id, component MAV_COMP_ID_AUTOPILOT1, its own sequence
// numbers) over one host.
//
// What it does for its host:
//   - telemetry, on wall-clock rates (a GCS's timeouts are wall time; in fast time it is a
//     time-lapse of the flight): HEARTBEAT, SYS_STATUS, SYSTEM_TIME, EXTENDED_SYS_STATE,
//     MISSION_CURRENT, WIND_COV 1 Hz, ATTITUDE 20 Hz, GLOBAL_POSITION_INT and
//     NAV_CONTROLLER_OUTPUT 5 Hz, VFR_HUD 4 Hz, GPS_RAW_INT 2 Hz, HOME_POSITION 0.5 Hz (once the
//     estimate has an origin), STATUSTEXT on tern's events (phase changes, controller handovers,
//     failsafes); a TIMESYNC request answered;
//   - the parameter protocol (PARAM_REQUEST_LIST, PARAM_REQUEST_READ, PARAM_SET -> PARAM_VALUE;
//     https://mavlink.io/en/services/parameter.html) over every instance's numeric and boolean
//     parameters (param_ids.hpp), a set going through Host::request_param as the console's does;
//   - the mission protocol (mission_protocol.hpp), the commands (gcs_commands.hpp) and MAVLink
//     FTP serving the parameter metadata (mavlink_ftp.hpp, component_metadata.hpp).
// It only reads the host's topics (state: the estimate, never truth; flight_phase, gnss,
// actuators, rc, the commands and the path: telemetry.hpp) in a tick observer (observe) that
// copies them every 20 ms of flight time under a mutex held only for the copy; a flight flies the
// same bytes with or without it. A GCS's HEARTBEAT (type MAV_TYPE_GCS) feeds the link-loss
// failsafe (Host::ground_link_heard), as the DDS bridge's requests do.
//
// Threads: observe() on the flight thread; everything else on the link's thread. Parameter values
// are read from that thread as the DDS bridge reads them (ParamBase::value()).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tern/time.hpp"
#include "mavlink/link_counters.hpp"
#include "mavlink/mavlink_codec.hpp"

namespace tern::core {

class Host;

namespace mavlink {

class GcsVehicle {
 public:
  /// Where the vehicle's frames go (whole MAVLink 2 frames, on the link's thread).
  using FrameSink = std::function<void(const std::vector<std::uint8_t>& frame)>;

  /// `dir`: where the mission protocol writes accepted uploads (created; removed by the destructor).
  GcsVehicle(Host& host, std::uint8_t system_id, FrameSink sink, const std::filesystem::path& dir);
  ~GcsVehicle();
  GcsVehicle(const GcsVehicle&) = delete;
  GcsVehicle& operator=(const GcsVehicle&) = delete;

  /// The flight thread's tick observer (Host::add_tick_observer).
  void observe(Nanos now);
  /// A frame from the GCS addressed to this system or to every system (link's thread).
  void on_frame(const Frame& f);
  /// Telemetry due, STATUSTEXTs waiting, a parameter list's next values, the mission protocol's
  /// retries; `link`: the endpoint's counts for SYS_STATUS (every 10 ms, link's thread).
  void on_tick(const Counters& link);

  Host& host() const;
  std::uint8_t system_id() const;
  /// How many parameters it serves.
  std::size_t param_count() const;
  /// The parameters whose MAVLink id is not their name: (instance.param, id) (param_ids.hpp).
  std::vector<std::pair<std::string, std::string>> shortened_ids() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mavlink
}  // namespace tern::core
