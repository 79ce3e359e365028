// tern/path/manager.hpp: the path manager of Beard & McLain, *Small Unmanned Aircraft*, ch. 11:
// turns a waypoint list into the segment (line or orbit) to follow now. Plain C++, no host types.
//
// Per waypoint, as ROSplane's path manager:
//   * use_chi            -> a Dubins path (Alg. 8) arriving at the waypoint with course chi_d;
//   * otherwise, corner = fillet (ROSplane's default) -> a fillet (Alg. 6) of radius R_min
//     rounds the corner at the waypoint; corner = line -> straight lines with half-plane
//     switching (Alg. 5).
// A Dubins segment starts from the previous waypoint and its chi_d when that waypoint was
// itself reached by a Dubins path (Alg. 8), otherwise from the aircraft's position and course
// at the moment the segment begins. (ROSplane picks Dubins by the waypoint flown *from*; tern by
// the waypoint flown *to*, matching the Waypoint message's "desired course at this waypoint".)
//
// A new list starts from the aircraft's position: the first leg runs from there (at the first
// waypoint's altitude) to waypoint 0. After the last waypoint the manager loops to waypoint 0
// (list loop = true and orbit_last = false) or orbits the last waypoint (radius R_min,
// clockwise). With no waypoints it orbits the origin at default_altitude.
//
// Degenerate input never yields NaN nor a stuck aircraft; each case is reported once per list
// through the warn callback and has a fallback:
//   * repeated waypoints (closer than min_separation horizontally, also last == first in a
//     loop): the repeat is skipped;
//   * non-finite waypoint positions: skipped; non-finite chi_d: the waypoint uses a fillet;
//     Va_d not > 0: default_airspeed;
//   * corners too sharp for a fillet of radius R_min (up to 180-degree doubling back): fly over
//     the waypoint, then turn onto the next leg (half-plane switching at the waypoint);
//   * Dubins waypoints closer than 2 R_min: RSL/LSR are impossible there, the shortest of the
//     possible types is flown (RSR and LSL always exist);
//   * one-waypoint missions: orbit the waypoint; two-waypoint loops: fly back and forth,
//     turning around beyond each waypoint (or Dubins turns when use_chi).
//
// Mission items (item.hpp): a `loiter` item is flown as an orbit (its radius, else the turn
// radius of an orbit; its direction) from the moment it becomes the target; the follower's orbit
// law brings the aircraft onto the circle. Once the aircraft is on the orbit (its distance to the
// centre within kOnOrbit of the radius) its time and turns count; when either is flown the
// manager goes on to the next item (leg from the loiter centre). With neither, the aircraft
// loiters until the list changes. A `return_home` item is a loiter at home (n = e = 0, the item's
// altitude) that never ends. The waypoint before a loiter item is passed over (no fillet into
// the orbit). A list of one loiter or return_home item is flown without the one-waypoint warning.
//
// A `land` item (item.hpp, landing.hpp) is the mission's end: a Dubins path to the approach's
// entry point arriving on the runway heading, then the glide path (Stage::land_final, a line
// whose segment is marked `landing`), which never switches: the phase machine takes the
// aircraft through flare and rollout. The touchdown altitude is measured from the home altitude
// (set_home_altitude: where the estimate put the ground before the takeoff), or once a range
// finder sees the runway on the final, from its measurement (set_runway_down: the estimate's
// altitude minus the height the range finder measures, as PX4's landing takes its terrain
// estimate; it assumes the ground under the final is level with the runway). go_around() (the
// phase machine's go-around, through the plugin) climbs out along the runway heading at the
// approach altitude until 2 turn radii past the touchdown point (or past the aircraft, if it is
// further), then flies the Dubins path to the entry point again; after land_attempts approaches
// the landing is abandoned: the aircraft orbits above the touchdown point at the approach
// altitude (warned once).
//
// Edits: a list that extends the current one (same first entries, same loop flag) is taken
// over at once without changing the segment being flown. Any other list takes effect at the
// next waypoint decision (when the current segment's waypoint is reached), and is then flown
// from waypoint 0; if the manager is orbiting (no list, or mission complete) it takes effect
// at once. An empty list takes effect at once: orbit the origin. A list marked `immediate` (a
// failsafe, or a mission edit with set_current) takes effect at the next update, from its
// first item, whatever is being flown.
#pragma once

