// Command-line overrides of a mission config: see cli_overrides.hpp.
#include "config/cli_overrides.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "config/error.hpp"

namespace tern::core {

namespace {

constexpr const char* kBuiltins[] = {"phase_machine", "metrics"};

std::vector<std::string> instance_names(const MissionConfig& c) {
  std::vector<std::string> names;
  for (const auto& ic : c.plugins) names.push_back(ic.name);
  return names;
}

bool has_instance(const MissionConfig& c, const std::string& name) {
  for (const auto& ic : c.plugins)
    if (ic.name == name) return true;
  return false;
}

std::string no_instance(const MissionConfig& c, const std::string& name, std::vector<std::string> also = {}) {
  std::vector<std::string> names = instance_names(c);
  names.insert(names.end(), also.begin(), also.end());
  return fmt::format("no plugin instance named '{}'{} (the config's: {})", name, did_you_mean(name, names),
                     fmt::join(instance_names(c), ", "));
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t") - a + 1);
}

std::map<msg::Phase, std::string> parse_phase_table(const MissionConfig& c, const std::vector<std::string>& items,
                                                    const std::string& option) {
  const auto table = parse_phase_entries(c, items, option);
  for (auto p : {msg::Phase::takeoff, msg::Phase::climb, msg::Phase::cruise})
    if (!table.count(p))
      throw ConfigError(fmt::format("{}: no controller for phase '{}' (the table is replaced: takeoff, climb and cruise are required)",
                                    option, msg::phase_name(p)));
  return table;
}

void apply_set(MissionConfig& c, const ParamOverride& po) {
  // a file in the working directory: a relative path value resolves against it, as in a shell
  ParamSetting s{po.value, fs::current_path() / "command-line", po.option, true, po.option};
  if (po.instance == "phase_machine") {
    if (c.phases.empty()) throw ConfigError(po.option + ": this mission has no phase machine (no phases: table; --phases gives one)");
    c.phase_params[po.param] = s;
  } else if (po.instance == "metrics") {
    c.metrics_params[po.param] = s;
  } else {
    bool found = false;
    for (auto& ic : c.plugins)
      if (ic.name == po.instance) {
        ic.params[po.param] = s;
        found = true;
      }
    if (!found) throw ConfigError(po.option + ": " + no_instance(c, po.instance, {std::begin(kBuiltins), std::end(kBuiltins)}));
  }
}

}  // namespace

std::map<msg::Phase, std::string> parse_phase_entries(const MissionConfig& c, const std::vector<std::string>& items,
                                                      const std::string& option) {
  std::vector<std::string> phase_names;
  for (auto p : msg::kControllerPhases) phase_names.emplace_back(msg::phase_name(p));
  std::map<msg::Phase, std::string> table;
  for (const auto& item : items) {
    std::size_t start = 0;
    while (start <= item.size()) {
      const std::size_t comma = std::min(item.find(',', start), item.size());
      const std::string word = trim(item.substr(start, comma - start));
      start = comma + 1;
      if (word.empty()) continue;
      const auto eq = word.find('=');
      if (eq == std::string::npos)
        throw ConfigError(fmt::format("{}: '{}' is not PHASE=INSTANCE (e.g. takeoff=slc,climb=slc,cruise=tecs)", option, word));
      const std::string phase = trim(word.substr(0, eq)), name = trim(word.substr(eq + 1));
      const auto p = msg::phase_from_name(phase);
      if (!p || *p == msg::Phase::preflight || *p == msg::Phase::stopped)
        throw ConfigError(fmt::format("{}: unknown phase '{}'{} (one of {})", option, phase, did_you_mean(phase, phase_names),
                                      fmt::join(phase_names, ", ")));
      if (!has_instance(c, name)) throw ConfigError(fmt::format("{}: {}: {}", option, phase, no_instance(c, name)));
      if (!table.emplace(*p, name).second) throw ConfigError(fmt::format("{}: phase '{}' is given twice", option, phase));
    }
  }
  return table;
}

ParamOverride parse_param_override(const std::string& item) {
  const auto eq = item.find('=');
  const std::string name = item.substr(0, eq);
  const auto dot = name.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 == name.size())
    throw ConfigError(fmt::format("--set '{}': give INSTANCE.PARAM=VALUE, e.g. --set slc.roll_kp=0.5", item));
  ParamOverride po{name.substr(0, dot), name.substr(dot + 1), YAML::Node(), "--set " + item};
  const std::string text = item.substr(eq + 1);
  try {
    po.value = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(fmt::format("{}: the value is not YAML: {}", po.option, e.msg));
  }
  if (po.value.IsNull() || po.value.IsMap())
    throw ConfigError(fmt::format("{}: expected a value: a number, true/false, text or [a, b, c]", po.option));
  try {
    (void)to_param_value(po.value, "", "");
  } catch (const ConfigError&) {
    throw ConfigError(fmt::format("{}: expected a value: a number, true/false, text or a list of numbers [a, b, c]", po.option));
  }
  return po;
}

void apply_overrides(MissionConfig& c, const CliOverrides& o) {
  if (!o.phases.empty()) {
    c.phases_option = "--phases " + fmt::format("{}", fmt::join(o.phases, " "));
    c.phases = parse_phase_table(c, o.phases, c.phases_option);
    c.overrides.push_back(c.phases_option);
  }
  if (o.fallback) {
    c.fallback_option = "--fallback " + *o.fallback;
    if (c.phases.empty()) throw ConfigError(c.fallback_option + ": needs a phase table (the config's phases: or --phases)");
    if (!has_instance(c, *o.fallback)) throw ConfigError(c.fallback_option + ": " + no_instance(c, *o.fallback));
    c.fallback = *o.fallback;
    c.overrides.push_back(c.fallback_option);
  }
  for (const auto& item : o.sets) {
    const ParamOverride po = parse_param_override(item);
    apply_set(c, po);
    c.overrides.push_back(po.option);
  }
}

}  // namespace tern::core
