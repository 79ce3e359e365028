// Mission reading and LLA -> NED conversion. See mission.hpp.
#include "tern/path/mission.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <GeographicLib/LocalCartesian.hpp>
#include <yaml-cpp/yaml.h>

namespace tern::path {

namespace {

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

/// "<source>: line N: " (line N omitted when unknown).
std::string at(const std::string& source, const YAML::Node& n, int line_offset = 0) {
  const auto m = n.Mark();
  if (m.line >= 0) return source + ": line " + std::to_string(m.line + 1 + line_offset) + ": ";
  return source + ": ";
}

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

Eigen::Vector3d as_vec3(const YAML::Node& n, const Ctx& c, const std::string& field) {
  if (!n.IsSequence() || n.size() != 3)
    throw MissionError(c.prefix(n) + field + ": expected a list of 3 numbers");
  Eigen::Vector3d v;
  for (std::size_t i = 0; i < 3; ++i) v[static_cast<Eigen::Index>(i)] = as_double(n[i], c, field + "[" + std::to_string(i) + "]");
  return v;
}

MissionWaypoint parse_entry(const YAML::Node& n, const Ctx& c, const std::string& name, double default_Va) {
  MissionWaypoint wp;
  wp.Va_d = default_Va;
  if (n.IsSequence()) {
    wp.w = as_vec3(n, c, name);
    validate_waypoint(wp, c.prefix(n) + name);
    return wp;
  }
  if (!n.IsMap())
    throw MissionError(c.prefix(n) + name + ": expected [n, e, d] or a map with ned, w or lla");
  int positions = 0;
  bool lla_flag = false;
  for (const auto& kv : n) {
    const std::string key = kv.first.as<std::string>();
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
    } else if (key == "use_chi") {
      wp.use_chi = as_bool(v, c, field);
    } else if (key == "Va_d" || key == "va_d") {
      wp.Va_d = as_double(v, c, field);
    } else {
      throw MissionError(c.prefix(kv.first) + name + ": unknown key '" + key +
                         "' (expected ned, w, lla, chi_d, use_chi, Va_d)");
    }
  }
  if (positions == 0) throw MissionError(c.prefix(n) + name + ": no position (ned, w or lla: [lat, lon, alt])");
  if (positions > 1) throw MissionError(c.prefix(n) + name + ": more than one position (ned, w, lla)");
  if (lla_flag) {
    if (wp.lla) throw MissionError(c.prefix(n) + name + ": lla: true given with an lla position");
    wp.lla = true;
  }
  validate_waypoint(wp, c.prefix(n) + name);
  return wp;
}

/// The keys shared by the config section and a tern waypoint file.
Mission parse_map(const YAML::Node& root, const Ctx& c, bool allow_file, const std::filesystem::path& base_dir) {
  Mission m;
  m.source = c.source;
  if (!root || root.IsNull()) return m;
  if (!root.IsMap()) throw MissionError(c.prefix(root) + "expected a map with waypoints (or file)");
  double default_Va = 0.0;
  if (root["Va_d"]) {
    default_Va = as_double(root["Va_d"], c, "Va_d");
    if (default_Va < 0.0) throw MissionError(c.prefix(root["Va_d"]) + "Va_d: " + num(default_Va) + " m/s is negative");
  }
  bool have_file = false, have_wps = false;
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (key == "loop") {
      m.loop = as_bool(kv.second, c, "loop");
    } else if (key == "Va_d") {
    } else if (key == "waypoints") {
      have_wps = true;
      const YAML::Node& list = kv.second;
      if (list.IsNull()) continue;
      if (!list.IsSequence()) throw MissionError(c.prefix(list) + "waypoints: expected a list");
      for (std::size_t i = 0; i < list.size(); ++i)
        m.waypoints.push_back(parse_entry(list[i], c, "waypoints[" + std::to_string(i) + "]", default_Va));
    } else if (key == "file" && allow_file) {
      have_file = true;
    } else {
      throw MissionError(c.prefix(kv.first) + "unknown key '" + key + "' (expected " +
                         (allow_file ? "waypoints or file" : "waypoints") + ", loop, Va_d)");
    }
  }
  if (have_file) {
    if (have_wps) throw MissionError(c.prefix(root["file"]) + "give either waypoints or file, not both");
    if (!root["file"].IsScalar()) throw MissionError(c.prefix(root["file"]) + "file: expected a path");
    std::filesystem::path f = root["file"].as<std::string>();
    if (f.is_relative()) f = (base_dir / f).lexically_normal();
    const bool loop_set = static_cast<bool>(root["loop"]);
    Mission from_file = load_mission_file(f);
    if (loop_set) from_file.loop = m.loop;
    if (default_Va > 0.0)
      for (auto& wp : from_file.waypoints)
        if (wp.Va_d <= 0.0) wp.Va_d = default_Va;
    return from_file;
  }
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
      throw MissionError(source + ": line " + std::to_string(number) + ": unexpected top-level entry '" + line +
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
      throw MissionError(source + ": line " + std::to_string(chunks[k].first + (e.mark.line >= 0 ? e.mark.line : 0)) +
                         ": " + e.msg);
    }
    m.waypoints.push_back(parse_entry(doc["wp"], c, "wp " + std::to_string(k + 1), 0.0));
  }
  return m;
}

}  // namespace