#include <functional>
#include <optional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "tern/path/follower.hpp"
#include "tern/path/geometry.hpp"
#include "tern/path/item.hpp"
#include "tern/path/landing.hpp"

namespace tern::path {

/// One waypoint in local NED (the planner converts latitude/longitude before this).
struct MissionPoint {
  Vec3 w = Vec3::Zero();  ///< position NED, m (d = -altitude above the origin)
  double chi_d = 0.0;     ///< desired course at the waypoint, rad (used when use_chi)
  bool use_chi = false;   ///< arrive with course chi_d (Dubins path), else fillet/line
  double Va_d = 0.0;      ///< desired airspeed, m/s; <= 0: the manager's default_airspeed
  ItemType type = ItemType::waypoint;
  LoiterSpec loiter;    ///< loiter and return_home items (return_home: n and e ignored)
  LandSpec land;        ///< land items (chi_d: the runway heading; w: the touchdown point)
  double Vg_min = 0.0;  ///< least ground speed, m/s (0: none): airspeed() raises Va_d in a headwind
};

/// A loiter's time and turns count once |distance to the centre - radius| <= kOnOrbit * radius.
inline constexpr double kOnOrbit = 0.25;

struct ManagerConfig {
  enum class Corner { fillet, line };
  double R_min = 50.0;             ///< minimum turn radius (fillets, Dubins, orbits), m, > 0
  bool orbit_last = false;         ///< orbit the last waypoint instead of looping
  double default_altitude = 50.0;  ///< altitude of the origin orbit when there are no waypoints, m
  double default_airspeed = 15.0;  ///< airspeed when a waypoint has none, m/s, > 0
  Corner corner = Corner::fillet;  ///< corners of non-Dubins waypoints
  double min_separation = 1.0;     ///< waypoints closer than this (horizontally) repeat, m, > 0
  /// Bank angle the turns are planned for, rad, [0, 1.4]. 0 (ROSplane): every turn has radius
  /// R_min. > 0: each turn gets the radius at which a ground circle needs at most this bank at
  /// the highest ground speed of the turn in the wind given by set_wind() (wind_turn_radius()
  /// over the courses it sweeps; a turn through the downwind course needs (Va + |w|)^2 /
  /// (g tan(turn_bank))), never less than R_min. A fillet gets at most the radius whose
  /// tangent points lie within half of each of its legs (warned once), so that consecutive
  /// fillets never overlap; Dubins paths and orbits consider every course.
  double turn_bank = 0.0;
  int land_attempts = 3;  ///< approaches to a land item before the landing is abandoned, >= 1
  /// The flare's expected duration, s, [0, 30]: a land item's glide path is aimed
  /// aim_offset(Vg, flare_time, spec) before its touchdown point (landing.hpp), with Vg the
  /// ground speed along the runway at the item's airspeed in the wind given by set_wind() when
  /// the final approach is planned. 0: aimed at the touchdown point. ArduPlane's LAND_FLARE_SEC
  /// plays the same part (default 2 s).
  double flare_time = 3.0;
  /// A loiter with LoiterSpec::to_altitude goes on once the estimated altitude is within this of
  /// the item's, m, > 0 (the altitude loop's steady band: it settles, it does not cross exactly).
  double altitude_band = 5.0;
};

class PathManager {
 public:
  using Message = std::function<void(const std::string&)>;
  enum class Mode { origin_orbit, waypoint_orbit, route };
  enum class Stage {
    line,          ///< straight line to the waypoint, half-plane switching (Alg. 5)
    fillet_line,   ///< fillet, state 1 (Alg. 6): line until z1
    fillet_orbit,  ///< fillet, state 2: orbit until z2
    dubins_1,
    dubins_2,
    dubins_3,
    dubins_4,
    dubins_5,    ///< Alg. 8 states 1..5
    orbit,       ///< orbiting (origin, single waypoint, mission complete)
    loiter,      ///< orbiting a loiter or return_home item (time and turns count on the orbit)
    land_final,  ///< a land item's glide path (never switches)
    go_around,   ///< climbing out along the runway heading after a go-around
  };

