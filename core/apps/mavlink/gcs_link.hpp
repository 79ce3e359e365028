// core/apps/mavlink/gcs_link.hpp: `tern fly --gcs` and `tern serve --gcs`: a MAVLink 2 ground-station
// endpoint over UDP (common dialect), as PX4's SITL offers one to QGroundControl and Mission
// Planner (docs/ground-station.md).
//
// What it does:
//   - telemetry, on wall-clock rates (a GCS's timeouts are wall time; in fast time it is a
//     time-lapse of the flight): HEARTBEAT, SYS_STATUS, SYSTEM_TIME, EXTENDED_SYS_STATE,
//     MISSION_CURRENT, WIND_COV 1 Hz, ATTITUDE 20 Hz, GLOBAL_POSITION_INT and
//     NAV_CONTROLLER_OUTPUT 5 Hz, VFR_HUD 4 Hz, GPS_RAW_INT 2 Hz, HOME_POSITION 0.5 Hz (once the
//     estimate has an origin), STATUSTEXT on tern's events (phase changes, controller handovers);
//     a TIMESYNC request answered;
//   - the parameter protocol (PARAM_REQUEST_LIST, PARAM_REQUEST_READ, PARAM_SET -> PARAM_VALUE;
//     https://mavlink.io/en/services/parameter.html) over every instance's numeric and boolean
//     parameters (param_ids.hpp), a set going through Host::request_param as the console's does;
//   - bad datagrams (wrong CRC, truncated, unknown ids, MAVLink 1) are counted (SYS_STATUS's
//     drop_rate_comm and errors_comm) and dropped.
// It only reads the host's topics (state: the estimate, never truth; flight_phase, gnss,
// actuators, rc, the commands and the path: telemetry.hpp) in a tick observer that copies them
// every 20 ms of flight time under a mutex held only for the copy; a flight flies the same bytes
// with or without it. A GCS's HEARTBEAT (type MAV_TYPE_GCS) feeds the link-loss failsafe
// (Host::ground_link_heard), as the DDS bridge's requests do: a GCS going silent changes nothing
// unless the mission configures `failsafes.link_loss`.
//
// Addresses: it binds `bind` (default 127.0.0.1:14580) and sends to `send_to` (default
// 127.0.0.1:14550, where QGroundControl listens) and to every address a good frame came from
// (at most 8; one silent for 10 s is forgotten), as PX4's SITL does.
//
// Threads: one, its own (Boost.Asio), started by the constructor, joined by the destructor.
// Parameter values are read from that thread as the DDS bridge reads them (ParamBase::value()).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "mavlink/link_counters.hpp"

namespace tern::core {

class Host;

namespace mavlink {

struct GcsOptions {
  std::string send_to = "127.0.0.1:14550";  ///< ADDR:PORT, IPv4: where telemetry goes before a GCS is heard
  std::string bind = "127.0.0.1:14580";     ///< ADDR:PORT, IPv4: the vehicle's own address (port 0: a free one)
  std::uint8_t system_id = 1;               ///< MAVLink system id of the vehicle (1-255)
};

/// Checks an "ADDR:PORT" (IPv4 dotted quad, port 0-65535). Throws ConfigError naming `what` ("": the
/// value only, for a caller that names the option itself).
void check_endpoint(const std::string& text, const std::string& what);

class GcsLink {
 public:
  /// Binds the socket and starts the thread; adds a tick observer to `host` (construct between
  /// flights). Throws ConfigError: a bad address, or a port that cannot be bound.
  GcsLink(Host& host, const GcsOptions& options);
  ~GcsLink();  ///< removes the observer, stops the thread
  GcsLink(const GcsLink&) = delete;
  GcsLink& operator=(const GcsLink&) = delete;

  /// "udp 127.0.0.1:14580 -> 127.0.0.1:14550" (the bound port when 0 was asked).
  std::string describe() const;
  /// The parameters whose MAVLink id is not their name: (instance.param, id) (param_ids.hpp).
  std::vector<std::pair<std::string, std::string>> shortened_ids() const;
  /// What was received and dropped so far (any thread).
  Counters counters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mavlink
}  // namespace tern::core
