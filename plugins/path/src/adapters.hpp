// Adapters binding the path library (tern/path/*.hpp) to tern ports and parameters: the
// path_planner, path_manager and path_follower plugins. Each is registered in its own shared
// object (register_*.cpp); the tests use the classes directly with the SDK harness.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tern/msg/path.hpp"
#include "tern/path/follower.hpp"
#include "tern/path/manager.hpp"
#include "tern/path/mission.hpp"
#include "tern/plugin.hpp"

namespace tern::path {

/// msg::Waypoint::type as an ItemType (an unknown value: a plain waypoint), and back.
inline ItemType item_type_of(std::uint8_t t) {
  switch (t) {
    case msg::Waypoint::loiter: return ItemType::loiter;
    case msg::Waypoint::return_home: return ItemType::return_home;
    case msg::Waypoint::land: return ItemType::land;
    default: return ItemType::waypoint;
  }
}
inline std::uint8_t msg_item_type(ItemType t) {
  switch (t) {
    case ItemType::loiter: return msg::Waypoint::loiter;
    case ItemType::return_home: return msg::Waypoint::return_home;
    case ItemType::land: return msg::Waypoint::land;
    case ItemType::waypoint: break;
  }
  return msg::Waypoint::waypoint;
}

/// path_planner: the mission (config section, waypoint file or ROSplane file) as a NED
/// WaypointList on `waypoints`, with runtime edits from `mission_edit` and LLA waypoints held
/// back until `state` reports a valid origin.
class PlannerPlugin final : public Plugin {
 public:
  void configure() override;
  void start() override;
  void step(Nanos now) override;
  void reset() override;
  std::vector<std::pair<std::string, double>> summary() const override;

 private:
  void apply_edit(const msg::MissionEdit& e);
  /// MissionEdit add: the item validated, and a land item kept last (tern/path/mission.hpp).
  void add_item(const msg::MissionEdit& e, const std::string& tag);
  void replace(Mission m, const std::string& why);
  /// Reads the configured mission (mission_file, else the config's mission: section).
  void load_configured();

  Input<msg::State> state_;
  Input<msg::MissionEdit> edit_;
  Output<msg::WaypointList> waypoints_;
  Param<std::string> mission_file_;

  Mission configured_;           ///< the mission as configured (reset() returns to it)
  std::string configured_from_;  ///< mission_file when configured_ was read
  /// Everything one flight changes: reset() replaces it wholesale (then takes the configured mission).
  struct Flight {
    std::vector<MissionWaypoint> wps;  ///< the mission now (lla entries unconverted)
    bool loop = true;
    int loops = 0;      ///< Mission::loops
    bool dirty = true;  ///< the list changed since the last publish
    bool waiting_logged = false;
    bool held = false;               ///< edits made with publish_now = false wait to be published
    bool immediate = false;          ///< the next list published is flown at once (set_current)
    std::optional<GeoPoint> origin;  ///< origin the published list was converted with
    std::uint32_t revision = 0;
    std::uint64_t edits = 0;
  } f_;
};

/// path_manager: waypoints -> the segment to follow (`current_path`), see tern/path/manager.hpp.
class ManagerPlugin final : public Plugin {
 public:
  void configure() override;
  void start() override;
  void step(Nanos now) override;
  void reset() override;
  std::vector<std::pair<std::string, double>> summary() const override;

 private:
  ManagerConfig config() const;
  void rebuild();

  /// Home's altitude while at rest on the ground before the takeoff; a go-around to the manager.
  void follow_phase(const msg::State& s, Nanos now);

  Input<msg::State> state_;
  Input<msg::WaypointList> waypoints_;
  Input<msg::FlightPhase> phase_;
  Input<msg::Range> range_;
  Output<msg::CurrentPath> path_;
  Param<double> R_min_, default_altitude_, default_airspeed_, min_separation_, turn_bank_, wind_tau_;
  Param<std::int64_t> land_attempts_;
  Param<double> flare_time_, altitude_band_;
  Param<bool> orbit_last_;
  Param<std::string> corner_;

  std::unique_ptr<PathManager> manager_;  ///< made anew by reset()
  /// Everything else one flight changes: reset() replaces it wholesale.
  struct Flight {
    std::optional<std::uint32_t> revision;  ///< of the waypoint list the manager has
    // The state's wind estimate, low-passed with wind_tau (turn radii with turn_bank > 0).
    Vec3 wind = Vec3::Zero();
    std::optional<Nanos> wind_stamp;
    // Tracking of the estimated position on lines after the first waypoint (summary): sum of
    // squares, count, maximum of |cross-track error|, m.
    double xt_sq = 0.0, xt_max = 0.0;
    std::uint64_t xt_n = 0;
    // The estimate's altitude at rest before the takeoff, low-passed (home's ground), m; the
    // flight phase seen at the last step (a go-around leaves the approach).
    std::optional<double> home_h;
    Nanos home_stamp = 0;
    msg::Phase last_phase = msg::Phase::preflight;
    // The runway's NED down as the range finder sees it on the final, low-passed, m.
    std::optional<double> runway_d;
    Nanos runway_stamp = 0;
  } f_;
  void follow_runway(const msg::State& s, Nanos now);
};

/// path_follower: current_path + state -> controller_command (Va_c, h_c, chi_c, phi_ff), see
/// tern/path/follower.hpp.
class FollowerPlugin final : public Plugin {
 public:
  void configure() override;
  void step(Nanos now) override;
  void reset() override { f_ = Flight{}; }

 private:
  Input<msg::State> state_;
  Input<msg::CurrentPath> path_;
  Output<msg::ControllerCommand> command_;
  Param<double> chi_infty_, k_path_, k_orbit_;
  /// Everything one flight changes: reset() replaces it wholesale.
  struct Flight {
    bool warned_nan = false;  ///< the non-finite input was logged this flight
  } f_;
};

}  // namespace tern::path
