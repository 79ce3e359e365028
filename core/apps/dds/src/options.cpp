// core/apps/dds/src/options.cpp: the mission config's `dds:` section.
#include <arpa/inet.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>

#include <yaml-cpp/yaml.h>

#include "dds_bridge.hpp"
#include "dds_keystore.hpp"
#include "config/error.hpp"

namespace tern::core {

namespace fs = std::filesystem;

int default_depth(DdsQos q) { return q == DdsQos::reliable ? 10 : 1; }

bool DdsOptions::loopback_only() const {
  if (multicast) return false;
  for (const auto& i : interfaces)
    if (i != "127.0.0.1") return false;
  return true;
}

namespace {

std::string fmt_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string show(const YAML::Node& n) {
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a map";
  return "nothing";
}

double number(const YAML::Node& n, const fs::path& file, const std::string& field, double lo, double hi) {
  double v = 0;
  try {
    if (!n.IsScalar()) throw YAML::Exception(YAML::Mark(), "");
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    throw ConfigError(where(file, n) + field + ": expected a number, got " + show(n));
  }
  if (!std::isfinite(v) || v < lo || v > hi)
    throw ConfigError(where(file, n) + field + ": " + n.Scalar() + " is outside [" + fmt_number(lo) + ", " + fmt_number(hi) + "]");
  return v;
}

std::string text(const YAML::Node& n, const fs::path& file, const std::string& field, bool allow_empty) {
  if (!n.IsScalar() || (!allow_empty && n.Scalar().empty()))
    throw ConfigError(where(file, n) + field + ": expected a " + (allow_empty ? "" : "non-empty ") + "string, got " + show(n));
  return n.Scalar();
}

/// A DDS name part: letters, digits, '_' and '/' (ROS 2 names), not starting with a digit or '/'.
std::string dds_name(const YAML::Node& n, const fs::path& file, const std::string& field, bool allow_empty) {
  std::string s = text(n, file, field, allow_empty);
  while (!s.empty() && s.back() == '/') s.pop_back();
  while (!s.empty() && s.front() == '/') s.erase(s.begin());
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '/'))
      throw ConfigError(where(file, n) + field + ": '" + n.Scalar() + "' is not a ROS 2 name (letters, digits, '_', '/')");
  if (!s.empty() && std::isdigit(static_cast<unsigned char>(s.front())))
    throw ConfigError(where(file, n) + field + ": '" + n.Scalar() + "' must not start with a digit");
  return s;
}

std::vector<std::string> ipv4_list(const YAML::Node& n, const fs::path& file, const std::string& field) {
  if (!n.IsSequence()) throw ConfigError(where(file, n) + field + ": expected a list of IPv4 addresses, got " + show(n));
  std::vector<std::string> out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const std::string f = field + "[" + std::to_string(i) + "]";
    const std::string s = text(n[i], file, f, false);
    in_addr a{};
    if (inet_pton(AF_INET, s.c_str(), &a) != 1)
      throw ConfigError(where(file, n[i]) + f + ": '" + s + "' is not an IPv4 address (e.g. 127.0.0.1)");
    out.push_back(s);
  }
  if (out.empty()) throw ConfigError(where(file, n) + field + ": the list is empty");
  return out;
}

std::vector<fs::path> dir_list(const YAML::Node& n, const fs::path& file, const std::string& field) {
  if (!n.IsSequence()) throw ConfigError(where(file, n) + field + ": expected a list of directories, got " + show(n));
  std::vector<fs::path> out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const std::string f = field + "[" + std::to_string(i) + "]";
    const fs::path p(text(n[i], file, f, false));
    out.push_back((p.is_absolute() ? p : file.parent_path() / p).lexically_normal());
  }
  return out;
}

DdsQos qos(const YAML::Node& n, const fs::path& file, const std::string& field) {
  const std::string s = text(n, file, field, false);
  if (s == "best_effort") return DdsQos::best_effort;
  if (s == "reliable") return DdsQos::reliable;
  if (s == "transient_local") return DdsQos::transient_local;
  throw ConfigError(where(file, n) + field + ": '" + s + "' is not one of best_effort, reliable, transient_local" +
                    did_you_mean(s, {"best_effort", "reliable", "transient_local"}));
}

DdsTime time_source(const YAML::Node& n, const fs::path& file) {
  const std::string s = text(n, file, "dds.time", false);
  if (s == "auto") return DdsTime::automatic;
  if (s == "sim") return DdsTime::sim;
  if (s == "wall") return DdsTime::wall;
  throw ConfigError(where(file, n) + "dds.time: '" + s + "' is not one of auto, sim, wall" + did_you_mean(s, {"auto", "sim", "wall"}));
}

/// A ROS 2 message type name "package/msg/Name".
std::string ros_type(const YAML::Node& n, const fs::path& file, const std::string& field) {
  const std::string s = text(n, file, field, false);
  const auto a = s.find('/'), b = s.rfind('/');
  if (a == std::string::npos || a == 0 || b == a || s.compare(a, b - a + 1, "/msg/") != 0 || b + 1 == s.size())
    throw ConfigError(where(file, n) + field + ": '" + s + "' is not a ROS 2 message type (package/msg/Name, e.g. sensor_msgs/msg/Imu)");
  return s;
}

