// Mission reading and LLA -> NED conversion. See mission.hpp.
#include "tern/path/mission.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "entry_text.hpp"
#include "number_text.hpp"
#include "tern/input_file.hpp"
#include "tern/math.hpp"
#include "tern/yaml_keys.hpp"

namespace tern::path {

namespace {

std::string num(double v) { return number_text(v); }

/// "<source>: line N: " (line N omitted when unknown).
std::string at(const std::string& source, const YAML::Mark& m, int line_offset = 0) {
  if (m.line >= 0) return source + ":" + std::to_string(m.line + 1 + line_offset) + ": ";
  return source + ": ";
}

std::string at(const std::string& source, const YAML::Node& n, int line_offset = 0) { return at(source, n.Mark(), line_offset); }

struct Ctx {
  std::string source;
  int line_offset = 0;  ///< added to yaml-cpp's line numbers (ROSplane chunks)
  std::string prefix(const YAML::Node& n) const { return at(source, n, line_offset); }
};

double as_double(const YAML::Node& n, const Ctx& c, const std::string& field) {
  if (!n.IsScalar()) throw MissionError(c.prefix(n) + field + ": expected a number");
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    throw MissionError(c.prefix(n) + field + ": '" + n.Scalar() + "' is not a number");
  }
  if (!std::isfinite(v)) throw MissionError(c.prefix(n) + field + ": value " + n.Scalar() + " is not finite");
  return v;
}

bool as_bool(const YAML::Node& n, const Ctx& c, const std::string& field) {
  if (!n.IsScalar()) throw MissionError(c.prefix(n) + field + ": expected true or false");
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    throw MissionError(c.prefix(n) + field + ": '" + n.Scalar() + "' is not true or false");
  }
}

/// A map's key as a name: a list or a map where a key belongs (`{[1, 2]: 3}`) is refused here,
/// not left to yaml-cpp's bare "bad conversion".
std::string key_name(const YAML::Node& key, const Ctx& c, const std::string& where) {
  if (!key.IsScalar())
    throw MissionError(c.prefix(key) + where + "a key is a name, got a " + (key.IsSequence() ? "list" : key.IsMap() ? "map" : "null"));
  return key.Scalar();
}

/// Throws MissionError "<source>:<line>: WHERE key 'k' given twice (first at line N)" for a key
/// `map` holds twice (tern/yaml_keys.hpp).
void check_unique_keys(const YAML::Node& map, const Ctx& c, const std::string& where) {
  if (const auto r = repeated_key(map))
    throw MissionError(at(c.source, r->again, c.line_offset) + where + "key '" + printable(r->key) + "' given twice (first at line " +
                       std::to_string(r->first.line + 1 + c.line_offset) + "): one of the two would be ignored");
}

Eigen::Vector3d as_vec3(const YAML::Node& n, const Ctx& c, const std::string& field) {
  if (!n.IsSequence() || n.size() != 3) throw MissionError(c.prefix(n) + field + ": expected a list of 3 numbers");
  Eigen::Vector3d v;
  for (std::size_t i = 0; i < 3; ++i) v[static_cast<Eigen::Index>(i)] = as_double(n[i], c, field + "[" + std::to_string(i) + "]");
  return v;
}

ItemType as_item_type(const YAML::Node& n, const Ctx& c, const std::string& field) {
  const std::string t = n.IsScalar() ? n.Scalar() : "";
  if (t == "waypoint") return ItemType::waypoint;
  if (t == "loiter") return ItemType::loiter;
  if (t == "return_home") return ItemType::return_home;
  if (t == "land") return ItemType::land;
  throw MissionError(c.prefix(n) + field + ": '" + t + "' is not a mission item type (expected waypoint, loiter, return_home or land)");
}

int as_direction(const YAML::Node& n, const Ctx& c, const std::string& field) {
  const std::string d = n.IsScalar() ? n.Scalar() : "";
  if (d == "cw" || d == "1") return 1;
  if (d == "ccw" || d == "-1") return -1;
  throw MissionError(c.prefix(n) + field + ": '" + d + "' is not an orbit direction (expected cw or ccw)");
}

double as_non_negative(const YAML::Node& n, const Ctx& c, const std::string& field, const char* unit) {
  const double v = as_double(n, c, field);
  if (v < 0.0) throw MissionError(c.prefix(n) + field + ": " + num(v) + unit + " is negative");
  return v;
}

