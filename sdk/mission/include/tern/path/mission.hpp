// tern/path/mission.hpp: reading missions (waypoint lists) and converting latitude/longitude
// to local NED. Plain C++ (yaml-cpp, tern/geodesy.hpp), no host types: the path planner plugin,
// the host's command line and its DDS bridge use the same functions, so a file that one of
// them accepts, all accept.
//
// Three sources, one result (a Mission):
//
// 1. The mission config's `mission:` section (parse_mission_section):
//      mission:
//        loop: true                 # optional, default true: after the last waypoint, the first
//        Va_d: 17.0                 # optional default airspeed of the entries, m/s
//        waypoints:
//          - [400.0, -250.0, -70.0]                     # NED, m (d = -altitude above origin)
//          - {ned: [-400, -50, -70], Va_d: 17}
//          - {lla: [40.2455, -111.6480, 1450.0]}        # lat deg, lon deg, alt m MSL
//          - {w: [-400, -250, -70], chi_d: 1.1518, use_chi: true, va_d: 17, lla: false}
//      or
//        file: ../missions/fixedwing_mission.yaml     # relative to the config's directory
//    (`waypoints` beside `file`: the file's items, then these.)
//    `loops: N` (a whole number >= 1; implies loop: true): the items before a final land item
//    are flown N times, then the land item (none: the last item is orbited), e.g.
//        file: fixedwing_mission.yaml
//        loops: 5
//        waypoints:
//          - {type: land, ned: [0, 0, 0], heading: 2.3562}
// 2. A tern waypoint file (load_mission_file): a YAML map with the same keys as the section
//    (loop, Va_d, waypoints); `file` is not allowed inside a file.
// 3. A ROSplane mission file, unchanged (load_mission_file detects it by its top-level `wp:`
//    keys): one `wp:` map per waypoint with w, lla (bool), chi_d, use_chi, va_d. The file
//    repeats the key `wp:`, which a YAML map cannot hold; a line-level pre-pass splits the
//    document at every top-level `wp:` line (column 0) and parses each chunk on its own, so
//    every waypoint is read, in file order, on any yaml-cpp version.
//
// Entry keys: ned | w (3 numbers), lla (3 numbers, or a bool flag saying that w is lat/lon/alt),
// chi_d (rad, finite), use_chi (bool), Va_d | va_d (m/s, >= 0; 0: the path manager's default),
// and tern's mission items (item.hpp; ROSplane files may use them too):
//   type: waypoint | loiter | return_home | land   (default waypoint)
//   radius: m >= 0 (0: the path manager's turn radius), direction: cw | ccw (default cw),
//   time: s >= 0, turns: >= 0, to_altitude: bool   (loiter only; to_altitude: go on once at the
//                                              item's altitude; none: loiter until the mission changes)
//   Vg_min: m/s >= 0                           (least ground speed: the path manager raises the
//                                              airspeed in a headwind; 0: none)
//   altitude: m above home                     (return_home only, instead of a position; absent:
//                                              the altitude of the item before it)
//   heading: rad in [-2 pi, 2 pi]              (land only, required: the runway heading, the
//                                              direction of landing; a ROSplane file may give it
//                                              as chi_d, never both)
//   glide_slope: rad in (0, 0.35], flare_height: m > 0, decision_height: m > flare_height
//                                              (land only; defaults: item.hpp LandSpec)
// e.g.  - {type: loiter, ned: [0, 300, -70], radius: 80, direction: ccw, turns: 2}
//       - {type: return_home, altitude: 70}
//       - {type: land, ned: [0, 0, 0], heading: 2.3562, glide_slope: 0.0873, flare_height: 3}
// loiter and return_home take no chi_d/use_chi; return_home takes no position (home is the
// origin); items after a return_home are never reached. A land item's position (ned or lla)
// is the touchdown point; it takes no radius, direction, time, turns, altitude or use_chi:
// true. It is the mission's last item (an item after it is an error) and must be reached (not
// after a return_home or a loiter without time, turns or to_altitude: an error). A mission ending with a
// land item flies the items before it once, or `loops` times: `loop` alone is moot there, and
// `loop: true` without `loops` (never landing) is an error; a file's `loop: true` gives way when
// a config's section appends a land item to it.
// Latitude must be in [-90, 90] deg, longitude in [-180, 180] deg. Unknown keys are errors.
//
// Errors: every function throws MissionError (a std::runtime_error) with one line naming the
// file (or "mission config") and line ("file:line: "), the waypoint number and field, and the
// bad value. mission_check.hpp checks where the waypoints are (home, turn radius, fence).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tern/geodesy.hpp"
#include "tern/path/item.hpp"