DdsTopicOptions topic_entry(const YAML::Node& e, const fs::path& file, const std::string& f) {
  DdsTopicOptions to;
  if (!e.IsMap()) {
    to.topic = text(e, file, f, false);
    to.name = dds_name(e, file, f, false);
    return to;
  }
  check_keys(e, file, f, {"topic", "name", "rate", "qos", "depth", "type"});
  if (!e["topic"]) throw ConfigError(where(file, e) + f + ": missing key 'topic'");
  to.topic = text(e["topic"], file, f + ".topic", false);
  to.name = e["name"] ? dds_name(e["name"], file, f + ".name", false) : to.topic;
  if (e["rate"]) to.rate = number(e["rate"], file, f + ".rate", 0, 1e6);
  if (e["qos"]) to.qos = qos(e["qos"], file, f + ".qos");
  if (e["depth"]) {
    const double d = number(e["depth"], file, f + ".depth", 1, 1000);
    if (d != std::floor(d)) throw ConfigError(where(file, e["depth"]) + f + ".depth: expected an integer, got " + show(e["depth"]));
    to.depth = static_cast<int>(d);
  }
  if (e["type"]) to.type = ros_type(e["type"], file, f + ".type");
  return to;
}

/// `dds.security: {keystore: DIR, enclave: NAME}` (DIR relative to the config file).
DdsSecurity security(const YAML::Node& n, const fs::path& file) {
  if (!n.IsMap()) throw ConfigError(where(file, n) + "dds.security: expected a map {keystore: DIR, enclave: NAME}, got " + show(n));
  check_keys(n, file, "dds.security", {"keystore", "enclave"});
  if (!n["keystore"])
    throw ConfigError(where(file, n) + "dds.security: missing key 'keystore' (a directory made by `tern dds keystore create`)");
  DdsSecurity s;
  const fs::path k(text(n["keystore"], file, "dds.security.keystore", false));
  s.keystore = (k.is_absolute() ? k : file.parent_path() / k).lexically_normal();
  s.enclave = n["enclave"] ? text(n["enclave"], file, "dds.security.enclave", false) : std::string(kVehicleEnclave);
  if (!is_enclave_name(s.enclave))
    throw ConfigError(where(file, n["enclave"]) + "dds.security.enclave: '" + s.enclave +
                      "' is not an enclave name (letters, digits, '_', '/')");
  return s;
}

}  // namespace

DdsOptions parse_dds_options(const YAML::Node& dds, const std::filesystem::path& file) {
  DdsOptions o;
  o.topics = DdsOptions::rosplane_profile(o.aliases);
  if (!dds || dds.IsNull()) return o;
  if (!dds.IsMap()) throw ConfigError(where(file, dds) + "dds: expected a map of key: value, got " + show(dds));
  check_keys(dds, file, "dds",
             {"enabled", "domain", "namespace", "interfaces", "peers", "multicast", "rate", "topics", "read_only", "mission_dirs",
              "param_dirs", "security", "aliases", "time", "clock_rate"});
  if (dds["enabled"]) o.enabled = yaml_bool(dds["enabled"], file, "dds.enabled");
  if (dds["domain"]) {
    const double d = number(dds["domain"], file, "dds.domain", 0, 232);
    if (d != std::floor(d)) throw ConfigError(where(file, dds["domain"]) + "dds.domain: expected an integer, got " + show(dds["domain"]));
    o.domain = static_cast<std::uint32_t>(d);
  }
  if (dds["namespace"]) o.ns = dds_name(dds["namespace"], file, "dds.namespace", true);
  if (dds["interfaces"]) o.interfaces = ipv4_list(dds["interfaces"], file, "dds.interfaces");
  if (dds["peers"]) o.peers = ipv4_list(dds["peers"], file, "dds.peers");
  if (dds["multicast"]) o.multicast = yaml_bool(dds["multicast"], file, "dds.multicast");
  if (dds["read_only"]) o.read_only = yaml_bool(dds["read_only"], file, "dds.read_only");
  if (dds["mission_dirs"]) o.mission_dirs = dir_list(dds["mission_dirs"], file, "dds.mission_dirs");
  if (dds["param_dirs"]) o.param_dirs = dir_list(dds["param_dirs"], file, "dds.param_dirs");
  if (dds["security"]) o.security = security(dds["security"], file);
  if (dds["rate"]) o.rate = number(dds["rate"], file, "dds.rate", 0, 1e6);
  if (dds["aliases"]) o.aliases = yaml_bool(dds["aliases"], file, "dds.aliases");
  o.topics = DdsOptions::rosplane_profile(o.aliases);
  if (dds["time"]) o.time = time_source(dds["time"], file);
  if (dds["clock_rate"]) o.clock_rate = number(dds["clock_rate"], file, "dds.clock_rate", 0, 10000);
  if (const auto t = dds["topics"]) {
    if (!t.IsSequence()) throw ConfigError(where(file, t) + "dds.topics: expected a list of topics, got " + show(t));
    o.topics.clear();
    o.topics_from_config = true;
    std::set<std::string> names;
    for (std::size_t i = 0; i < t.size(); ++i) {
      const std::string f = "dds.topics[" + std::to_string(i) + "]";
      const YAML::Node e = t[i];
      DdsTopicOptions to = topic_entry(e, file, f);
      if (!names.insert(to.name).second) throw ConfigError(where(file, e) + f + ": DDS name '" + to.name + "' is bridged twice");
      o.topics.push_back(std::move(to));
    }
  }
  return o;
}

}  // namespace tern::core