/// The entry's keys that only some item types take; checked once the type is known.
struct ItemKeys {
  bool radius = false, direction = false, time = false, turns = false, to_altitude = false, chi = false;  // given
  bool chi_d = false, heading = false, land = false;  // given; land: glide_slope, flare_height or decision_height
  YAML::Node altitude, heading_value;                 // (null when not given)
};

// A land item: the keys it takes, and its runway heading (`heading`, or ROSplane's `chi_d`).
void finish_land(MissionWaypoint& wp, const ItemKeys& k, const YAML::Node& n, const Ctx& c, const std::string& name) {
  if (k.radius || k.direction || k.time || k.turns || k.to_altitude)
    throw MissionError(c.prefix(n) + name + ": a land item takes no radius, direction, time, turns or to_altitude (those are loiter keys)");
  if (wp.use_chi) throw MissionError(c.prefix(n) + name + ": use_chi: true is for waypoints (a land item always arrives on its heading)");
  if (k.heading && k.chi_d) throw MissionError(c.prefix(n) + name + ": give the runway heading once: heading or chi_d, not both");
  if (k.heading) wp.chi_d = as_double(k.heading_value, c, name + ".heading");
  if (!k.heading && !k.chi_d)
    throw MissionError(c.prefix(n) + name + ": a land item needs heading: the runway heading, rad (the course of the final approach)");
}

// Type-specific checks and the return_home position (altitude: NaN when not given, filled in
// by fill_return_home_altitudes()).
void finish_item(MissionWaypoint& wp, int positions, const ItemKeys& k, const YAML::Node& n, const Ctx& c, const std::string& name) {
  const bool orbit = wp.type == ItemType::loiter || wp.type == ItemType::return_home;
  const char* type = item_type_name(wp.type);
  if (wp.type != ItemType::land && k.heading)
    throw MissionError(c.prefix(n) + name + ": heading is a land item's runway heading (a " + type + " takes chi_d)");
  if (wp.type != ItemType::land && k.land)
    throw MissionError(c.prefix(n) + name + ": glide_slope, flare_height and decision_height are for land items (type: land)");
  if (wp.type == ItemType::land) finish_land(wp, k, n, c, name);
  if (!orbit && (k.radius || k.direction || k.time || k.turns || k.to_altitude))
    throw MissionError(c.prefix(n) + name +
                       ": radius, direction, time, turns and to_altitude are for loiter and return_home items (type: loiter)");
  if (orbit && k.chi) throw MissionError(c.prefix(n) + name + ": a " + type + " item takes no chi_d or use_chi");
  if (wp.type == ItemType::return_home && (k.time || k.turns || k.to_altitude))
    throw MissionError(c.prefix(n) + name + ": return_home loiters until the mission changes: no time, turns or to_altitude");
  if (wp.type != ItemType::return_home && k.altitude.IsDefined() && !k.altitude.IsNull())
    throw MissionError(c.prefix(n) + name + ": altitude is for return_home items (others give a position)");
  if (wp.type == ItemType::return_home) {
    if (positions > 0) throw MissionError(c.prefix(n) + name + ": return_home takes no position (home is the origin): give altitude");
    const double alt = k.altitude.IsDefined() && !k.altitude.IsNull() ? as_double(k.altitude, c, name + ".altitude") : std::nan("");
    wp.w = Eigen::Vector3d(0.0, 0.0, -alt);
    return;
  }
  if (positions == 0) throw MissionError(c.prefix(n) + name + ": no position (ned, w or lla: [lat, lon, alt])");
  if (positions > 1) throw MissionError(c.prefix(n) + name + ": more than one position (ned, w, lla)");
}

const std::vector<std::string> kEntryKeys = {
    "ned",  "w",     "lla",         "chi_d",  "use_chi",  "Va_d",    "va_d",        "type",         "radius",         "direction",
    "time", "turns", "to_altitude", "Vg_min", "altitude", "heading", "glide_slope", "flare_height", "decision_height"};

