#include "fleet/fleet_config.hpp"

#include <algorithm>
#include <map>
#include <set>

#include <fmt/format.h>

#include "config/error.hpp"
#include "tern/input_file.hpp"

namespace tern::core {

namespace {

const std::vector<std::string> kFleetOnly = {"vehicles", "coordination", "world", "separation"};
/// What a vehicle may set over the shared stack (besides name, initial and params).
const std::vector<std::string> kVehicleOverrides = {"aircraft", "mission", "phases", "fallback", "phase_machine", "failsafes"};
/// The shared keys the coordination's own mission keeps.
const std::vector<std::string> kCoordinationKeys = {"seed", "duration", "plugin_path", "log", "watchdog"};

std::string text_of(const YAML::Node& n) { return n.IsScalar() ? n.Scalar() : "<" + std::string(n.IsMap() ? "map" : "list") + ">"; }

double number(const YAML::Node& n, const fs::path& f, const std::string& field) {
  try {
    if (n.IsScalar()) return n.as<double>();
  } catch (const YAML::Exception&) {
  }
  throw ConfigError(where(f, n) + field + ": expected a number, got '" + text_of(n) + "'");
}

std::string fleet_name(const YAML::Node& root, const fs::path& f) {
  if (!root["name"]) return f.stem().string();
  const std::string v = root["name"].IsScalar() ? root["name"].Scalar() : "";
  if (v.empty() || v.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-") != std::string::npos ||
      v[0] == '.' || v[0] == '-')
    throw ConfigError(where(f, root["name"]) + "name: '" + text_of(root["name"]) +
                      "' must be letters, digits, '_', '-' and '.' (not first): it names the run directory");
  return v;
}

// The sim_aero instance a vehicle's `initial:` and the world set; nullptr when the stack has none.
InstanceConfig* simulator(MissionConfig& c) {
  for (auto& ic : c.plugins)
    if (ic.plugin == "sim_aero") return &ic;
  return nullptr;
}

// Sets `param` of `ic` from `node`. The world's settings are the only ones (each parameter set
// once: a stack that sets them too is refused); a vehicle's own (`over`) replace the stack's.
void set_param(InstanceConfig& ic, const std::string& param, const YAML::Node& node, const fs::path& f, const std::string& field,
               bool over = false) {
  if (auto it = ic.params.find(param); it != ic.params.end() && !over)
    throw ConfigError(where(f, node) + field + ": sets " + ic.name + "." + param + ", which " + it->second.field +
                      " sets already: keep one");
  ic.params[param] = ParamSetting{node, f, field, true};
}

void apply_world(MissionConfig& c, const YAML::Node& world, const fs::path& f) {
  if (!world) return;
  InstanceConfig* sim = simulator(c);
  if (sim == nullptr) throw ConfigError(where(f, world) + "world: no sim_aero instance in plugins: to fly in it");
  for (const char* key : {"wind", "turbulence"})
    if (world[key]) set_param(*sim, key, world[key], f, std::string("world.") + key);
  if (const YAML::Node o = world["origin"]) {
    if (!o.IsSequence() || o.size() != 3)
      throw ConfigError(where(f, o) + "world.origin: expected [latitude deg, longitude deg, altitude m MSL], got " + text_of(o));
    const char* names[] = {"origin_lat", "origin_lon", "origin_alt"};
    for (std::size_t k = 0; k < 3; ++k) set_param(*sim, names[k], o[k], f, fmt::format("world.origin[{}]", k));
  }
}

void apply_initial(MissionConfig& c, const YAML::Node& init, const fs::path& f, const std::string& field) {
  if (!init) return;
  if (!init.IsMap()) throw ConfigError(where(f, init) + field + ".initial: expected a map (mode, position, altitude, airspeed, heading)");
  check_keys(init, f, field + ".initial", {"mode", "position", "altitude", "airspeed", "heading"});
  InstanceConfig* sim = simulator(c);
  if (sim == nullptr) throw ConfigError(where(f, init) + field + ".initial: no sim_aero instance in plugins: to start");
  for (const auto& kv : init) {
    const std::string key = kv.first.as<std::string>();
    set_param(*sim, "init_" + key, kv.second, f, field + ".initial." + key, true);
  }
}

void apply_params(MissionConfig& c, const YAML::Node& params, const fs::path& f, const std::string& field) {
  if (!params) return;
  if (!params.IsMap()) throw ConfigError(where(f, params) + field + ".params: expected a map of instance.param: value");
  std::vector<std::string> names;
  for (const auto& ic : c.plugins) names.push_back(ic.name);
  for (const auto& kv : params) {
    const std::string key = key_name(kv.first, f, field + ".params");
    const auto dot = key.find('.');
    InstanceConfig* target = nullptr;
    for (auto& ic : c.plugins)
      if (dot != std::string::npos && ic.name == key.substr(0, dot)) target = &ic;
    if (target == nullptr)
      throw ConfigError(where(f, kv.first) + field + ".params." + key +
                        ": expected instance.param with an instance of plugins:" + did_you_mean(key.substr(0, dot), names));
    target->params[key.substr(dot + 1)] = ParamSetting{kv.second, f, field + ".params." + key, true};
  }
}

// The vehicle's DDS namespace: its name, under the mission's dds.namespace when one is given.
// One /clock for the fleet (every vehicle's sim time is the same): the first vehicle's bridge
// publishes it, the others' have clock_rate 0.
YAML::Node vehicle_dds(const YAML::Node& dds, const std::string& name, bool first, const fs::path& f) {
  YAML::Node out(YAML::NodeType::Map);
  if (dds && dds.IsMap())
    for (const auto& kv : dds) out[key_name(kv.first, f, "dds")] = kv.second;
  std::string ns = name;
  if (dds && dds.IsMap() && dds["namespace"] && dds["namespace"].IsScalar() && !dds["namespace"].Scalar().empty())
    ns = dds["namespace"].Scalar() + "/" + name;
  out["namespace"] = ns;
  if (!first) out["clock_rate"] = 0;
  return out;
}

VehicleConfig load_vehicle(const YAML::Node& root, const YAML::Node& v, const fs::path& f, std::size_t i) {
  VehicleConfig out;
  out.field = "vehicles[" + std::to_string(i) + "]";
  if (!v.IsMap()) throw ConfigError(where(f, v) + out.field + ": expected a map (name, initial, mission, ...)");
  std::vector<std::string> keys = kVehicleOverrides;
  keys.insert(keys.end(), {"name", "initial", "params", "system_id"});
  check_keys(v, f, out.field, keys);
  if (!v["name"] || !v["name"].IsScalar()) throw ConfigError(where(f, v) + out.field + ": missing name (an identifier, e.g. uav1)");
  out.name = v["name"].Scalar();
  if (const std::string bad = identifier_problem(out.name); !bad.empty())
    throw ConfigError(where(f, v["name"]) + out.field + ".name: " + bad);
  YAML::Node vroot(YAML::NodeType::Map);
  for (const auto& kv : root) {
    const std::string key = key_name(kv.first, f, "");
    if (std::find(kFleetOnly.begin(), kFleetOnly.end(), key) == kFleetOnly.end()) vroot[key] = kv.second;
  }
  for (const auto& key : kVehicleOverrides)
    if (v[key]) vroot[key] = v[key];
  vroot["name"] = out.name;
  vroot["dds"] = vehicle_dds(root["dds"], out.name, i == 0, f);
  try {
    out.config = config_from_yaml(vroot, f);
  } catch (const ConfigError& e) {
    throw ConfigError(std::string(e.what()) + " (vehicle " + out.name + ")");
  }
  out.config.fleet_part = out.name;
  const std::string who = out.field + " (" + out.name + ")";
  if (out.config.aircraft.empty()) throw ConfigError(where(f, v) + who + ": no aircraft (aircraft: here or for every vehicle at the top)");
  if (!out.config.mission || out.config.mission.IsNull())
    throw ConfigError(where(f, v) + who + ": no mission (mission: here or for every vehicle at the top)");
  apply_world(out.config, root["world"], f);
  apply_initial(out.config, v["initial"], f, out.field);
  apply_params(out.config, v["params"], f, out.field);
  return out;
}

// `system_id:` of vehicle `v` (the i-th), or i + 1; one another vehicle of `taken` has already is refused.
std::uint8_t load_system_id(const YAML::Node& v, const fs::path& f, const VehicleConfig& out, std::size_t i,
                            const std::map<int, std::string>& taken) {
  int id = static_cast<int>(i) + 1;
  const std::string field = out.field + ".system_id";
  if (const YAML::Node n = v["system_id"]) {
    try {
      id = n.IsScalar() ? n.as<int>() : 0;
    } catch (const YAML::Exception&) {
      id = 0;
    }
    if (id < 1 || id > 255)
      throw ConfigError(where(f, n) + field + ": expected a MAVLink system id, an integer 1-255, got '" + text_of(n) + "'");
  } else if (id > 255) {
    throw ConfigError(where(f, v) + out.field + " (" + out.name + "): no MAVLink system id left (255 at most): give it system_id: 1-255");
  }
  if (const auto it = taken.find(id); it != taken.end())
    throw ConfigError(where(f, v["system_id"] ? v["system_id"] : v) + field + ": MAVLink system id " + std::to_string(id) +
                      (v["system_id"] ? "" : " (its place in vehicles:)") + " of " + out.name + " is " + it->second +
                      "'s already (system_id: gives each vehicle its own, 1-255)");
  return static_cast<std::uint8_t>(id);
}

SeparationConfig load_separation(const YAML::Node& s, const fs::path& f) {
  SeparationConfig out;
  if (!s) return out;
  if (!s.IsMap()) throw ConfigError(where(f, s) + "separation: expected a map (min_distance, response, hold_climb)");
  check_keys(s, f, "separation", {"min_distance", "response", "hold_climb"});
  if (s["min_distance"]) out.min_distance = number(s["min_distance"], f, "separation.min_distance");
  if (!(out.min_distance > 0 && out.min_distance < 1e5))
    throw ConfigError(where(f, s["min_distance"]) + "separation.min_distance: must be > 0 m (and < 100 km), got " +
                      text_of(s["min_distance"]));
  if (s["hold_climb"]) out.hold_climb = number(s["hold_climb"], f, "separation.hold_climb");
  if (!(out.hold_climb >= 0 && out.hold_climb <= 1000))
    throw ConfigError(where(f, s["hold_climb"]) + "separation.hold_climb: must be 0 to 1000 m, got " + text_of(s["hold_climb"]));
  if (const YAML::Node r = s["response"]) {
    const std::string v = r.IsScalar() ? r.Scalar() : "";
    if (v == "report")
      out.response = SeparationConfig::Response::report;
    else if (v == "hold")
      out.response = SeparationConfig::Response::hold;
    else
      throw ConfigError(where(f, r) + "separation.response: expected report or hold, got '" + text_of(r) + "'");
  }
  return out;
}

MissionConfig load_coordination(const YAML::Node& root, const fs::path& f, const std::vector<std::string>& vehicles) {
  YAML::Node croot(YAML::NodeType::Map);
  for (const auto& key : kCoordinationKeys)
    if (root[key]) croot[key] = root[key];
  croot["name"] = "coordination";
  croot["coordination"] = root["coordination"];
  MissionConfig c = config_from_yaml(croot, f, "coordination");
  c.vehicles = vehicles;
  c.fleet_part = "coordination";
  for (const auto& ic : c.plugins)
    if (std::find(vehicles.begin(), vehicles.end(), ic.name) != vehicles.end())
      throw ConfigError(where(f, ic.node) + ic.field + ".name: '" + ic.name + "' is a vehicle's name: give the instance another");
  return c;
}

}  // namespace

bool is_fleet(const YAML::Node& root) { return root.IsMap() && root["vehicles"]; }

bool is_fleet_file(const fs::path& file) {
  try {
    return is_fleet(load_yaml_file(file, "config file"));  // bounded: /dev/zero is no fleet (tern/input_file.hpp)
  } catch (const std::exception&) {
    return false;
  }
}

FleetConfig load_fleet(const fs::path& file_in) {
  FleetConfig out;
  out.file = fs::absolute(file_in).lexically_normal();
  const fs::path& f = out.file;
  out.root = load_yaml(f, "config file");
  const YAML::Node& root = out.root;
  if (!is_fleet(root)) throw ConfigError(where(f, root) + "vehicles: missing (a multi-vehicle mission lists its vehicles)");
  out.name = fleet_name(root, f);
  if (const YAML::Node w = root["world"]) {
    if (!w.IsMap()) throw ConfigError(where(f, w) + "world: expected a map (wind, turbulence, origin)");
    check_keys(w, f, "world", {"wind", "turbulence", "origin"});
  }
  const YAML::Node vs = root["vehicles"];
  if (!vs.IsSequence() || vs.size() == 0) throw ConfigError(where(f, vs) + "vehicles: expected a non-empty list of vehicles");
  std::set<std::string> names;
  std::vector<std::string> order;
  std::map<int, std::string> system_ids;  // MAVLink system id -> vehicle
  for (std::size_t i = 0; i < vs.size(); ++i) {
    VehicleConfig v = load_vehicle(root, vs[i], f, i);
    if (!names.insert(v.name).second)
      throw ConfigError(where(f, vs[i]["name"]) + v.field + ".name: vehicle name '" + v.name + "' is used twice");
    order.push_back(v.name);
    v.system_id = load_system_id(vs[i], f, v, i, system_ids);
    system_ids[v.system_id] = v.name;
    out.vehicles.push_back(std::move(v));
  }
  const MissionConfig& first = out.vehicles.front().config;
  out.seed = first.seed;
  out.duration = first.duration;
  out.log = first.log;
  if (root["coordination"]) out.coordination = load_coordination(root, f, order);
  out.separation = load_separation(root["separation"], f);
  return out;
}

MissionConfig fleet_stack(const fs::path& file) {
  const FleetConfig fleet = load_fleet(file);  // every part checked
  YAML::Node stack(YAML::NodeType::Map);
  for (const auto& kv : fleet.root)
    if (std::find(kFleetOnly.begin(), kFleetOnly.end(), kv.first.as<std::string>()) == kFleetOnly.end()) stack[kv.first] = kv.second;
  stack["name"] = fleet.name;
  MissionConfig c = config_from_yaml(stack, fleet.file);
  c.root = fleet.root;
  return c;
}

MissionConfig load_fleet_part(const fs::path& file, const std::string& part) {
  FleetConfig fleet = load_fleet(file);
  if (part == "coordination" && fleet.coordination) return std::move(*fleet.coordination);
  for (auto& v : fleet.vehicles)
    if (v.name == part) return std::move(v.config);
  throw ConfigError(file.string() + ": no vehicle named '" + part + "'");
}

}  // namespace tern::core
