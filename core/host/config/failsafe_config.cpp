#include "config/failsafe_config.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "config/error.hpp"

namespace tern::core {

bool inside_polygon(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) in = !in;
  }
  return in;
}

bool FenceZone::contains(const Eigen::Vector2d& p) const {
  return polygon.empty() ? (p - centre).norm() <= radius : inside_polygon(polygon, p);
}

bool inside_zones(const std::vector<FenceZone>& zones, const Eigen::Vector2d& p) {
  std::vector<std::uint32_t> groups, outside;  // the inclusion groups, and those p leaves
  for (const FenceZone& z : zones) {
    if (!z.inclusion) {
      if (z.contains(p)) return false;
      continue;
    }
    if (std::find(groups.begin(), groups.end(), z.group) == groups.end()) groups.push_back(z.group);
    if (!z.contains(p) && std::find(outside.begin(), outside.end(), z.group) == outside.end()) outside.push_back(z.group);
  }
  return groups.empty() || outside.size() < groups.size();
}

std::optional<std::size_t> nearest_rally(const std::vector<Eigen::Vector3d>& rally, const std::vector<FenceZone>& zones,
                                         const Eigen::Vector2d& from) {
  std::optional<std::size_t> best;
  double best_distance = from.norm();  // home's
  for (std::size_t i = 0; i < rally.size(); ++i) {
    const Eigen::Vector2d at = rally[i].head<2>();
    if (!inside_zones(zones, at)) continue;
    if (const double d = (at - from).norm(); d < best_distance) best = i, best_distance = d;
  }
  return best;
}

namespace {

struct Reader {
  const std::filesystem::path& file;

  std::string value_of(const YAML::Node& n) const {
    return n.IsScalar() ? n.Scalar() : n.IsMap() ? "<map>" : n.IsSequence() ? "<list>" : "<null>";
  }
  void map(const YAML::Node& n, const std::string& field, const std::vector<std::string>& keys) const {
    if (!n.IsMap()) throw ConfigError(where(file, n) + field + ": expected a map of key: value, got " + value_of(n));
    check_keys(n, file, field, keys);
  }
  double number(const YAML::Node& n, const std::string& field, double lo, const char* unit) const {
    double v = NAN;
    if (n.IsScalar()) {
      try {
        v = n.as<double>();
      } catch (const YAML::Exception&) {
      }
    }
    if (!std::isfinite(v)) throw ConfigError(where(file, n) + field + ": expected a number (" + unit + "), got '" + value_of(n) + "'");
    if (v < lo) throw ConfigError(where(file, n) + fmt::format("{}: {} {} is below {}", field, v, unit, lo));
    return v;
  }
  bool boolean(const YAML::Node& n, const std::string& field) const { return yaml_bool(n, file, field); }
};

void read_gnss(const Reader& r, const YAML::Node& n, GnssLossConfig& c) {
  r.map(n, "failsafes.gnss_loss", {"enabled", "timeout", "radius"});
  if (n["enabled"]) c.enabled = r.boolean(n["enabled"], "failsafes.gnss_loss.enabled");
  if (n["timeout"]) c.timeout = r.number(n["timeout"], "failsafes.gnss_loss.timeout", 0.0, "s");
  if (n["radius"]) c.radius = r.number(n["radius"], "failsafes.gnss_loss.radius", 0.0, "m");
}

void read_link(const Reader& r, const YAML::Node& n, LinkLossConfig& c) {
  r.map(n, "failsafes.link_loss", {"enabled", "timeout", "altitude", "radius", "terminate"});
  c.enabled = n["enabled"] ? r.boolean(n["enabled"], "failsafes.link_loss.enabled") : true;
  if (n["timeout"]) c.timeout = r.number(n["timeout"], "failsafes.link_loss.timeout", 0.0, "s");
  if (n["altitude"]) c.altitude = r.number(n["altitude"], "failsafes.link_loss.altitude", 0.0, "m");
  if (n["radius"]) c.radius = r.number(n["radius"], "failsafes.link_loss.radius", 0.0, "m");
  if (const YAML::Node t = n["terminate"]) {
    r.map(t, "failsafes.link_loss.terminate", {"after", "action"});
    if (!t["after"]) throw ConfigError(where(r.file, t) + "failsafes.link_loss.terminate: give after (s after the return home)");
    c.terminate_after = r.number(t["after"], "failsafes.link_loss.terminate.after", 0.0, "s");
    if (const YAML::Node a = t["action"]) {
      const std::string v = r.value_of(a);
      if (v == "glide")
        c.terminate_action = TerminateAction::glide;
      else if (v == "spin")
        c.terminate_action = TerminateAction::spin;
      else
        throw ConfigError(where(r.file, a) + "failsafes.link_loss.terminate.action: '" + v + "' is not glide or spin");
    }
  }
}

std::vector<Eigen::Vector2d> read_vertices(const Reader& r, const YAML::Node& n) {
  const std::string field = "failsafes.geofence.polygon";
  if (!n.IsSequence() || n.size() < 3)
    throw ConfigError(where(r.file, n) + field + ": expected a list of at least 3 [n, e] vertices (m from home), got " + r.value_of(n));
  std::vector<Eigen::Vector2d> vertices;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const std::string at = fmt::format("{}[{}]", field, i);
    if (!n[i].IsSequence() || n[i].size() != 2)
      throw ConfigError(where(r.file, n[i]) + at + ": expected [n, e] (m), got " + r.value_of(n[i]));
    vertices.emplace_back(r.number(n[i][0], at + "[0]", -1e7, "m"), r.number(n[i][1], at + "[1]", -1e7, "m"));
  }
  if (!inside_polygon(vertices, Eigen::Vector2d::Zero()))
    throw ConfigError(where(r.file, n) + field + ": home (n 0, e 0) is outside the polygon: the return inside would leave it");
  return vertices;
}