// The keys of loiter, return_home and land items (item.hpp); false for any other key.
bool parse_item_key(const std::string& key, const YAML::Node& v, const Ctx& c, const std::string& field, MissionWaypoint& wp, ItemKeys& k) {
  if (key == "type") {
    wp.type = as_item_type(v, c, field);
  } else if (key == "radius") {
    wp.loiter.radius = as_non_negative(v, c, field, " m");
    k.radius = true;
  } else if (key == "direction") {
    wp.loiter.direction = as_direction(v, c, field);
    k.direction = true;
  } else if (key == "time") {
    wp.loiter.time = as_non_negative(v, c, field, " s");
    k.time = true;
  } else if (key == "turns") {
    wp.loiter.turns = as_non_negative(v, c, field, " turns");
    k.turns = true;
  } else if (key == "to_altitude") {
    wp.loiter.to_altitude = as_bool(v, c, field);
    k.to_altitude = true;
  } else if (key == "heading") {
    k.heading = true;
    k.heading_value = v;
  } else if (key == "glide_slope") {
    wp.land.glide_slope = as_double(v, c, field);
    k.land = true;
  } else if (key == "flare_height") {
    wp.land.flare_height = as_double(v, c, field);
    k.land = true;
  } else if (key == "decision_height") {
    wp.land.decision_height = as_double(v, c, field);
    k.land = true;
  } else if (key == "altitude") {
    k.altitude = v;
  } else {
    return false;
  }
  return true;
}

MissionWaypoint parse_entry(const YAML::Node& n, const Ctx& c, const std::string& name, double default_Va) {
  MissionWaypoint wp;
  wp.Va_d = default_Va;
  wp.field = name;
  wp.source = c.source;
  if (n.Mark().line >= 0) wp.line = n.Mark().line + 1 + c.line_offset;
  if (n.IsSequence()) {
    wp.w = as_vec3(n, c, name);
    validate_waypoint(wp, c.prefix(n) + name);
    return wp;
  }
  if (!n.IsMap()) throw MissionError(c.prefix(n) + name + ": expected [n, e, d] or a map with ned, w or lla");
  check_unique_keys(n, c, name + ": ");
  int positions = 0;
  bool lla_flag = false;
  ItemKeys k;
  for (const auto& kv : n) {
    const std::string key = key_name(kv.first, c, name + ": ");
    const YAML::Node& v = kv.second;
    const std::string field = name + "." + key;
    if (key == "ned" || key == "w") {
      wp.w = as_vec3(v, c, field);
      ++positions;
    } else if (key == "lla") {
      if (v.IsSequence()) {
        wp.w = as_vec3(v, c, field);
        wp.lla = true;
        ++positions;
      } else {
        lla_flag = as_bool(v, c, field);
      }
    } else if (key == "chi_d") {
      wp.chi_d = as_double(v, c, field);
      k.chi = k.chi_d = true;
    } else if (key == "use_chi") {
      wp.use_chi = as_bool(v, c, field);
      k.chi = true;
    } else if (key == "Va_d" || key == "va_d") {
      wp.Va_d = as_double(v, c, field);
    } else if (key == "Vg_min") {
      wp.Vg_min = as_double(v, c, field);
    } else if (!parse_item_key(key, v, c, field, wp, k)) {
      throw MissionError(c.prefix(kv.first) + name + ": ", key, kEntryKeys);
    }
  }
  finish_item(wp, positions, k, n, c, name);
  if (lla_flag) {
    if (wp.lla) throw MissionError(c.prefix(n) + name + ": lla: true given with an lla position");
    if (wp.type == ItemType::return_home) throw MissionError(c.prefix(n) + name + ": return_home takes no lla (home is the origin)");
    wp.lla = true;
  }
  if (wp.type != ItemType::return_home || std::isfinite(wp.w.z())) validate_waypoint(wp, c.prefix(n) + name);
  return wp;
}

// A return_home without `altitude` keeps the altitude of the item before it.
void fill_return_home_altitudes(Mission& m) {
  for (std::size_t i = 0; i < m.waypoints.size(); ++i) {
    MissionWaypoint& wp = m.waypoints[i];
    if (wp.type != ItemType::return_home || std::isfinite(wp.w.z())) continue;
    const std::string name = m.source + ": item " + std::to_string(i + 1) + " (return_home)";
    if (i == 0) throw MissionError(name + ": no altitude, and no item before it to keep the altitude of: give altitude");
    if (m.waypoints[i - 1].lla) throw MissionError(name + ": no altitude, and the item before it is lat/lon (MSL): give altitude");
    wp.w.z() = m.waypoints[i - 1].w.z();
  }
}