  /// warn: one line per degenerate case (once per list, and for each case and waypoint number at
  /// most once a minute, so that lists re-sent by a coordination plugin do not repeat it every
  /// time); info: mission progress.
  explicit PathManager(ManagerConfig config = {}, Message warn = {}, Message info = {});

  /// New parameters; they apply from the next segment on. Throws std::invalid_argument if a
  /// value is out of range (R_min, default_airspeed, min_separation must be finite and > 0).
  void set_config(const ManagerConfig& config);
  const ManagerConfig& config() const { return cfg_; }

  /// A new waypoint list (see "Edits" above). loop: the list's own loop flag; immediate: fly it
  /// from the next update on, from its first item; loops > 0 (with loop): the items before a
  /// final land item are flown that many times, then the land item (none: the last is orbited).
  void set_waypoints(const std::vector<MissionPoint>& list, bool loop, bool immediate = false, int loops = 0);
  /// Loops of the list completed (back at its first item).
  int loops_done() const { return loops_done_; }

  /// The wind (NED m/s, the direction the air moves to) the turn radii are planned for when
  /// turn_bank > 0; it applies to segments that begin (and orbits) from now on. Non-finite
  /// values are ignored.
  void set_wind(const Vec3& wind);
  /// Radius of the current turn (fillet, Dubins path or orbit), m.
  double turn_radius() const { return seg_R_; }

  /// One step: p is the aircraft's NED position (m), chi its course (rad), t the flight time (s,
  /// non-decreasing: a loiter item's time). Returns the segment to follow now. A non-finite
  /// position keeps the previous segment (warned once).
  PathSegment update(const Vec3& p, double chi, double t);

  Mode mode() const { return mode_; }
  Stage stage() const { return stage_; }
  /// Index (in the list as given) of the waypoint being flown to or orbited, -1: none.
  int target() const;
  /// Indices (in the list they belonged to) of the waypoints passed so far, in order.
  const std::vector<int>& passed() const { return passed_; }
  /// Geometry of the current segment, valid in the fillet / Dubins stages.
  const Fillet& fillet() const { return fillet_; }
  const DubinsPath& dubins() const { return dubins_; }
  /// On a loiter item: the aircraft has reached the orbit; its turns flown since then.
  bool on_loiter_orbit() const { return loiter_on_; }
  double loiter_turns_flown() const;
  /// The estimate's altitude (m above the origin) of the ground at home: a land item's touchdown
  /// altitude is measured from it (applies to approaches planned from now on). Non-finite: ignored.
  void set_home_altitude(double h);
  /// The runway's NED down in the estimate's frame as a range finder measures it (p_d + the
  /// height above the ground), m: the glide path's touchdown point takes it from now on (the
  /// estimate's altitude drifts metres over a flight; the plugin low-passes it). Non-finite: ignored.
  void set_runway_down(double d);
  /// Abandons the current approach to a land item (no effect otherwise): climb out, come round
  /// for another approach, or after land_attempts orbit above the touchdown point.
  void go_around(const Vec3& p);
  /// Approaches flown to the current land item (0: none), and whether the landing was abandoned.
  int approaches() const { return approaches_; }
  bool landing_abandoned() const { return land_abandoned_; }
  /// The current land item's approach (valid once a land item became the target).
  const std::optional<Approach>& approach() const { return approach_; }
  /// Number of the waypoints as they are flown (after repeats were skipped).
  std::size_t active_count() const { return wps_.size(); }

  /// The item's airspeed (Va_d, else default_airspeed); with Vg_min (not on a land item) at least
  /// Vg_min + |wind|, the ground speed's floor on every course (an orbit's headwind side).
  double airspeed(const MissionPoint& w) const;
  /// The same on a line of horizontal direction q (zero: every course): at least |Vg_min q - wind|,
  /// the airspeed whose wind triangle (B&M eq. 2.10) gives Vg_min along q.
  double airspeed_along(const MissionPoint& w, const Vec3& q) const;

