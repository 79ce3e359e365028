// core/apps/mavlink/gcs_link.hpp: `tern fly --gcs` and `tern serve --gcs`: a MAVLink 2 ground-station
// endpoint over UDP (common dialect), as PX4's SITL offers one to QGroundControl and Mission
// Planner (docs/ground-station.md).
//
// Each vehicle behind it is a MAVLink system of its own (gcs_vehicle.hpp: its HEARTBEAT and
// telemetry, parameters, mission protocol, commands and FTP): one for `tern fly --gcs` of a
// mission, every vehicle of a fleet for one of a multi-vehicle mission, as several ArduPilot
// SITLs behind one MAVLink router appear (docs/ground-station.md, "Several vehicles"). A frame
// from the GCS goes to the vehicle its target_system names, or to every vehicle when it names 0
// or the message has no target (HEARTBEAT); one for a system no vehicle here has is ignored and
// counted (Counters::other_system). Bad datagrams (wrong CRC, truncated, unknown ids, MAVLink 1)
// are counted (SYS_STATUS's drop_rate_comm and errors_comm) and dropped.
//
// Addresses: it binds `bind` (default 127.0.0.1:14580) and sends to `send_to` (default
// 127.0.0.1:14550, where QGroundControl listens) and to every address a good frame came from
// (at most 8; one silent for 10 s is forgotten), as PX4's SITL does.
//
// Threads: one, its own (Boost.Asio), started by the constructor, joined by the destructor; it
// runs every vehicle's side. Each vehicle's tick observer runs on the flight thread and hands
// the link copies under a mutex (gcs_vehicle.hpp).
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
  std::string bind = "127.0.0.1:14580";     ///< ADDR:PORT, IPv4: the vehicles' own address (port 0: a free one)
};

/// A vehicle on the endpoint: its host, its name (a fleet's vehicle; "" for one mission's) and
/// its MAVLink system id (1-255; a mission's one vehicle is 1, as PX4's and ArduPilot's default).
struct LinkedVehicle {
  Host* host = nullptr;
  std::string name;
  std::uint8_t system_id = 1;
};

/// Checks an "ADDR:PORT" (IPv4 dotted quad, port 0-65535). Throws ConfigError naming `what` ("": the
/// value only, for a caller that names the option itself).
void check_endpoint(const std::string& text, const std::string& what);

class GcsLink {
 public:
  /// Binds the socket and starts the thread; adds a tick observer to each vehicle's host
  /// (construct between flights). Throws ConfigError: a bad address, a port that cannot be bound,
  /// two vehicles with one system id.
  GcsLink(const std::vector<LinkedVehicle>& vehicles, const GcsOptions& options);
  ~GcsLink();  ///< removes the observers, stops the thread
  GcsLink(const GcsLink&) = delete;
  GcsLink& operator=(const GcsLink&) = delete;

  /// "udp 127.0.0.1:14580 -> 127.0.0.1:14550, 335 parameters" (the bound port when 0 was asked);
  /// for several vehicles "..., systems 1 uav1 (335 parameters), 2 uav2 (335 parameters)".
  std::string describe() const;
  /// The parameters whose MAVLink id is not their name: (instance.param, id) (param_ids.hpp), the
  /// first vehicle's.
  std::vector<std::pair<std::string, std::string>> shortened_ids() const;
  /// What was received and dropped so far (any thread).
  Counters counters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mavlink
}  // namespace tern::core