bool orbits_forever(const MissionWaypoint& wp) {
  return wp.type == ItemType::return_home ||
         (wp.type == ItemType::loiter && wp.loiter.time <= 0.0 && wp.loiter.turns <= 0.0 && !wp.loiter.to_altitude);
}

}  // namespace

void check_land_last(const Mission& m) {
  const auto& w = m.waypoints;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w[i].type != ItemType::land) continue;
    const std::string land = w[i].field.empty() ? "the land item" : "the land item " + w[i].field;
    if (i + 1 < w.size()) throw MissionError(entry_prefix(m, w[i + 1]) + "comes after " + land + ", which ends the mission: never reached");
    if (i > 0 && orbits_forever(w[i - 1]))
      throw MissionError(entry_prefix(m, w[i]) + "never reached: the item before it (" + item_type_name(w[i - 1].type) +
                         ") orbits until the mission changes (a loiter before a landing needs time, turns or to_altitude)");
  }
}

namespace {

// A mission that ends with a land item flies the items before it `loops` times, else once: a
// loop without a count would never reach the landing. `loop` (null: not given) is this map's.
void settle_landing_loop(Mission& m, const YAML::Node& loop, const Ctx& c) {
  check_land_last(m);
  if (m.waypoints.empty() || m.waypoints.back().type != ItemType::land) return;
  if (loop && loop.IsScalar() && m.loop && m.loops == 0)
    throw MissionError(c.prefix(loop) + "loop: true would never reach the land item " + m.waypoints.back().field +
                       ": give loops: N (the items before it flown N times, then the landing), or leave loop out (once)");
  m.loop = m.loops > 0;
}

/// The keys shared by the config section and a tern waypoint file.
Mission parse_map(const YAML::Node& root, const Ctx& c, bool allow_file, const std::filesystem::path& base_dir) {
  Mission m;
  m.source = c.source;
  if (!root || root.IsNull()) return m;
  if (!root.IsMap()) throw MissionError(c.prefix(root) + "expected a map with waypoints (or file)");
  check_unique_keys(root, c, "");
  double default_Va = 0.0;
  if (root["Va_d"]) {
    default_Va = as_double(root["Va_d"], c, "Va_d");
    if (default_Va < 0.0) throw MissionError(c.prefix(root["Va_d"]) + "Va_d: " + num(default_Va) + " m/s is negative");
  }
  bool have_file = false, have_wps = false;
  for (const auto& kv : root) {
    const std::string key = key_name(kv.first, c, "");
    if (key == "loop") {
      m.loop = as_bool(kv.second, c, "loop");
    } else if (key == "loops") {
      const double n = as_double(kv.second, c, "loops");
      if (!(n >= 1.0 && n <= 1000.0 && n == std::floor(n)))
        throw MissionError(c.prefix(kv.second) + "loops: " + num(n) + " is not a whole number of loops in [1, 1000]");
      m.loops = static_cast<int>(n);
    } else if (key == "Va_d") {
    } else if (key == "waypoints") {
      have_wps = true;
      const YAML::Node& list = kv.second;
      if (list.IsNull()) continue;
      if (!list.IsSequence()) throw MissionError(c.prefix(list) + "waypoints: expected a list");
      for (std::size_t i = 0; i < list.size(); ++i)
        m.waypoints.push_back(parse_entry(list[i], c, "waypoints[" + std::to_string(i) + "]", default_Va));
      fill_return_home_altitudes(m);
    } else if (key == "file" && allow_file) {
      have_file = true;
    } else {
      throw MissionError(c.prefix(kv.first), key,
                         allow_file ? std::vector<std::string>{"waypoints", "file", "loop", "loops", "Va_d"}
                                    : std::vector<std::string>{"waypoints", "loop", "loops", "Va_d"});
    }
  }
  if (m.loops > 0) m.loop = true;
  if (have_file) {
    if (!root["file"].IsScalar()) throw MissionError(c.prefix(root["file"]) + "file: expected a path");
    std::filesystem::path f = root["file"].as<std::string>();
    if (f.is_relative()) f = (base_dir / f).lexically_normal();
    const bool loop_set = static_cast<bool>(root["loop"]);
    Mission from_file = load_mission_file(f);
    if (loop_set || m.loops > 0) from_file.loop = m.loop;
    if (m.loops > 0) from_file.loops = m.loops;
    if (default_Va > 0.0)
      for (auto& wp : from_file.waypoints)
        if (wp.Va_d <= 0.0) wp.Va_d = default_Va;
    // `waypoints` beside `file`: the file's items, then these (a land item after a shared route)
    if (have_wps) from_file.waypoints.insert(from_file.waypoints.end(), m.waypoints.begin(), m.waypoints.end());
    settle_landing_loop(from_file, root["loop"], c);
    return from_file;
  }
  settle_landing_loop(m, root["loop"], c);
  return m;
}

bool is_top_level_wp(const std::string& line) {
  if (line.size() < 3 || line.compare(0, 2, "wp") != 0) return false;
  std::size_t i = 2;
  while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
  return i < line.size() && line[i] == ':';
}

bool blank_or_comment(const std::string& line) {
  for (char ch : line) {
    if (ch == '#') return true;
    if (ch != ' ' && ch != '\t' && ch != '\r') return false;
  }
  return true;
}

Mission parse_rosplane(const std::string& text, const std::string& source) {
  Mission m;
  m.source = source;
  std::istringstream in(text);
  std::string line;
  std::vector<std::pair<int, std::string>> chunks;  // (first line number, text)
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (is_top_level_wp(line)) {
      chunks.emplace_back(number, line + "\n");
    } else if (!line.empty() && line[0] != ' ' && line[0] != '\t' && !blank_or_comment(line) && line != "---") {
      throw MissionError(source + ":" + std::to_string(number) + ": unexpected top-level entry '" + line +
                         "' in a ROSplane mission file (only wp: entries)");
    } else if (!chunks.empty()) {
      chunks.back().second += line + "\n";
    }
  }
  for (std::size_t k = 0; k < chunks.size(); ++k) {
    Ctx c{source, chunks[k].first - 1};
    YAML::Node doc;
    try {
      doc = YAML::Load(chunks[k].second);
    } catch (const YAML::Exception& e) {
      throw MissionError(source + ":" + std::to_string(chunks[k].first + (e.mark.line >= 0 ? e.mark.line : 0)) + ": " + e.msg);
    }
    // "wp:x" (no space after the colon) starts a chunk but is one scalar to YAML, not a map with wp
    if (!doc.IsMap())
      throw MissionError(source + ":" + std::to_string(chunks[k].first) + ": wp " + std::to_string(k + 1) +
                         ": expected 'wp:' and the waypoint, got '" + printable(chunks[k].second.substr(0, chunks[k].second.find('\n'))) +
                         "'");
    m.waypoints.push_back(parse_entry(doc["wp"], c, "wp " + std::to_string(k + 1), 0.0));
    m.waypoints.back().line = chunks[k].first;  // the entry's `wp:` line
  }
  fill_return_home_altitudes(m);
  settle_landing_loop(m, YAML::Node(), Ctx{source, 0});
  return m;
}

}  // namespace