 private:
  struct Entry {
    MissionPoint wp;
    int index;  ///< index in the list as given
  };
  std::vector<Entry> clean(const std::vector<MissionPoint>& list);  ///< uses loop_, warns once
  void adopt(const std::vector<MissionPoint>& list, bool loop, const Vec3& p, double chi, int first);
  void start_route(std::size_t first, const Vec3& p, double chi);
  void begin_segment(const Vec3& p, double chi);
  void advance(const Vec3& p, double chi);
  std::optional<std::size_t> next_of(std::size_t i) const;
  /// True the first time `key` comes up for this list (and not within kRewarnInterval of its last).
  bool first_notice(const std::string& key);
  void warn_once(const std::string& key, const std::string& text);
  void inform_once(const std::string& key, const std::string& text);
  PathSegment orbit_segment(const Vec3& c, int index, double Va) const;
  /// The orbit of loiter or return_home entry `e`.
  PathSegment loiter_segment(const Entry& e) const;
  /// Counts the loiter's time and turns (aircraft at p, time t s); true when it is flown.
  bool loiter_done(const Vec3& p, double t);
  /// R_min, or with turn_bank > 0 the radius of a turn of `sweep` rad from course chi0 at Va.
  double planned_radius(double Va, double chi0, double sweep) const;
  PathSegment current_segment() const;
  /// Plans the approach to the land item being targeted and the Dubins path to its entry point.
  void begin_land(const Vec3& p, double chi);
  /// The segments of a land item's final approach, go-around and abandoned-landing orbit.
  PathSegment land_segment(const Entry& e) const;
  bool same_prefix(const std::vector<MissionPoint>& list, bool loop) const;

  ManagerConfig cfg_;
  Message warn_, info_;
  std::set<std::string> warned_;                   ///< keys warned for the current list
  std::map<std::string, double> warned_at_;        ///< when each key last warned, s (update()'s t)
  double now_ = 0.0;                               ///< s, the last update()'s t
  static constexpr double kRewarnInterval = 60.0;  ///< s: a later list repeats a case's warning after this long

  std::vector<MissionPoint> raw_;  ///< the list as given
  bool raw_loop_ = true;
  std::optional<std::pair<std::vector<MissionPoint>, bool>> pending_;
  bool need_adopt_ = false;   ///< raw_ was replaced while not on a route: adopt at next update
  int adopt_first_ = 0;       ///< ... starting at this index of raw_
  double seg_R_ = 50.0;       ///< turn radius of the current segment, m
  Vec3 wind_ = Vec3::Zero();  ///< wind for the turn radii, NED m/s

  std::vector<Entry> wps_;  ///< the list as flown (repeats skipped)
  bool loop_ = true;
  int raw_loops_ = 0, loops_ = 0;  ///< loops asked for (0: until the list changes) as given / as flown
  int pending_loops_ = 0;          ///< loops of the pending list
  int loops_done_ = 0;
  Mode mode_ = Mode::origin_orbit;
  Stage stage_ = Stage::orbit;
  std::size_t target_ = 0;
  Vec3 prev_ = Vec3::Zero();     ///< start of the current leg
  bool prev_chi_valid_ = false;  ///< the current leg starts at a waypoint reached by Dubins
  double prev_chi_ = 0.0;
  Vec3 switch_z_ = Vec3::Zero(), switch_n_ = Vec3::UnitX();  ///< line stage half-plane
  Fillet fillet_;
  DubinsPath dubins_;
  std::vector<int> passed_;
  PathSegment last_{};
  bool have_last_ = false;
  // the loiter being flown: on its orbit since loiter_since_ (s), angle swept in its direction
  // (rad), the aircraft's last bearing from the centre (rad)
  bool loiter_on_ = false;
  double loiter_since_ = 0.0, loiter_swept_ = 0.0, loiter_angle_ = 0.0;
  // the land item being flown: its approach, approaches begun, abandoned, home's altitude (m),
  // the go-around's climb-out line (start, switch point; along the runway heading)
  std::optional<Approach> approach_;
  int approaches_ = 0;
  bool land_abandoned_ = false;
  double home_h_ = 0.0;
  std::optional<double> runway_d_;  // set_runway_down
  Vec3 go_r_ = Vec3::Zero(), go_z_ = Vec3::Zero();
};

}  // namespace tern::path
