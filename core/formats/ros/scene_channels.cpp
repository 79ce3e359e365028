#include "ros/scene_channels.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "tern/common_frame.hpp"
#include "ros/scene_msgs.hpp"
#include "tern/aircraft.hpp"
#include "tern/math.hpp"
#include "tern/msg/path.hpp"
#include "tern/path/item.hpp"

namespace tern::core {

namespace {

// Drawing choices (what the panel shows, not what the aircraft is): the model's surfaces are
// boxes 12 % of their chord thick (a common airfoil's t/c), the horizontal tail a third of the
// span, the fin a sixth of it high, the fuselage a square section one chord wide.
constexpr double kThicknessOfChord = 0.12;
constexpr double kTailSpanOfSpan = 1.0 / 3.0;
constexpr double kFinHeightOfSpan = 1.0 / 6.0;
// The mission at its scale (hundreds of metres): points 3 m across, lines 0.5 m wide, an orbit
// as 72 chords (5 deg each).
constexpr double kPointDiameter = 3.0;
constexpr double kLineWidth = 0.5;
constexpr int kOrbitChords = 72;
// The wind arrow and each track's next segment: at most once a second of flight time; the arrow
// as long as the air moves in 5 s.
constexpr Nanos kSlowPeriod = 1'000'000'000;
constexpr double kWindArrowSeconds = 5.0;

using Color = std::array<float, 4>;
constexpr Color kTruthColor{0.95F, 0.55F, 0.10F, 1.0F};
constexpr Color kEstimateColor{0.20F, 0.55F, 0.95F, 0.45F};
constexpr Color kRouteColor{0.90F, 0.90F, 0.90F, 1.0F};
constexpr Color kHomeColor{0.20F, 0.80F, 0.30F, 1.0F};
constexpr Color kLandColor{0.95F, 0.85F, 0.20F, 1.0F};
constexpr Color kPathColor{0.95F, 0.20F, 0.60F, 1.0F};
constexpr Color kWindColor{0.40F, 0.85F, 0.95F, 1.0F};

const msg::State& as_state(const void* m) { return *static_cast<const msg::State*>(m); }

RosMarker marker(Nanos stamp, std::string frame, std::string ns, std::int32_t id, RosMarker::Type type, const Color& color) {
  RosMarker m;
  m.stamp = stamp;
  m.frame_id = std::move(frame);
  m.ns = std::move(ns);
  m.id = id;
  m.type = type;
  m.color = color;
  // drawn where its frame is now: the panel need not find the frame at the marker's stamp (the
  // mission is stamped before the estimate's first transform)
  m.frame_locked = true;
  return m;
}

RosMarker line(Nanos stamp, const std::string& frame, std::string ns, std::int32_t id, RosMarker::Type type, const Color& color) {
  RosMarker m = marker(stamp, frame, std::move(ns), id, type, color);
  m.scale = Eigen::Vector3d(kLineWidth, kLineWidth, kLineWidth);
  return m;
}

// The orbit about `c` (NED) of radius rho, as ENU points (closed: the first point again at the end).
std::vector<Eigen::Vector3d> orbit_points(const Eigen::Vector3d& c, double rho) {
  std::vector<Eigen::Vector3d> pts;
  for (int k = 0; k <= kOrbitChords; ++k) {
    const double a = 2.0 * kPi * k / kOrbitChords;
    pts.push_back(enu_of_ned(c + rho * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0)));
  }
  return pts;
}

void append_segments(std::vector<Eigen::Vector3d>& list, const std::vector<Eigen::Vector3d>& strip) {
  for (std::size_t k = 1; k < strip.size(); ++k) {
    list.push_back(strip[k - 1]);
    list.push_back(strip[k]);
  }
}

// The model's boxes in `frame` (FLU), as o's dimensions give them.
std::vector<RosMarker> model_markers(const SceneOptions& o, Nanos stamp, const std::string& frame, const std::string& ns,
                                     const Color& color) {
  const double t = kThicknessOfChord * o.chord;
  const double tail_x = o.tail_x + 0.5 * o.chord;  // the tail surfaces' trailing edges at the tail point
  const double tail_z = -o.tail_z;                 // FRD -> FLU
  struct Box {
    Eigen::Vector3d centre, size;
  };
  const Box boxes[] = {{{0.5 * (o.nose_x + o.tail_x), 0.0, 0.0}, {o.nose_x - o.tail_x, o.chord, o.chord}},  // fuselage
                       {{0.0, 0.0, 0.0}, {o.chord, o.span, t}},                                             // wing
                       {{tail_x, 0.0, tail_z}, {o.chord, kTailSpanOfSpan * o.span, t}},                     // horizontal tail
                       {{tail_x, 0.0, tail_z + 0.5 * kFinHeightOfSpan * o.span}, {o.chord, t, kFinHeightOfSpan * o.span}}};  // fin
  std::vector<RosMarker> out;
  for (const Box& b : boxes) {
    RosMarker m = marker(stamp, frame, ns, static_cast<std::int32_t>(out.size()), RosMarker::cube, color);
    m.position = b.centre;
    m.scale = b.size;
    out.push_back(std::move(m));
  }
  return out;
}

// Where an item is flown to, NED: home (n = e = 0) at the item's altitude for a return_home.
Eigen::Vector3d item_point(const msg::Waypoint& w) {
  return w.type == msg::Waypoint::return_home ? Eigen::Vector3d(0.0, 0.0, w.w.z()) : w.w;
}

bool same_path(const msg::CurrentPath& a, const msg::CurrentPath& b) {
  return a.path_type == b.path_type && a.r == b.r && a.q == b.q && a.c == b.c && a.rho == b.rho && a.landing == b.landing &&
         a.waypoint_index == b.waypoint_index;
}

}  // namespace