namespace {
std::string key_list(const std::vector<std::string>& keys) {
  std::string s;
  for (const auto& k : keys) s += (s.empty() ? "" : ", ") + k;
  return s;
}
}  // namespace

MissionError::MissionError(const std::string& where, const std::string& key, const std::vector<std::string>& expected)
    : std::runtime_error(where + "unknown key '" + key + "' (expected " + key_list(expected) + ")"),
      where_(where),
      key_(key),
      expected_(expected) {}

bool Mission::has_lla() const {
  for (const auto& wp : waypoints)
    if (wp.lla) return true;
  return false;
}

namespace {
/// " (radians: D deg would be R)" when `rad` looks like D degrees given as radians, else "".
std::string degrees_hint(double rad, double max_rad) {
  if (!(std::fabs(rad) > max_rad && std::fabs(rad) <= 360.0)) return "";
  return " (radians: " + num(rad) + " deg would be " + number_text(rad * kRadPerDeg, 4) + ")";
}

void validate_land(const MissionWaypoint& wp, const std::string& where) {
  const LandSpec& l = wp.land;
  if (std::fabs(wp.chi_d) > 2.0 * kPi)
    throw MissionError(where + ": heading " + num(wp.chi_d) + " rad is outside [-2 pi, 2 pi]" + degrees_hint(wp.chi_d, 2.0 * kPi));
  if (!(l.glide_slope > 0.0 && l.glide_slope <= kMaxGlideSlope))
    throw MissionError(where + ": glide_slope " + num(l.glide_slope) + " rad is outside (0, " + num(kMaxGlideSlope) + "]" +
                       degrees_hint(l.glide_slope, kMaxGlideSlope));
  if (!(std::isfinite(l.flare_height) && l.flare_height > 0.0))
    throw MissionError(where + ": flare_height " + num(l.flare_height) + " m must be > 0 (above the touchdown point)");
  if (!(std::isfinite(l.decision_height) && l.decision_height > l.flare_height))
    throw MissionError(where + ": decision_height " + num(l.decision_height) + " m must be above flare_height " + num(l.flare_height) +
                       " m (the approach is judged before the flare)");
}
}  // namespace

