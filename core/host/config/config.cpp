#include "config/config.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <iterator>
#include <set>

#include <fmt/format.h>

#include "config/error.hpp"
#include "config/external_spec.hpp"
#include "config/failsafe_config.hpp"
#include "tern/input_file.hpp"

namespace tern::core {

namespace {

std::string str(const YAML::Node& n) {
  return n.IsScalar() ? n.Scalar() : std::string("<") + (n.IsMap() ? "map" : n.IsSequence() ? "list" : "null") + ">";
}

void require_map(const YAML::Node& n, const fs::path& file, const std::string& field) {
  if (!n.IsMap()) throw ConfigError(where(file, n) + field + ": expected a map of key: value, got " + str(n));
}

double as_number(const YAML::Node& n, const fs::path& file, const std::string& field) {
  if (!n.IsScalar()) throw ConfigError(where(file, n) + field + ": expected a number, got " + str(n));
  try {
    const double v = n.as<double>();
    if (!std::isfinite(v)) throw YAML::Exception(n.Mark(), "not finite");
    return v;
  } catch (const YAML::Exception&) {
    throw ConfigError(where(file, n) + field + ": expected a number, got '" + n.Scalar() + "'");
  }
}

std::string as_string(const YAML::Node& n, const fs::path& file, const std::string& field) {
  if (!n.IsScalar() || n.Scalar().empty()) throw ConfigError(where(file, n) + field + ": expected a non-empty string, got " + str(n));
  return n.Scalar();
}

fs::path resolve(const fs::path& base_dir, const std::string& p) {
  fs::path path(p);
  if (path.is_relative()) path = base_dir / path;
  return path.lexically_normal();
}

std::map<std::string, ParamSetting> params_from_map(const YAML::Node& map, const fs::path& file, const std::string& field, bool strict) {
  std::map<std::string, ParamSetting> out;
  check_unique_keys(map, file, field);
  for (const auto& kv : map) {
    const std::string key = key_name(kv.first, file, field);
    out[key] = ParamSetting{kv.second, file, field.empty() ? key : field + "." + key, strict};
  }
  return out;
}

}  // namespace

YAML::Node load_yaml(const fs::path& file, const char* what) {
  if (!fs::exists(file)) throw ConfigError(std::string(what) + " '" + file.string() + "' not found");
  try {
    return load_yaml_file(file, what);  // a regular file, bounded (tern/input_file.hpp)
  } catch (const std::runtime_error& e) {
    throw ConfigError(e.what());
  }
}

namespace {

/// A rate (Hz) the scheduler can run: > 0 and <= kMaxRateHz.
double as_rate(const YAML::Node& n, const fs::path& file, const std::string& field) {
  const double r = as_number(n, file, field);
  if (!(r > 0)) throw ConfigError(where(file, n) + field + ": must be > 0 Hz, got " + str(n));
  if (r > kMaxRateHz)
    throw ConfigError(where(file, n) + field + fmt::format(": {} Hz is above the scheduler's limit of {} Hz", str(n), kMaxRateHz));
  return r;
}

/// A mission name: it names the run directory, so a file-name word ([A-Za-z0-9_][A-Za-z0-9_.-]*).
std::string mission_name(const YAML::Node& n, const fs::path& file) {
  const std::string v = as_string(n, file, "name");
  const bool ok = std::isalnum(static_cast<unsigned char>(v[0])) || v[0] == '_';
  if (!ok || v.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-") != std::string::npos)
    throw ConfigError(where(file, n) + "name: '" + v +
                      "' must be letters, digits, '_', '-' and '.' (not first): it names the run directory");
  return v;
}

}  // namespace

const char* log_level_name(LogLevel level) {
  switch (level) {
    case LogLevel::summary: return "summary";
    case LogLevel::decimated: return "decimated";
    case LogLevel::replay: return "replay";
    case LogLevel::sysid: return "sysid";
    case LogLevel::full: return "full";
  }
  return "full";
}

namespace {
constexpr LogLevel kLogLevels[] = {LogLevel::summary, LogLevel::decimated, LogLevel::replay, LogLevel::sysid, LogLevel::full};
}

std::optional<LogLevel> log_level_from_name(const std::string& name) {
  for (LogLevel l : kLogLevels)
    if (name == log_level_name(l)) return l;
  return std::nullopt;
}

std::string log_level_names() {
  std::string names;
  const std::size_t n = std::size(kLogLevels);
  for (std::size_t i = 0; i < n; ++i) names += std::string(i == 0 ? "" : i + 1 == n ? " or " : ", ") + log_level_name(kLogLevels[i]);
  return names;
}

const char* log_format_name(LogFormat format) {
  switch (format) {
    case LogFormat::csv: return "csv";
    case LogFormat::mcap: return "mcap";
    case LogFormat::both: return "both";
  }
  return "csv";
}

std::optional<LogFormat> log_format_from_name(const std::string& name) {
  for (LogFormat f : {LogFormat::csv, LogFormat::mcap, LogFormat::both})
    if (name == log_format_name(f)) return f;
  return std::nullopt;
}

std::string duration_problem(double s) {
  if (!std::isfinite(s)) return fmt::format("must be a finite number of seconds, got {}", s);
  if (!(s > 0)) return fmt::format("must be > 0 s, got {}", s);
  if (s > kMaxDurationS) return fmt::format("must be at most {} s ({:.1f} days), got {}", kMaxDurationS, kMaxDurationS / 86400, s);
  return "";
}

std::optional<std::uint64_t> parse_seed(const std::string& text) {
  std::uint64_t v = 0;
  const char* end = text.data() + text.size();
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  const auto [p, ec] = std::from_chars(text.data(), end, v);
  if (ec != std::errc() || p != end) return std::nullopt;  // out of range
  return v;
}

std::string identifier_problem(const std::string& name) {
  const bool ok = !name.empty() && (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_') &&
                  name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") == std::string::npos;
  return ok ? "" : "'" + name + "' is not an identifier (letters, digits and '_', not starting with a digit)";
}

void check_log_topics(const MissionConfig& c, const std::vector<std::string>& published) {
  const YAML::Node log = c.root["log"];
  if (!log) return;
  auto check = [&](const YAML::Node& node, const std::string& field) {
    const std::string t = node.Scalar();
    if (std::find(published.begin(), published.end(), t) == published.end())
      throw ConfigError(where(c.file, node) + field + ": no instance publishes topic '" + t + "'" + did_you_mean(t, published));
  };
  if (const YAML::Node t = log["topics"]; t && t.IsSequence())
    for (std::size_t i = 0; i < t.size(); ++i) check(t[i], "log.topics[" + std::to_string(i) + "]");
  if (const YAML::Node r = log["rates"])
    for (const auto& kv : r) check(kv.first, "log.rates." + kv.first.Scalar());
}

std::string ParamSetting::location() const { return option.empty() ? where(file, node) + field : option; }

std::string ParamSetting::source() const {
  if (!option.empty()) return option;
  if (!node.IsDefined() || node.Mark().is_null()) return file.string();
  return file.string() + ":" + std::to_string(node.Mark().line + 1);
}

ParamValue to_param_value(const YAML::Node& node, const fs::path& file, const std::string& field) {
  if (node.IsSequence()) {
    std::vector<double> v;
    for (const auto& e : node) {
      if (!e.IsScalar()) throw ConfigError(where(file, e) + field + ": expected a list of numbers");
      try {
        v.push_back(e.as<double>());
      } catch (const YAML::Exception&) {
        throw ConfigError(where(file, e) + field + ": expected a list of numbers, got '" + e.Scalar() + "'");
      }
    }
    return v;
  }
  if (!node.IsScalar()) throw ConfigError(where(file, node) + field + ": expected a value, got " + str(node));
  const std::string& s = node.Scalar();
  if (node.Tag() == "!") return s;  // quoted: always text
  if (s == "true" || s == "True" || s == "TRUE") return true;
  if (s == "false" || s == "False" || s == "FALSE") return false;
  {
    std::size_t pos = 0;
    try {
      const long long i = std::stoll(s, &pos, 10);
      if (pos == s.size()) return static_cast<std::int64_t>(i);
    } catch (const std::exception&) {
    }
  }
  try {
    const double d = node.as<double>();
    return d;
  } catch (const YAML::Exception&) {
  }
  return s;
}

std::map<std::string, ParamSetting> load_param_file(const fs::path& file, const std::string& instance, const std::string& plugin) {
  const YAML::Node root = load_yaml(file, "parameter file");
  if (root.IsNull()) return {};
  require_map(root, file, "parameter file");
  bool ros2 = false;
  for (const auto& kv : root) {
    if (kv.second.IsMap() && kv.second["ros__parameters"]) ros2 = true;
  }
  if (!ros2) return params_from_map(root, file, "", true);
  std::map<std::string, ParamSetting> out;
  for (const std::string& block : {std::string("/**"), plugin, instance}) {
    for (const std::string& key : {block, "/" + block}) {
      const YAML::Node b = root[key];
      if (!b || !b.IsMap() || !b["ros__parameters"]) continue;
      const YAML::Node p = b["ros__parameters"];
      require_map(p, file, key + ".ros__parameters");
      for (auto& [k, v] : params_from_map(p, file, key + ".ros__parameters", false)) out[k] = v;
    }
  }
  return out;
}

MissionConfig load_config(const fs::path& file_in) {
  const fs::path file = fs::absolute(file_in).lexically_normal();
  const YAML::Node root = load_yaml(file, "config file");
  if (root.IsMap() && root["vehicles"])
    throw ConfigError(where(file, root["vehicles"]) +
                      "vehicles: a multi-vehicle mission: `tern fly` and `tern check` take it (docs/multi-vehicle.md), not this command");
  try {
    return config_from_yaml(root, file);
  } catch (const YAML::Exception& e) {  // a value of a type no reader expected there (a key that is a list)
    throw ConfigError(where(file, e.mark) + e.msg);
  }
}

// ---- config_from_yaml's readers, one per section of the mission file, in the order it calls them

namespace {

void read_watchdog(const YAML::Node& root, const fs::path& f, MissionConfig& c) {
  if (const YAML::Node wd = root["watchdog"]) {
    require_map(wd, f, "watchdog");
    check_keys(wd, f, "watchdog", {"soft_ms", "hard_ms"});
    if (wd["soft_ms"]) c.watchdog.soft_ms = as_number(wd["soft_ms"], f, "watchdog.soft_ms");
    if (wd["hard_ms"]) c.watchdog.hard_ms = as_number(wd["hard_ms"], f, "watchdog.hard_ms");
    if (!(c.watchdog.soft_ms > 0 && c.watchdog.soft_ms <= c.watchdog.hard_ms && c.watchdog.hard_ms <= 3.6e6))
      throw ConfigError(where(f, wd) + fmt::format("watchdog: need 0 < soft_ms <= hard_ms <= 3600000, got soft_ms {}, hard_ms {}",
                                                   c.watchdog.soft_ms, c.watchdog.hard_ms));
  }
}

void read_check(const YAML::Node& root, const fs::path& f, MissionConfig& c) {
  if (const YAML::Node ck = root["check"]) {
    require_map(ck, f, "check");
    check_keys(ck, f, "check", {"max_waypoint_distance"});
    if (const YAML::Node d = ck["max_waypoint_distance"]) {
      c.check.max_waypoint_distance = as_number(d, f, "check.max_waypoint_distance");
      if (!(c.check.max_waypoint_distance > 0))
        throw ConfigError(where(f, d) + "check.max_waypoint_distance: must be > 0 m, got " + str(d));
    }
  }
}

// name, seed, duration, base_rate, aircraft, plugin_path
void read_run(const YAML::Node& root, const fs::path& f, MissionConfig& c) {
  c.name = root["name"] ? mission_name(root["name"], f) : c.file.stem().string();
  if (root["seed"]) {
    const auto seed = root["seed"].IsScalar() ? parse_seed(root["seed"].Scalar()) : std::nullopt;
    if (!seed) throw ConfigError(where(f, root["seed"]) + "seed: expected an integer 0 .. 2^64-1, got '" + str(root["seed"]) + "'");
    c.seed = *seed;
  }
  if (root["duration"]) {
    c.duration = as_number(root["duration"], f, "duration");
    if (const std::string p = duration_problem(c.duration); !p.empty()) throw ConfigError(where(f, root["duration"]) + "duration: " + p);
  }
  if (root["base_rate"]) c.base_rate = as_rate(root["base_rate"], f, "base_rate");
  if (root["aircraft"]) c.aircraft = resolve(c.dir, as_string(root["aircraft"], f, "aircraft"));
  if (const YAML::Node pp = root["plugin_path"]) {
    if (pp.IsScalar()) {
      c.plugin_path.push_back(resolve(c.dir, pp.Scalar()));
    } else if (pp.IsSequence()) {
      for (std::size_t i = 0; i < pp.size(); ++i)
        c.plugin_path.push_back(resolve(c.dir, as_string(pp[i], f, "plugin_path[" + std::to_string(i) + "]")));
    } else {
      throw ConfigError(where(f, pp) + "plugin_path: expected a directory or a list of directories");
    }
  }
}

// log.decimated_rate, plot_rate, max_rate, rates: how often each topic is written
void read_log_rates(const YAML::Node& log, const fs::path& f, MissionConfig& c) {
  if (log["decimated_rate"]) {
    c.log.decimated_rate = as_number(log["decimated_rate"], f, "log.decimated_rate");
    if (!(c.log.decimated_rate > 0)) throw ConfigError(where(f, log["decimated_rate"]) + "log.decimated_rate: must be > 0 Hz");
  }
  if (log["plot_rate"]) {
    c.log.plot_rate = as_number(log["plot_rate"], f, "log.plot_rate");
    if (!(c.log.plot_rate > 0)) throw ConfigError(where(f, log["plot_rate"]) + "log.plot_rate: must be > 0 Hz");
  }
  if (log["max_rate"]) {
    c.log.max_rate = as_number(log["max_rate"], f, "log.max_rate");
    if (c.log.max_rate < 0) throw ConfigError(where(f, log["max_rate"]) + "log.max_rate: must be >= 0 Hz (0: every message)");
    if (!log["level"]) c.log.level = LogLevel::full;  // max_rate is level full's: giving it alone asks for that level
  }
  if (const YAML::Node rates = log["rates"]) {
    require_map(rates, f, "log.rates");
    for (const auto& kv : rates) {
      const std::string k = key_name(kv.first, f, "log.rates");
      const double r = as_number(kv.second, f, "log.rates." + k);
      if (r < 0) throw ConfigError(where(f, kv.second) + "log.rates." + k + ": must be >= 0 Hz (0: every message)");
      c.log.rates[k] = r;
    }
  }
}

void read_log(const YAML::Node& root, const fs::path& f, MissionConfig& c) {
  c.log.dir = fs::current_path() / "runs";
  if (root["log"] && root["log"].IsScalar()) {  // `log: summary` is short for `log: {level: summary}`
    YAML::Node m(YAML::NodeType::Map);
    m["level"] = root["log"];
    c.root["log"] = m;
  }
  if (const YAML::Node log = root["log"]) {
    require_map(log, f, "log");
    check_keys(log, f, "log",
               {"dir", "level", "format", "chunk_size", "ros_channels", "zstd_level", "decimated_rate", "plot_rate", "topics", "max_rate",
                "rates"});
    if (const YAML::Node fm = log["format"]) {
      const auto format = fm.IsScalar() ? log_format_from_name(fm.Scalar()) : std::nullopt;
      if (!format) throw ConfigError(where(f, fm) + "log.format: expected csv, mcap or both, got '" + str(fm) + "'");
      c.log.format = *format;
    }
    if (log["chunk_size"]) {
      const double n = as_number(log["chunk_size"], f, "log.chunk_size");
      if (!(n >= 1024 && n <= 1024.0 * 1024 * 1024))
        throw ConfigError(where(f, log["chunk_size"]) + "log.chunk_size: must be 1024 to 1073741824 bytes, got " + str(log["chunk_size"]));
      c.log.chunk_size = static_cast<std::size_t>(n);
    }
    if (const YAML::Node rc = log["ros_channels"]) c.log.ros_channels = yaml_bool(rc, f, "log.ros_channels");
    if (const YAML::Node z = log["zstd_level"]) {
      const double n = as_number(z, f, "log.zstd_level");
      if (!(n >= kZstdLevelMin && n <= kZstdLevelMax && n == std::floor(n)))
        throw ConfigError(where(f, z) +
                          fmt::format("log.zstd_level: must be an integer from {} to {}, got {}", kZstdLevelMin, kZstdLevelMax, str(z)));
      c.log.zstd_level = static_cast<int>(n);
    }
    if (const YAML::Node lv = log["level"]) {
      const auto level = lv.IsScalar() ? log_level_from_name(lv.Scalar()) : std::nullopt;
      if (!level) throw ConfigError(where(f, lv) + "log.level: expected " + log_level_names() + ", got '" + str(lv) + "'");
      c.log.level = *level;
    }
    read_log_rates(log, f, c);
    if (log["dir"]) c.log.dir = resolve(c.dir, as_string(log["dir"], f, "log.dir"));
    if (const YAML::Node t = log["topics"]) {
      if (t.IsScalar() && t.Scalar() == "all") {
        c.log.all_topics = true;
      } else if (t.IsSequence()) {
        c.log.all_topics = false;
        for (std::size_t i = 0; i < t.size(); ++i) c.log.topics.push_back(as_string(t[i], f, "log.topics[" + std::to_string(i) + "]"));
      } else {
        throw ConfigError(where(f, t) + "log.topics: expected 'all' or a list of topic names");
      }
    }
  }
}

// One entry of `plugins:` (`coordination:` in a fleet); `names` collects the instance names.
InstanceConfig read_instance(const YAML::Node& p, std::size_t i, const std::string& plugins_key, const fs::path& f, const fs::path& dir,
                             std::set<std::string>& names) {
  const std::string field = plugins_key + "[" + std::to_string(i) + "]";
  require_map(p, f, field);
  // `library` is written by the flight log's resolved config.yaml (where the plugin came from)
  std::vector<std::string> keys{"name", "plugin", "rate", "trigger", "params", "param_file", "remap", "budget_us", "library", "isolate"};
  // an external module's ports are DDS topics (external_spec.hpp)
  const bool external = p["plugin"] && p["plugin"].IsScalar() && p["plugin"].Scalar() == "external";
  if (external) keys.insert(keys.end(), external_keys().begin(), external_keys().end());
  check_keys(p, f, field, keys);
  InstanceConfig ic;
  ic.index = i;
  ic.field = field;
  ic.node = p;
  if (!p["plugin"]) throw ConfigError(where(f, p) + field + ": missing key 'plugin' (the plugin to load, e.g. sim_aero)");
  ic.plugin = as_string(p["plugin"], f, field + ".plugin");
  ic.name = p["name"] ? as_string(p["name"], f, field + ".name") : ic.plugin;
  if (const std::string bad = identifier_problem(ic.name); !bad.empty())
    throw ConfigError(where(f, p["name"] ? p["name"] : p["plugin"]) + field + ".name: " + bad +
                      (p["name"] ? "" : " (the instance is named after its plugin: give it a name:)"));
  if (!names.insert(ic.name).second)
    throw ConfigError(where(f, p["name"] ? p["name"] : p) + field + ".name: instance name '" + ic.name + "' is used twice");
  if (p["rate"]) ic.rate = as_rate(p["rate"], f, field + ".rate");
  if (p["trigger"]) ic.trigger = as_string(p["trigger"], f, field + ".trigger");
  if (ic.rate && ic.trigger) throw ConfigError(where(f, p["trigger"]) + field + ": give either rate or trigger, not both");
  if (!ic.rate && !ic.trigger)
    throw ConfigError(where(f, p) + field + " (" + ic.name + "): missing 'rate' (Hz) or 'trigger' (an input port name)");
  if (p["budget_us"]) {
    ic.budget_us = as_number(p["budget_us"], f, field + ".budget_us");
    if (!(*ic.budget_us > 0))
      throw ConfigError(where(f, p["budget_us"]) + field + ".budget_us: must be > 0 us, got " + str(p["budget_us"]));
  }
  if (const YAML::Node iso = p["isolate"]) ic.isolate = yaml_bool(iso, f, field + ".isolate");
  if (const YAML::Node pf = p["param_file"]) {
    const fs::path pfile = resolve(dir, as_string(pf, f, field + ".param_file"));
    try {
      ic.params = load_param_file(pfile, ic.name, ic.plugin);
    } catch (const ConfigError& e) {
      if (!fs::exists(pfile)) throw ConfigError(where(f, pf) + field + ".param_file: '" + pfile.string() + "' not found");
      throw;
    }
  }
  if (const YAML::Node pr = p["params"]) {
    if (!pr.IsNull()) {
      require_map(pr, f, field + ".params");
      for (auto& [k, v] : params_from_map(pr, f, field + ".params", true)) ic.params[k] = v;
    }
  }
  if (const YAML::Node rm = p["remap"]) {
    require_map(rm, f, field + ".remap");
    for (const auto& kv : rm) {
      const std::string port = key_name(kv.first, f, field + ".remap");
      ic.remap[port] = as_string(kv.second, f, field + ".remap." + port);
    }
  }
  return ic;
}

void read_plugins(const YAML::Node& root, const fs::path& f, const std::string& plugins_key, MissionConfig& c) {
  const YAML::Node plugins = root[plugins_key];
  if (!plugins) throw ConfigError(f.string() + ": " + plugins_key + ": missing (the list of plugin instances to load)");
  if (!plugins.IsSequence() || plugins.size() == 0)
    throw ConfigError(where(f, plugins) + plugins_key + ": expected a non-empty list of plugin instances");
  std::set<std::string> names;
  for (std::size_t i = 0; i < plugins.size(); ++i) c.plugins.push_back(read_instance(plugins[i], i, plugins_key, f, c.dir, names));
}

// phases, fallback, phase_machine: the controllers they name must be instances of `plugins:`
void read_phases(const YAML::Node& root, const fs::path& f, MissionConfig& c) {
  std::vector<std::string> instance_names;
  for (const auto& ic : c.plugins) instance_names.push_back(ic.name);
  const std::set<std::string> names(instance_names.begin(), instance_names.end());
  auto check_instance = [&](const YAML::Node& n, const std::string& field) {
    const std::string v = as_string(n, f, field);
    if (!names.count(v))
      throw ConfigError(where(f, n) + field + ": no plugin instance named '" + v + "'" + did_you_mean(v, instance_names));
    return v;
  };
  if (const YAML::Node ph = root["phases"]) {
    require_map(ph, f, "phases");
    std::vector<std::string> phase_names;
    for (auto p : msg::kControllerPhases) phase_names.emplace_back(msg::phase_name(p));
    check_keys(ph, f, "phases", phase_names);
    for (const auto& kv : ph) {
      const std::string key = kv.first.as<std::string>();
      c.phases[*msg::phase_from_name(key)] = check_instance(kv.second, "phases." + key);
    }
    for (auto p : {msg::Phase::takeoff, msg::Phase::climb, msg::Phase::cruise}) {
      if (!c.phases.count(p))
        throw ConfigError(where(f, ph) + "phases: no controller for phase '" + std::string(msg::phase_name(p)) +
                          "' (takeoff, climb and cruise are required)");
    }
  }
  if (root["fallback"]) {
    if (!root["phases"]) throw ConfigError(where(f, root["fallback"]) + "fallback: needs a 'phases:' table");
    c.fallback = check_instance(root["fallback"], "fallback");
  }
  if (const YAML::Node pm = root["phase_machine"]) {
    if (!root["phases"]) throw ConfigError(where(f, pm) + "phase_machine: needs a 'phases:' table");
    require_map(pm, f, "phase_machine");
    c.phase_params = params_from_map(pm, f, "phase_machine", true);
  }
}

}  // namespace

MissionConfig config_from_yaml(const YAML::Node& root, const fs::path& file, const std::string& plugins_key) {
  MissionConfig c;
  c.file = file;
  c.dir = c.file.parent_path();
  const fs::path& f = c.file;
  if (!root.IsMap()) throw ConfigError(where(f, root) + "a mission config is a map of key: value");
  c.root = root;
  check_keys(root, f, "",
             {"name", "seed", "duration", "base_rate", "aircraft", "plugin_path", "log", plugins_key, "phases", "fallback", "phase_machine",
              "metrics", "mission", "dds", "failsafes", "watchdog", "check"});
  read_watchdog(root, f, c);
  read_check(root, f, c);
  read_run(root, f, c);
  read_log(root, f, c);
  read_plugins(root, f, plugins_key, c);
  read_phases(root, f, c);
  if (const YAML::Node mt = root["metrics"]) {
    require_map(mt, f, "metrics");
    c.metrics_params = params_from_map(mt, f, "metrics", true);
  }
  if (root["mission"]) c.mission = root["mission"];
  if (root["dds"]) c.dds = root["dds"];
  c.failsafes = parse_failsafes(root["failsafes"], f);
  return c;
}

}  // namespace tern::core
