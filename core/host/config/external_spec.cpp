#include "config/external_spec.hpp"

#include <cmath>

#include "config/error.hpp"

namespace tern::core {

namespace {

const std::string kExternal = "external";

std::string text(const YAML::Node& n, const fs::path& file, const std::string& field) {
  if (!n.IsScalar()) throw ConfigError(where(file, n) + field + ": expected text");
  return n.Scalar();
}

std::vector<std::string> ros_types(bool input) {
  std::vector<std::string> out;
  for (const auto& b : external_bindings())
    if (b.input == input) out.emplace_back(b.ros_type);
  return out;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

// One `inputs:`/`outputs:` entry {port, topic, type}.
ExternalTopic parse_topic(const YAML::Node& n, const fs::path& file, const std::string& field, bool input) {
  if (!n.IsMap()) throw ConfigError(where(file, n) + field + ": expected {port, topic, type}");
  check_keys(n, file, field, {"port", "topic", "type"});
  for (const char* k : {"port", "topic", "type"})
    if (!n[k]) throw ConfigError(where(file, n) + field + ": missing key '" + k + "'");
  ExternalTopic t;
  t.port = text(n["port"], file, field + ".port");
  t.topic = text(n["topic"], file, field + ".topic");
  const std::string type = text(n["type"], file, field + ".type");
  t.binding = find_external_binding(type);
  if (t.binding == nullptr || t.binding->input != input)
    throw ConfigError(where(file, n["type"]) + field + ".type: '" + type + "' cannot be an external module's " +
                      (input ? "input" : "output") + " (it may be: " + joined(ros_types(input)) + ")" +
                      did_you_mean(type, ros_types(input)));
  if (t.topic.empty() || t.topic.front() == '/' || t.topic.find("//") != std::string::npos)
    throw ConfigError(where(file, n["topic"]) + field + ".topic: '" + t.topic + "' is not a relative ROS topic name");
  return t;
}

std::vector<ExternalTopic> parse_topics(const YAML::Node& list, const fs::path& file, const std::string& field, bool input) {
  if (!list.IsSequence() || list.size() == 0)
    throw ConfigError(where(file, list) + field + ": expected a non-empty list of {port, topic, type}");
  std::vector<ExternalTopic> out;
  for (std::size_t i = 0; i < list.size(); ++i) out.push_back(parse_topic(list[i], file, field + "[" + std::to_string(i) + "]", input));
  return out;
}

// ROSplane 2.0's controller node (rosplane/src/controller/controller_ros.cpp, ControllerROS()).
void fill_controller(ExternalSpec& s) {
  s.inputs = {{"state", "estimated_state", find_external_binding("rosplane_msgs/msg/State")},
              {"controller_command", "controller_command", find_external_binding("rosplane_msgs/msg/ControllerCommands")}};
  s.outputs = {{"actuators", "command", find_external_binding("rosflight_msgs/msg/Command")}};
}

}  // namespace

const std::vector<ExternalBinding>& external_bindings() {
  static const std::vector<ExternalBinding> kBindings = {
      {"rosplane_msgs/msg/State", "tern/State", true},
      {"rosplane_msgs/msg/ControllerCommands", "tern/ControllerCommand", true},
      {"rosflight_msgs/msg/Command", "tern/Actuators", false},
  };
  return kBindings;
}

const ExternalBinding* find_external_binding(std::string_view ros_type) {
  for (const auto& b : external_bindings())
    if (b.ros_type == ros_type) return &b;
  return nullptr;
}

std::string ExternalSpec::dds_name(const ExternalTopic& t) const { return "rt/" + (ns.empty() ? "" : ns + "/") + t.topic; }

bool is_external(const InstanceConfig& ic) { return ic.plugin == kExternal; }

const std::vector<std::string>& external_keys() {
  static const std::vector<std::string> keys = {"role", "inputs", "outputs", "timeout_ms", "namespace"};
  return keys;
}

ExternalSpec parse_external_spec(const InstanceConfig& ic, const fs::path& file) {
  const YAML::Node& n = ic.node;
  const std::string field = ic.label();
  ExternalSpec s;
  s.instance = ic.name;
  if (n["role"]) {
    s.role = text(n["role"], file, field + ".role");
    if (s.role != "controller")
      throw ConfigError(where(file, n["role"]) + field + ".role: unknown role '" + s.role + "' (roles: controller)" +
                        did_you_mean(s.role, {"controller"}));
    if (n["inputs"] || n["outputs"]) throw ConfigError(where(file, n["role"]) + field + ": give either role or inputs/outputs, not both");
    fill_controller(s);
  } else {
    if (!n["inputs"] || !n["outputs"])
      throw ConfigError(where(file, n) + field + " (" + ic.name + "): an external module needs role: controller, or inputs: and outputs:");
    s.inputs = parse_topics(n["inputs"], file, field + ".inputs", true);
    s.outputs = parse_topics(n["outputs"], file, field + ".outputs", false);
  }
  if (n["timeout_ms"]) {
    const YAML::Node& t = n["timeout_ms"];
    double v = NAN;
    try {
      v = t.as<double>();
    } catch (const YAML::Exception&) {
    }
    if (!(v > 0) || !std::isfinite(v))
      throw ConfigError(where(file, t) + field + ".timeout_ms: expected a number of ms > 0, got '" +
                        (t.IsScalar() ? t.Scalar() : "<not a number>") + "'");
    s.timeout_ms = v;
  }
  if (n["namespace"]) {
    s.ns = text(n["namespace"], file, field + ".namespace");
    while (!s.ns.empty() && s.ns.front() == '/') s.ns.erase(0, 1);
    while (!s.ns.empty() && s.ns.back() == '/') s.ns.pop_back();
  }
  s.kind = PluginKind::generic;
  for (const auto& o : s.outputs)
    if (o.port == "actuators") s.kind = PluginKind::controller;
  return s;
}

}  // namespace tern::core
