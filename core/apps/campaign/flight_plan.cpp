#include "flight_plan.hpp"

#include <algorithm>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "config/error.hpp"
#include "files/log_file.hpp"

namespace tern::campaign {

using core::ConfigError;

std::string shell_quote(const std::string& s) {
  if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-./=:+") == std::string::npos)
    return s;
  std::string q = "'";
  for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

namespace {

YAML::Node to_yaml(const ParamValue& v) {
  if (const auto* x = std::get_if<std::vector<double>>(&v)) {
    YAML::Node n(YAML::NodeType::Sequence);
    for (double d : *x) n.push_back(number_text(d));
    n.SetStyle(YAML::EmitterStyle::Flow);
    return n;
  }
  if (const auto* d = std::get_if<double>(&v)) return YAML::Node(number_text(*d));
  if (const auto* i = std::get_if<std::int64_t>(&v)) return YAML::Node(*i);
  if (const auto* b = std::get_if<bool>(&v)) return YAML::Node(*b ? "true" : "false");
  return YAML::Node(std::get<std::string>(v));
}

/// Replaced at once (log_file.hpp's temp file + rename); a failure is one ConfigError line.
void write_text(const fs::path& p, const std::string& text) {
  core::LogHealth health;
  if (!core::write_file_atomically(p, text, health)) throw ConfigError(health.error());
}

std::string emit(const YAML::Node& n) {
  YAML::Emitter e;
  e << n;
  return std::string(e.c_str()) + "\n";
}

/// The instance's parameters as set by the base (param files inlined), path values absolute.
YAML::Node base_params(const core::InstanceConfig& ic, const ParamCatalogue& params) {
  YAML::Node out(YAML::NodeType::Map);
  for (const auto& [name, setting] : ic.params) {
    YAML::Node v = YAML::Clone(setting.node);
    const auto it = params.find(ic.name + "." + name);
    if (it != params.end() && it->second->spec().is_path && v.IsScalar() && !v.Scalar().empty() && fs::path(v.Scalar()).is_relative())
      v = (setting.file.parent_path() / v.Scalar()).lexically_normal().string();
    out[name] = v;
  }
  return out;
}

/// A multi-vehicle base's paths (each vehicle's aircraft and mission file, the coordination's
/// parameter files) made absolute: the flight's copy lives in another directory.
void absolute_fleet_paths(YAML::Node& root, const fs::path& dir) {
  const auto absolute = [&dir](YAML::Node n) {
    if (n && n.IsScalar() && fs::path(n.Scalar()).is_relative()) n = (dir / n.Scalar()).lexically_normal().string();
  };
  if (root["vehicles"] && root["vehicles"].IsSequence())
    for (YAML::Node v : root["vehicles"]) {
      absolute(v["aircraft"]);
      if (v["mission"] && v["mission"].IsMap()) absolute(v["mission"]["file"]);
    }
  if (root["coordination"] && root["coordination"].IsSequence())
    for (YAML::Node p : root["coordination"]) absolute(p["param_file"]);
}

/// In a multi-vehicle flight the world (`world:`, fleet_config.hpp) sets the simulator's wind and
/// turbulence: a draw of sim.wind or sim.turbulence goes there, not into the shared stack.
void move_world_settings(YAML::Node& root, const core::MissionConfig& base) {
  if (!root["world"] || !root["world"].IsMap()) return;
  for (const auto& ic : base.plugins) {
    if (ic.plugin != "sim_aero") continue;
    YAML::Node params = root["plugins"][ic.index]["params"];
    for (const char* key : {"wind", "turbulence"})
      if (params[key] && root["world"][key]) {
        root["world"][key] = YAML::Clone(params[key]);
        params.remove(key);
      }
  }
}

/// The instance parameter that names the simulator's aircraft file.
std::string aircraft_param(const ParamCatalogue& params) {
  for (const auto& [name, p] : params)
    if (p->name() == "aircraft" && p->spec().is_path) return name;
  throw ConfigError(
      "the campaign perturbs the aircraft, but no instance of the base mission has an 'aircraft' file parameter (sim_aero's)");
}

YAML::Node perturbed_aircraft(const YAML::Node& aircraft, const FlightDraw& draw) {
  YAML::Node a = YAML::Clone(aircraft);
  for (const auto& [path, value] : draw.aircraft) {
    YAML::Node n = a;
    std::size_t from = 0;
    for (std::size_t dot; (dot = path.find('.', from)) != std::string::npos; from = dot + 1) n.reset(n[path.substr(from, dot - from)]);
    n[path.substr(from)] = number_text(value);
  }
  return a;
}

}  // namespace

FlightFiles flight_files(const fs::path& out, std::size_t k, const fs::path& tern_bin) {
  FlightFiles f;
  f.index = k;
  f.dir = out / "flights" / fmt::format("{:05}", k);
  f.config = f.dir / "config.yaml";
  f.aircraft = f.dir / "aircraft.yaml";
  f.run_dir = f.dir / "run";
  f.console = f.dir / "fly.log";
  f.argv = {tern_bin.string(), "fly", f.config.string(), "--log-dir", f.run_dir.string(), "-q"};
  for (const auto& a : f.argv) {
    if (!f.command.empty()) f.command += ' ';
    f.command += shell_quote(a);
  }
  return f;
}

void write_flight(const CampaignFile& c, const core::MissionConfig& base, const ParamCatalogue& params, const YAML::Node& aircraft,
                  const FlightDraw& draw, const FlightFiles& files) {
  fs::create_directories(files.dir);
  YAML::Node root = YAML::Clone(base.root);
  root["name"] = fmt::format("{}-{:05}", c.name, draw.index);
  root["seed"] = draw.seed;
  if (c.duration) root["duration"] = number_text(*c.duration);
  if (!base.aircraft.empty()) root["aircraft"] = base.aircraft.string();
  if (root["plugin_path"]) {
    YAML::Node pp(YAML::NodeType::Sequence);
    for (const auto& d : base.plugin_path) pp.push_back(d.string());
    root["plugin_path"] = pp;
  }
  YAML::Node log = root["log"] && root["log"].IsMap() ? root["log"] : YAML::Node(YAML::NodeType::Map);
  log.remove("dir");
  log["level"] = c.log_level;
  root["log"] = log;
  if (root["mission"] && root["mission"].IsMap() && root["mission"]["file"] && root["mission"]["file"].IsScalar()) {
    const fs::path mf(root["mission"]["file"].Scalar());
    if (mf.is_relative()) root["mission"]["file"] = (base.dir / mf).lexically_normal().string();
  }
  absolute_fleet_paths(root, base.dir);
  std::map<std::string, YAML::Node> instance_params;  // instance -> params map
  for (const auto& ic : base.plugins) {
    root["plugins"][ic.index].remove("param_file");
    instance_params[ic.name] = base_params(ic, params);
  }
  std::map<std::string, ParamValue> set = draw.params;
  if (!draw.aircraft.empty()) {
    write_text(files.aircraft, "# " + c.name + fmt::format(" flight {}: ", draw.index) + base.aircraft.string() + ", perturbed\n" +
                                   emit(perturbed_aircraft(aircraft, draw)));
    set[aircraft_param(params)] = files.aircraft.string();
  }
  for (const auto& [qualified, value] : set) {
    const std::string inst = qualified.substr(0, qualified.find('.')), name = qualified.substr(qualified.find('.') + 1);
    if (instance_params.count(inst)) {
      instance_params[inst][name] = to_yaml(value);
    } else {  // a built-in's section: phase_machine:, metrics:
      root[inst][name] = to_yaml(value);
    }
  }
  for (const auto& ic : base.plugins) root["plugins"][ic.index]["params"] = instance_params[ic.name];
  move_world_settings(root, base);
  write_text(
      files.config,
      fmt::format("# campaign {} ({}), flight {}: re-fly with\n#   {}\n", c.name, c.file.string(), draw.index, files.command) + emit(root));
}

fs::path finished_summary(const FlightFiles& files) {
  std::error_code ec;
  std::vector<fs::path> found;
  for (const auto& e : fs::directory_iterator(files.run_dir, ec))
    if (fs::exists(e.path() / "summary.json")) found.push_back(e.path() / "summary.json");
  std::sort(found.begin(), found.end());
  for (const auto& p : found) {
    std::ifstream in(p);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_discarded() || !j.contains("end_reason")) continue;
    const std::string end = j["end_reason"].get<std::string>();
    if (end != "SIGINT" && end != "SIGTERM" && end != "SIGHUP") return p;
  }
  return {};
}

}  // namespace tern::campaign