namespace YAML {
class Node;
}

namespace tern::path {

class MissionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  /// An unknown key: what() is "<where>unknown key 'key' (expected a, b, ...)"; the parts stay
  /// readable so that a caller can suggest the closest key instead.
  MissionError(const std::string& where, const std::string& key, const std::vector<std::string>& expected);
  const std::string& where() const { return where_; }      ///< "file:line: field: " ("" if not an unknown key)
  const std::string& unknown_key() const { return key_; }  ///< "" if not an unknown key
  const std::vector<std::string>& expected_keys() const { return expected_; }

 private:
  std::string where_, key_;
  std::vector<std::string> expected_;
};

/// One waypoint as the mission gives it.
struct MissionWaypoint {
  Eigen::Vector3d w = Eigen::Vector3d::Zero();  ///< NED m, or (lat deg, lon deg, alt m MSL) when lla
  bool lla = false;
  double chi_d = 0.0;    ///< desired course at the waypoint, rad
  bool use_chi = false;  ///< arrive with course chi_d (Dubins path)
  double Va_d = 0.0;     ///< desired airspeed, m/s (0: the path manager's default)
  /// Least ground speed, m/s, >= 0 (0: none): the path manager raises the airspeed above Va_d
  /// where the estimated wind would leave less (MAVLink DO_CHANGE_SPEED type 1, as ArduPlane flies it).
  double Vg_min = 0.0;
  ItemType type = ItemType::waypoint;
  LoiterSpec loiter;   ///< loiter and return_home items
  LandSpec land;       ///< land items (chi_d: the runway heading)
  int line = 0;        ///< 1-based line of the entry in its source (0: not read from text)
  std::string field;   ///< the entry's name in its source ("waypoints[2]", "wp 3"; "" if not read)
  std::string source;  ///< the file (or config) the entry was read from ("": not read; see Mission::source)
};

struct Mission {
  std::vector<MissionWaypoint> waypoints;
  bool loop = true;
  int loops = 0;       ///< > 0: the items before a final land item are flown this many times (loop), then it
  std::string source;  ///< "mission config" or the file path, for messages
  /// True when at least one waypoint is latitude/longitude/altitude.
  bool has_lla() const;
};

/// Reads the mission config's `mission:` section. base_dir resolves a relative `file:`; `source`
/// names the section in errors (the config file's path, whose line numbers the nodes carry).
/// A null or empty section gives an empty mission. Throws MissionError.
Mission parse_mission_section(const YAML::Node& section, const std::filesystem::path& base_dir,
                              const std::string& source = "mission config (mission:)");

/// Reads a tern waypoint file or a ROSplane mission file. Throws MissionError (also when the
/// file cannot be read).
Mission load_mission_file(const std::filesystem::path& file);

/// Reads a mission from text (tern or ROSplane format); `source` names it in errors.
Mission parse_mission_text(const std::string& text, const std::string& source);

/// NED position (m) of (lat deg, lon deg, alt m) relative to the origin of the local NED frame
/// (the estimator's origin_lat/lon/alt; alt on the waypoints' datum), computed with
/// tern::GeoOrigin (tern/geodesy.hpp: WGS-84, exact, no flat-earth approximation). Throws
/// MissionError for out-of-range or non-finite input.
Eigen::Vector3d lla_to_ned(const Eigen::Vector3d& lla, const GeoPoint& origin);

/// The mission's waypoints with every LLA position converted to NED (the others unchanged).
std::vector<MissionWaypoint> resolve_to_ned(const std::vector<MissionWaypoint>& wps, const GeoPoint& origin);

/// Checks one waypoint (finite values, latitude/longitude ranges, Va_d >= 0, a land item's
/// heading, glide slope and heights); `where` names it in the error, e.g. "mission_edit 7".
/// Throws MissionError.
void validate_waypoint(const MissionWaypoint& wp, const std::string& where);

/// Checks that a land item ends the mission (no item after it) and is reached (the item before
/// it is not a return_home or a loiter without time, turns or to_altitude). The readers call it; a mission
/// edit calls it on the list it would make. Throws MissionError naming the item ("source:line:
/// field: ", Mission::source for entries not read from text).
void check_land_last(const Mission& m);

}  // namespace tern::path
