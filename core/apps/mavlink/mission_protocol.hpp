// core/apps/mavlink/mission_protocol.hpp: the vehicle's side of MAVLink's mission protocol
// (https://mavlink.io/en/services/mission.html) for its three lists: MISSION, FENCE (the geofence's
// zones) and RALLY (rally points), on the link's thread (gcs_link.hpp). Every MISSION_COUNT,
// MISSION_REQUEST_INT and MISSION_ACK carries the list's mission_type.
//
// Upload: MISSION_COUNT -> MISSION_REQUEST_INT 0 .. n-1 (each re-sent after kRetryPeriod without
// the item, at most kRetries times, then the upload ends with MISSION_ACK OPERATION_CANCELLED, as
// PX4's retry timeout) -> MISSION_ITEM_INT -> MISSION_ACK. An item out of order is not taken: the
// one expected is requested again; an item of another mission_type ends the upload (MAV_MISSION_ERROR). A new MISSION_COUNT restarts the
// upload (an abandoned one is dropped). Each item is checked as it arrives, the whole mission at the end, with the planner's own reader
// (mission_items.hpp, tern/path/mission.hpp); a refusal ends the upload with the MAV_MISSION_RESULT and one STATUSTEXT naming the item and
// the mission is unchanged. An accepted mission is written as a tern waypoint file and handed to the planner with one mission edit
// load_file (Host::edit_mission, as `tern mission load` does): it replaces the mission, its loop
// setting included, at the next tick, in flight or before the next flight.
// Download: MISSION_REQUEST_LIST -> MISSION_COUNT -> MISSION_REQUEST_INT (or the deprecated
// MISSION_REQUEST, answered with MISSION_ITEM_INT too) -> MISSION_ITEM_INT ... -> the GCS's ACK.
// It gives what tern flies: the uploaded items as sent while the planner's list is the one they
// made (or is still to be made from them; set_current only renumbers it), else the planner's list
// (the configured mission, a failsafe's loiter, a mission loaded over DDS, a "fly here") as items
// (mission_items.hpp to_items).
// FENCE and RALLY: the same upload, each item checked as it arrives and the whole list at the end
// (fence_items.hpp); an accepted list replaces the config's zones or rally points in the host's
// failsafes (Host::set_fence_zones, set_rally_points) from the next tick on, and is what a
// download gives back, item for item. Before any upload a download gives the config's
// (failsafes.geofence.polygon, failsafes.rally) as items.
// MISSION_CLEAR_ALL: mission edit clear (the path manager then orbits home), ACK; of FENCE or
// RALLY: no zones or rally points (the config's distance and altitude limits stay); of ALL: all three.
// MISSION_SET_CURRENT: the item `seq` (a DO_CHANGE_SPEED: the nav item after it) flown next
// (mission edit set_current; an uploaded mission is loaded again first, so the index is its own).
//
// Errors: a bad or hostile message is answered (MISSION_ACK with a MAV_MISSION_RESULT, or a
// STATUSTEXT) and dropped; nothing throws out of the handlers except what Outbox throws.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mavlink/flight_view.hpp"
#include "mavlink/mavlink_codec.hpp"
#include "mavlink/mission_messages.hpp"

namespace tern::core {

class Host;

namespace mavlink {

/// How a handler answers: `send` a payload of message `msgid` to the GCS, `say` a STATUSTEXT.
struct Outbox {
  std::function<void(std::uint32_t msgid, const std::vector<std::uint8_t>& payload)> send;
  std::function<void(std::uint8_t severity, const std::string& text)> say;
};

class MissionProtocol {
 public:
  static constexpr std::uint16_t kMaxItems = 1000;               ///< the longest upload taken (items)
  static constexpr std::chrono::milliseconds kRetryPeriod{250};  ///< silence before an item is asked again
  static constexpr int kRetries = 5;                             ///< re-requests before an upload is given up

  /// `dir`: where accepted uploads are written (created; removed by the destructor).
  MissionProtocol(Host& host, const FlightWatch& flight, Outbox out, std::uint8_t system_id, std::filesystem::path dir);
  ~MissionProtocol();
  MissionProtocol(const MissionProtocol&) = delete;
  MissionProtocol& operator=(const MissionProtocol&) = delete;