void validate_waypoint(const MissionWaypoint& wp, const std::string& where) {
  if (!wp.w.allFinite()) throw MissionError(where + ": position is not finite");
  if (!std::isfinite(wp.chi_d)) throw MissionError(where + ": chi_d is not finite");
  if (!std::isfinite(wp.Va_d) || wp.Va_d < 0.0)
    throw MissionError(where + ": Va_d " + num(wp.Va_d) + " m/s must be >= 0 (0: default airspeed)");
  if (!std::isfinite(wp.Vg_min) || wp.Vg_min < 0.0)
    throw MissionError(where + ": Vg_min " + num(wp.Vg_min) + " m/s must be >= 0 (0: no least ground speed)");
  if (!std::isfinite(wp.loiter.radius) || wp.loiter.radius < 0.0)
    throw MissionError(where + ": loiter radius " + num(wp.loiter.radius) + " m must be >= 0 (0: the path manager's turn radius)");
  if (wp.loiter.direction != 1 && wp.loiter.direction != -1)
    throw MissionError(where + ": loiter direction " + std::to_string(wp.loiter.direction) + " must be 1 (cw) or -1 (ccw)");
  if (!std::isfinite(wp.loiter.time) || wp.loiter.time < 0.0 || !std::isfinite(wp.loiter.turns) || wp.loiter.turns < 0.0)
    throw MissionError(where + ": loiter time " + num(wp.loiter.time) + " s and turns " + num(wp.loiter.turns) + " must be >= 0");
  if (wp.type == ItemType::return_home && wp.lla) throw MissionError(where + ": return_home takes no lat/lon (home is the origin)");
  if (wp.type == ItemType::land) validate_land(wp, where);
  if (wp.lla) {
    if (std::fabs(wp.w.x()) > 90.0) throw MissionError(where + ": latitude " + num(wp.w.x()) + " deg is outside [-90, 90]");
    if (std::fabs(wp.w.y()) > 180.0) throw MissionError(where + ": longitude " + num(wp.w.y()) + " deg is outside [-180, 180]");
  }
}

Mission parse_mission_section(const YAML::Node& section, const std::filesystem::path& base_dir, const std::string& source) {
  return parse_map(section, Ctx{source, 0}, true, base_dir);
}

Mission parse_mission_text(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (is_top_level_wp(line)) return parse_rosplane(text, source);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw MissionError(source + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  try {
    check_yaml_size(root, source);
  } catch (const std::runtime_error& e) {
    throw MissionError(e.what());
  }
  Mission m = parse_map(root, Ctx{source, 0}, false, {});
  m.source = source;
  return m;
}

Mission load_mission_file(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw MissionError(printable(file.string()) + ": cannot read the mission file");
  std::string text;
  try {
    text = read_text_file(file, "mission file");  // a regular file, bounded (tern/input_file.hpp)
  } catch (const std::runtime_error& e) {
    throw MissionError(e.what());
  }
  return parse_mission_text(text, file.string());
}

Eigen::Vector3d lla_to_ned(const Eigen::Vector3d& lla, const GeoPoint& o) {
  MissionWaypoint probe;
  probe.w = lla;
  probe.lla = true;
  validate_waypoint(probe, "lla_to_ned");
  probe.w = Eigen::Vector3d(o.lat, o.lon, o.alt);
  validate_waypoint(probe, "lla_to_ned origin");
  return GeoOrigin(o).to_ned(lla.x(), lla.y(), lla.z());
}

std::vector<MissionWaypoint> resolve_to_ned(const std::vector<MissionWaypoint>& wps, const GeoPoint& origin) {
  std::vector<MissionWaypoint> out = wps;
  for (auto& wp : out) {
    if (!wp.lla) continue;
    wp.w = lla_to_ned(wp.w, origin);
    wp.lla = false;
  }
  return out;
}

}  // namespace tern::path