FenceAction read_action(const Reader& r, const YAML::Node& n) {
  const std::string v = r.value_of(n);
  if (v == "report") return FenceAction::report;
  if (v == "loiter") return FenceAction::loiter;
  if (v == "return_home") return FenceAction::return_home;
  throw ConfigError(where(r.file, n) + "failsafes.geofence.action: '" + v + "' is not report, loiter or return_home");
}

void read_geofence(const Reader& r, const YAML::Node& n, GeofenceConfig& c) {
  r.map(n, "failsafes.geofence",
        {"enabled", "max_distance", "min_altitude", "max_altitude", "polygon", "altitude_margin", "radius", "action"});
  c.enabled = n["enabled"] ? r.boolean(n["enabled"], "failsafes.geofence.enabled") : true;
  if (n["max_distance"]) c.max_distance = r.number(n["max_distance"], "failsafes.geofence.max_distance", 1.0, "m");
  if (n["min_altitude"]) c.min_altitude = r.number(n["min_altitude"], "failsafes.geofence.min_altitude", 0.0, "m");
  if (n["max_altitude"]) c.max_altitude = r.number(n["max_altitude"], "failsafes.geofence.max_altitude", 1.0, "m");
  if (n["altitude_margin"]) c.altitude_margin = r.number(n["altitude_margin"], "failsafes.geofence.altitude_margin", 0.0, "m");
  if (n["radius"]) c.radius = r.number(n["radius"], "failsafes.geofence.radius", 0.0, "m");
  if (n["action"]) c.action = read_action(r, n["action"]);
  if (n["polygon"]) c.zones.push_back(FenceZone{true, 0, read_vertices(r, n["polygon"]), Eigen::Vector2d::Zero(), 0.0});
  if (c.min_altitude && c.max_altitude && *c.max_altitude - *c.min_altitude < 2.0 * c.altitude_margin)
    throw ConfigError(
        where(r.file, n["max_altitude"]) +
        fmt::format("failsafes.geofence.max_altitude: {} m leaves less than 2 x altitude_margin ({} m) above min_altitude {} m",
                    *c.max_altitude, c.altitude_margin, *c.min_altitude));
  if (c.enabled && !c.limits())
    throw ConfigError(where(r.file, n) + "failsafes.geofence: no limit (give max_distance, min_altitude, max_altitude or polygon)");
}

std::vector<Eigen::Vector3d> read_rally(const Reader& r, const YAML::Node& n) {
  const std::string field = "failsafes.rally";
  if (!n.IsSequence())
    throw ConfigError(where(r.file, n) + field + ": expected a list of [n, e, altitude] points (m), got " + r.value_of(n));
  std::vector<Eigen::Vector3d> points;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const std::string at = fmt::format("{}[{}]", field, i);
    if (!n[i].IsSequence() || n[i].size() != 3)
      throw ConfigError(where(r.file, n[i]) + at + ": expected [n, e, altitude above home] (m), got " + r.value_of(n[i]));
    points.emplace_back(r.number(n[i][0], at + "[0]", -1e7, "m"), r.number(n[i][1], at + "[1]", -1e7, "m"),
                        r.number(n[i][2], at + "[2]", 0.0, "m"));
  }
  return points;
}

}  // namespace

FailsafeConfig parse_failsafes(const YAML::Node& section, const std::filesystem::path& file) {
  FailsafeConfig c;
  if (!section || section.IsNull()) return c;
  const Reader r{file};
  r.map(section, "failsafes", {"gnss_loss", "link_loss", "geofence", "rally"});
  if (section["gnss_loss"]) read_gnss(r, section["gnss_loss"], c.gnss_loss);
  if (section["link_loss"]) read_link(r, section["link_loss"], c.link_loss);
  if (section["geofence"]) read_geofence(r, section["geofence"], c.geofence);
  if (section["rally"]) c.rally = read_rally(r, section["rally"]);
  return c;
}

}  // namespace tern::core