  /// Takes a MISSION_* frame (any other id: false, untouched).
  bool on_frame(const Frame& f);
  /// Re-requests an overdue item, gives up an upload after kRetries (call every link tick).
  void on_tick();

  /// The mission tern flies now as items (the download's).
  std::vector<MissionItemInt> items() const;
  /// The items of list `mission_type` (MISSION, FENCE, RALLY) a download gives.
  std::vector<MissionItemInt> items(std::uint8_t mission_type) const;
  /// The seq of the item flown now (MISSION_CURRENT), or nullopt (no mission, nothing flown yet).
  std::optional<std::uint16_t> current_seq() const;
  /// Before a command replaces the planner's list (return to launch, "fly here", loiter): keeps
  /// the mission flown now (written as a file) for MISSION_START to fly again, unless it is an
  /// upload already kept.
  void keep_mission();
  /// The id of the next mission edit this link sends (the planner's log echoes it).
  std::uint32_t next_edit_id() { return ++edits_; }
  /// Flies the mission's item `seq` next (MISSION_SET_CURRENT, MAV_CMD_MISSION_START,
  /// MAV_CMD_DO_LAND_START). Returns "" or why not.
  std::string fly_from(std::uint16_t seq);

 private:
  struct Upload {
    std::uint16_t count = 0, next = 0;
    std::uint8_t gcs_sys = 0, gcs_comp = 0;
    std::uint8_t type = MAV_MISSION_TYPE_MISSION;  // MAV_MISSION_TYPE
    std::vector<MissionItemInt> items;
    std::chrono::steady_clock::time_point asked;
    int retries = 0;
  };
  struct Uploaded {
    std::vector<MissionItemInt> items;
    std::vector<std::uint16_t> nav_seq;    // the item each waypoint came from
    std::vector<msg::Waypoint> waypoints;  // NED, as the planner lists them
    std::uint64_t list_seq = 0;            // the planner's list count when it was handed over
    std::filesystem::path file;
    std::chrono::steady_clock::time_point handed{};  // when it was handed over (wall time)
    mutable bool listed = false;                     // the planner has listed it since
  };
  /// How long after a hand-over another list of the planner's is taken for one it published
  /// before applying the edit (it applies it at its next tick: well within this at any --speed).
  static constexpr std::chrono::milliseconds kHandover{2000};
  void on_count(const Frame& f);
  void on_item(const Frame& f);
  void on_request(const Frame& f);
  void on_list(const Frame& f);
  void on_clear(const Frame& f);
  void on_set_current(const Frame& f);
  void finish_upload();
  void finish_mission(const Upload& u);
  void request(const Upload& u);
  /// MISSION_ACK to (sys, comp): `result` (MAV_MISSION_RESULT) for the list of `mission_type`
  /// (MAV_MISSION_TYPE: a planner matches the answer to its transfer by it).
  void ack(std::uint8_t sys, std::uint8_t comp, std::uint8_t result, std::uint8_t mission_type = MAV_MISSION_TYPE_MISSION);
  /// A mission_type other than MISSION, FENCE and RALLY refused with its type and one STATUSTEXT.
  void refuse_type(const Frame& f, std::uint8_t mission_type);
  static bool known_type(std::uint8_t mission_type);
  static std::string type_name(std::uint8_t mission_type);
  bool for_us(std::uint8_t sys, std::uint8_t comp) const;
  /// The planner flies the upload (or the mission kept) now: it lists it, or has not applied the
  /// hand-over yet (no list since, or another one within kHandover before it ever listed ours).
  bool ours_flown(const FlightView& v) const;
  std::filesystem::path write(const std::string& text);

  Host& host_;
  const FlightWatch& flight_;
  Outbox out_;
  std::uint8_t system_id_;
  std::filesystem::path dir_;
  std::optional<Upload> upload_;
  std::optional<Uploaded> uploaded_;
  std::array<std::vector<MissionItemInt>, 3> download_;             // per mission_type: the items of the last MISSION_COUNT sent
  std::array<std::optional<std::vector<MissionItemInt>>, 3> kept_;  // FENCE, RALLY: as uploaded (or cleared)
  std::uint32_t files_ = 0, edits_ = 0;
  bool commanded_ = false;  // a command's list (return, loiter) replaced the mission kept in uploaded_
};

}  // namespace mavlink
}  // namespace tern::core