Eigen::Vector3d enu_of_ned(const Eigen::Vector3d& ned) { return {ned.y(), ned.x(), -ned.z()}; }

Eigen::Quaterniond flu_attitude_in_enu(const Eigen::Quaterniond& frd_to_ned) {
  // ENU <- NED swaps x and y and turns z over: 180 deg about (1, 1, 0)/sqrt(2); FRD <- FLU: 180 deg about x
  const double h = std::sqrt(0.5);
  const Eigen::Quaterniond ned_to_enu(0.0, h, h, 0.0);
  const Eigen::Quaterniond flu_to_frd(0.0, 1.0, 0.0, 0.0);
  return (ned_to_enu * frd_to_ned * flu_to_frd).normalized();
}

SceneOptions scene_options(const std::string& aircraft, const std::string& fleet_part) {
  SceneOptions o;
  if (!fleet_part.empty()) o.frame_prefix = fleet_part + "/";
  if (aircraft.empty()) return o;
  const Aircraft ac = load_aircraft(aircraft);
  o.span = ac.b;
  o.chord = ac.c;
  const auto defaults = default_structure(ac.b);  // nose and tail where the file names other points
  auto point = [&](const std::string& name) {
    for (const auto* list : {&ac.gear.structure, &defaults})
      for (const auto& [n, p] : *list)
        if (n == name) return p;
    return ContactPoint{};
  };
  o.nose_x = point("nose").x();
  o.tail_x = point("tail").x();
  o.tail_z = point("tail").z();
  return o;
}

// ---- the scene's state and encoders ------------------------------------------------------------