bool Mission::has_lla() const {
  for (const auto& wp : waypoints)
    if (wp.lla) return true;
  return false;
}

void validate_waypoint(const MissionWaypoint& wp, const std::string& where) {
  if (!wp.w.allFinite()) throw MissionError(where + ": position is not finite");
  if (!std::isfinite(wp.chi_d)) throw MissionError(where + ": chi_d is not finite");
  if (!std::isfinite(wp.Va_d) || wp.Va_d < 0.0)
    throw MissionError(where + ": Va_d " + num(wp.Va_d) + " m/s must be >= 0 (0: default airspeed)");
  if (wp.lla) {
    if (std::fabs(wp.w.x()) > 90.0)
      throw MissionError(where + ": latitude " + num(wp.w.x()) + " deg is outside [-90, 90]");
    if (std::fabs(wp.w.y()) > 180.0)
      throw MissionError(where + ": longitude " + num(wp.w.y()) + " deg is outside [-180, 180]");
  }
}

Mission parse_mission_section(const YAML::Node& section, const std::filesystem::path& base_dir) {
  return parse_map(section, Ctx{"mission config (mission:)", 0}, true, base_dir);
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
    throw MissionError(source + ": line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  Mission m = parse_map(root, Ctx{source, 0}, false, {});
  m.source = source;
  return m;
}

Mission load_mission_file(const std::filesystem::path& file) {
  std::ifstream f(file);
  if (!f) throw MissionError(file.string() + ": cannot read the mission file");
  std::stringstream ss;
  ss << f.rdbuf();
  return parse_mission_text(ss.str(), file.string());
}

Eigen::Vector3d lla_to_ned(const Eigen::Vector3d& lla, const GeoOrigin& o) {
  MissionWaypoint probe;
  probe.w = lla;
  probe.lla = true;
  validate_waypoint(probe, "lla_to_ned");
  probe.w = Eigen::Vector3d(o.lat, o.lon, o.alt);
  validate_waypoint(probe, "lla_to_ned origin");
  const GeographicLib::LocalCartesian proj(o.lat, o.lon, o.alt);
  double x = 0.0, y = 0.0, z = 0.0;  // east, north, up
  proj.Forward(lla.x(), lla.y(), lla.z(), x, y, z);
  return {y, x, -z};
}

std::vector<MissionWaypoint> resolve_to_ned(const std::vector<MissionWaypoint>& wps, const GeoOrigin& origin) {
  std::vector<MissionWaypoint> out = wps;
  for (auto& wp : out) {
    if (!wp.lla) continue;
    wp.w = lla_to_ned(wp.w, origin);
    wp.lla = false;
  }
  return out;
}

}  // namespace tern::path