struct Scene::State {
  SceneOptions o;
  std::optional<CommonFrame> map;       // about the first valid origin seen
  bool model_sent[2] = {false, false};  // truth's, the estimate's
  msg::WaypointList list{};
  bool has_list = false;
  Eigen::Vector3d estimate = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());  // NED, map_estimate
  std::optional<msg::CurrentPath> path;                                                            // last drawn
  Nanos last_wind = std::numeric_limits<Nanos>::min() / 2;
  struct Track {                          // truth's, the estimate's
    std::optional<Eigen::Vector3d> last;  // ENU, its frame
    Nanos t = 0;
    std::int32_t segments = 0;
  } tracks[2];

  std::string frame(const char* name) const { return o.frame_prefix + name; }
  // a marker namespace, prefixed as the frames: a fleet's files opened together keep their markers apart
  std::string ns(const char* name) const { return o.frame_prefix + name; }
  void see(const msg::State& s) {
    if (!map && s.origin_valid) map.emplace(origin_of(s));
  }
  // A State's position in map (NED, m).
  Eigen::Vector3d in_map(const msg::State& s) const {
    return map && s.origin_valid ? map->ned(origin_of(s), position_of(s)) : position_of(s);
  }
  // The estimate's origin in map (NED, m): zero until the estimate has one.
  Eigen::Vector3d estimate_origin(const msg::State& s) const {
    return map && s.origin_valid ? map->ned(origin_of(s)) : Eigen::Vector3d::Zero();
  }

  void truth_tf(const msg::State& s, std::vector<std::string>& out);
  void estimate_tf(const msg::State& s, std::vector<std::string>& out);
  void model(bool truth, const msg::State& s, std::vector<std::string>& out);
  void wind(const msg::State& s, std::vector<std::string>& out);
  void track(bool truth, const msg::State& s, std::vector<std::string>& out);
  void mission(const msg::WaypointList& l, std::vector<std::string>& out);
  void current_path(const msg::CurrentPath& p, std::vector<std::string>& out);
  std::vector<Eigen::Vector3d> route() const;
  void add_land(const msg::Waypoint& w, std::vector<RosMarker>& markers) const;
};

namespace {
void put(std::vector<std::string>& out, const std::vector<RosTransform>& tf) {
  out.emplace_back();
  encode_tf_message(tf, out.back());
}
void put(std::vector<std::string>& out, const std::vector<RosMarker>& markers) {
  out.emplace_back();
  encode_marker_array(markers, out.back());
}
}  // namespace

void Scene::State::truth_tf(const msg::State& s, std::vector<std::string>& out) {
  see(s);
  put(out, {{s.stamp, "map", frame("base_link"), enu_of_ned(in_map(s)), flu_attitude_in_enu(s.quat)}});
}

void Scene::State::estimate_tf(const msg::State& s, std::vector<std::string>& out) {
  see(s);
  estimate = position_of(s);
  put(out, {{s.stamp, "map", frame("map_estimate"), enu_of_ned(estimate_origin(s)), Eigen::Quaterniond::Identity()},
            {s.stamp, frame("map_estimate"), frame("base_link_estimate"), enu_of_ned(position_of(s)), flu_attitude_in_enu(s.quat)}});
}

void Scene::State::model(bool truth, const msg::State& s, std::vector<std::string>& out) {
  bool& sent = model_sent[truth ? 0 : 1];
  if (sent || o.span <= 0.0) return;
  sent = true;
  put(out, truth ? model_markers(o, s.stamp, frame("base_link"), ns("truth"), kTruthColor)
                 : model_markers(o, s.stamp, frame("base_link_estimate"), ns("estimate"), kEstimateColor));
}

void Scene::State::wind(const msg::State& s, std::vector<std::string>& out) {
  see(s);
  if (s.stamp - last_wind < kSlowPeriod) return;
  last_wind = s.stamp;
  RosMarker m = line(s.stamp, "map", ns("wind"), 0, RosMarker::arrow, kWindColor);
  m.scale = Eigen::Vector3d(kLineWidth, 2.0 * kLineWidth, 2.0 * kLineWidth);  // shaft and head diameters, head length
  const Eigen::Vector3d from = in_map(s);
  m.points = {enu_of_ned(from), enu_of_ned(from + kWindArrowSeconds * Eigen::Vector3d(s.w_n, s.w_e, s.w_d))};
  put(out, {m});
}

void Scene::State::track(bool truth, const msg::State& s, std::vector<std::string>& out) {
  see(s);
  Track& k = tracks[truth ? 0 : 1];
  const Eigen::Vector3d p = enu_of_ned(truth ? in_map(s) : position_of(s));
  if (!p.allFinite() || (k.last && s.stamp - k.t < kSlowPeriod)) return;
  if (k.last) {  // one segment a marker of its own (ids 0, 1 ...): the panel keeps them all
    RosMarker m = line(s.stamp, truth ? "map" : frame("map_estimate"), ns(truth ? "truth_track" : "estimate_track"), k.segments++,
                       RosMarker::line_list, truth ? kTruthColor : kEstimateColor);
    m.points = {*k.last, p};
    put(out, {m});
  }
  k.last = p;
  k.t = s.stamp;
}

std::vector<Eigen::Vector3d> Scene::State::route() const {
  std::vector<Eigen::Vector3d> pts;  // NED
  for (std::uint32_t i = 0; i < std::min<std::uint32_t>(list.count, msg::WaypointList::kCapacity); ++i) {
    const msg::Waypoint& w = list.items[i];
    if (w.lla) continue;  // not yet converted by the planner (no origin)
    pts.push_back(item_point(w));
  }
  return pts;
}

void Scene::State::add_land(const msg::Waypoint& w, std::vector<RosMarker>& markers) const {
  // the glide path from kMinEntryHeights decision heights down to the touchdown point w along the
  // runway heading chi_d; the runway's centre line on the ground below the glide path from the
  // decision height, continued as far past the touchdown point
  const Eigen::Vector3d along(std::cos(w.chi_d), std::sin(w.chi_d), 0.0);
  const double entry_h = path::kMinEntryHeights * w.land_decision_height;
  const double tan_gs = std::tan(w.land_glide_slope);
  RosMarker glide = line(0, frame("map_estimate"), ns("mission"), 3, RosMarker::line_strip, kLandColor);
  glide.points = {enu_of_ned(w.w - along * (entry_h / tan_gs) - Eigen::Vector3d(0.0, 0.0, entry_h)), enu_of_ned(w.w)};
  RosMarker runway = line(0, frame("map_estimate"), ns("mission"), 4, RosMarker::line_strip, kLandColor);
  runway.scale.x() = o.span > 0.0 ? o.span : kLineWidth;  // as wide as the aircraft's span
  const Eigen::Vector3d reach = along * (w.land_decision_height / tan_gs);
  runway.points = {enu_of_ned(w.w - reach), enu_of_ned(w.w + reach)};
  markers.push_back(std::move(glide));
  markers.push_back(std::move(runway));
}

void Scene::State::mission(const msg::WaypointList& l, std::vector<std::string>& out) {
  if (has_list && l.revision == list.revision) return;
  list = l;
  has_list = true;
  const std::string f = frame("map_estimate");
  RosMarker points = marker(l.stamp, f, ns("mission"), 0, RosMarker::sphere_list, kRouteColor);
  points.scale = Eigen::Vector3d::Constant(kPointDiameter);
  RosMarker route_line = line(l.stamp, f, ns("mission"), 1, RosMarker::line_strip, kRouteColor);
  RosMarker orbits = line(l.stamp, f, ns("mission"), 2, RosMarker::line_list, kRouteColor);
  for (const Eigen::Vector3d& p : route()) points.points.push_back(enu_of_ned(p));
  route_line.points = points.points;
  if (l.loop && route_line.points.size() > 2) route_line.points.push_back(route_line.points.front());
  std::vector<RosMarker> markers;
  for (std::uint32_t i = 0; i < std::min<std::uint32_t>(l.count, msg::WaypointList::kCapacity); ++i) {
    const msg::Waypoint& w = l.items[i];
    if (w.lla) continue;
    const bool orbit = w.type == msg::Waypoint::loiter || w.type == msg::Waypoint::return_home;
    if (orbit && w.loiter_radius > 0.0)  // radius 0: the path manager's turn radius, not in the list
      append_segments(orbits.points, orbit_points(item_point(w), w.loiter_radius));
    if (w.type == msg::Waypoint::land) add_land(w, markers);
  }
  if (markers.empty()) {  // no land item: its glide path and runway of an earlier revision go
    markers.push_back(line(l.stamp, f, ns("mission"), 3, RosMarker::line_strip, kLandColor));
    markers.push_back(line(l.stamp, f, ns("mission"), 4, RosMarker::line_strip, kLandColor));
  }
  RosMarker home = marker(l.stamp, f, ns("mission"), 5, RosMarker::sphere, kHomeColor);
  home.scale = Eigen::Vector3d::Constant(kPointDiameter);
  for (RosMarker* m : {&points, &route_line, &orbits, &home}) markers.push_back(std::move(*m));
  for (RosMarker& m : markers) m.stamp = l.stamp;
  put(out, markers);
}

void Scene::State::current_path(const msg::CurrentPath& p, std::vector<std::string>& out) {
  if (path && same_path(*path, p)) return;
  path = p;
  RosMarker m = line(p.stamp, frame("map_estimate"), ns("current_path"), 0, RosMarker::line_strip, kPathColor);
  if (p.path_type == msg::CurrentPath::orbit) {
    m.points = orbit_points(p.c, p.rho);
  } else {
    // from r, through the aircraft's and the target waypoint's places along the line
    double lo = 0.0, hi = 0.0;
    auto cover = [&](const Eigen::Vector3d& x) {
      const double s = p.q.dot(x - p.r);
      if (std::isfinite(s)) lo = std::min(lo, s), hi = std::max(hi, s);
    };
    cover(estimate);
    const auto i = p.waypoint_index;
    if (has_list && i >= 0 && static_cast<std::uint32_t>(i) < std::min<std::uint32_t>(list.count, msg::WaypointList::kCapacity) &&
        !list.items[static_cast<std::size_t>(i)].lla)
      cover(list.items[static_cast<std::size_t>(i)].w);
    m.points = {enu_of_ned(p.r + lo * p.q), enu_of_ned(p.r + hi * p.q)};
  }
  put(out, {m});
}

// ---- the channels --------------------------------------------------------------------------------

Scene::Scene(SceneOptions options) : state_(std::make_shared<State>()) { state_->o = std::move(options); }
Scene::~Scene() = default;

std::vector<RosChannel> Scene::channels_of(std::string_view topic, std::string_view type_name) {
  std::shared_ptr<State> s = state_;
  std::vector<RosChannel> out;
  auto add = [&](const char* channel, const char* type, std::string schema, auto encode) {
    out.push_back({channel, type, std::move(schema), encode});
  };
  const bool state = type_name == msg::State::type_name;
  if (state && (topic == "truth" || topic == "state")) {
    const bool truth = topic == "truth";
    add("/tf", kTfMessageType, tf_message_schema(),
        [s, truth](const void* m, std::vector<std::string>& o) { truth ? s->truth_tf(as_state(m), o) : s->estimate_tf(as_state(m), o); });
    add("/tern/markers/aircraft", kMarkerArrayType, marker_array_schema(),
        [s, truth](const void* m, std::vector<std::string>& o) { s->model(truth, as_state(m), o); });
    add("/tern/markers/track", kMarkerArrayType, marker_array_schema(),
        [s, truth](const void* m, std::vector<std::string>& o) { s->track(truth, as_state(m), o); });
    if (truth)
      add("/tern/markers/wind", kMarkerArrayType, marker_array_schema(),
          [s](const void* m, std::vector<std::string>& o) { s->wind(as_state(m), o); });
  } else if (topic == "waypoints" && type_name == msg::WaypointList::type_name) {
    add("/tern/markers/mission", kMarkerArrayType, marker_array_schema(),
        [s](const void* m, std::vector<std::string>& o) { s->mission(*static_cast<const msg::WaypointList*>(m), o); });
  } else if (topic == "current_path" && type_name == msg::CurrentPath::type_name) {
    add("/tern/markers/current_path", kMarkerArrayType, marker_array_schema(),
        [s](const void* m, std::vector<std::string>& o) { s->current_path(*static_cast<const msg::CurrentPath*>(m), o); });
  }
  return out;
}

}  // namespace tern::core
