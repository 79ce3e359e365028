#include "record/resolved_config.hpp"

#include <filesystem>
#include <type_traits>
#include <variant>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include "tern/msg/phase.hpp"

namespace tern::core {

namespace {

YAML::Node to_yaml(const ParamValue& v) {
  YAML::Node n;
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::vector<double>>) {
          n = YAML::Node(YAML::NodeType::Sequence);
          for (double d : x) n.push_back(d);
          n.SetStyle(YAML::EmitterStyle::Flow);
        } else {
          n = x;
        }
      },
      v);
  return n;
}

/// Everything resolved_config_yaml reads that may change between two flights of one host, but
/// the seed (the config file's own tree does not change): the duration, the phase table, the
/// fallback, and per instance its library and parameter values.
std::string inputs_but_seed(const FlightFacts& f) {
  std::string s = fmt::format("{}\n", f.duration_s);
  for (const auto& [phase, instance] : f.config.phases) s += fmt::format("{}={}\n", static_cast<int>(phase), instance);
  if (f.config.fallback) s += fmt::format("fallback={}\n", *f.config.fallback);
  for (const auto& inst : f.instances) {
    s += fmt::format("[{}] {}\n", inst->cfg.name, inst->info.path.string());
    for (const auto* p : inst->plugin->params()) std::visit([&](const auto& x) { s += fmt::format("{}={}\n", p->name(), x); }, p->value());
  }
  return s;
}

}  // namespace

std::string resolved_config_yaml(const FlightFacts& f) {
  YAML::Node root = YAML::Clone(f.config.root);
  // paths made absolute: the resolved config lives in the run directory, not beside the original
  if (!f.config.aircraft.empty()) root["aircraft"] = f.config.aircraft.string();
  if (root["plugin_path"]) {
    YAML::Node pp(YAML::NodeType::Sequence);
    for (const auto& d : f.config.plugin_path) pp.push_back(d.string());
    root["plugin_path"] = pp;
  }
  if (root["log"] && root["log"]["dir"]) root["log"]["dir"] = f.config.log.dir.string();
  if (root["mission"] && root["mission"].IsMap() && root["mission"]["file"] && root["mission"]["file"].IsScalar()) {
    const fs::path mf(root["mission"]["file"].Scalar());
    if (mf.is_relative()) root["mission"]["file"] = (f.config.dir / mf).lexically_normal().string();
  }
  root["name"] = f.config.name;
  if (!f.config.phases.empty()) {  // the table flown (--phases, `tern phases` between flights)
    YAML::Node ph;
    for (const auto& [phase, instance] : f.config.phases) ph[std::string(msg::phase_name(phase))] = instance;
    ph.SetStyle(YAML::EmitterStyle::Flow);
    root["phases"] = ph;
  }
  if (f.config.fallback) root["fallback"] = *f.config.fallback;
  root["seed"] = f.seed;
  root["duration"] = f.duration_s;
  for (const auto& inst : f.instances) {
    if (inst->builtin) {
      YAML::Node pm;
      for (const auto* p : inst->plugin->params()) pm[p->name()] = to_yaml(p->value());
      if (pm.size() > 0) root[inst->cfg.name] = pm;  // phase_machine:, metrics: (replay has none)
      continue;
    }
    YAML::Node entry = root["plugins"][inst->cfg.index];
    entry.remove("param_file");
    YAML::Node params;
    for (const auto* p : inst->plugin->params()) params[p->name()] = to_yaml(p->value());
    entry["params"] = params;
    entry["library"] = inst->info.path.string();
  }
  YAML::Emitter e;
  e << root;
  std::string head = "# resolved from " + f.config.file.string() + "\n";
  if (!f.config.overrides.empty()) head += fmt::format("# with {}\n", fmt::join(f.config.overrides, " "));
  return head + e.c_str() + "\n";
}

const std::string& ResolvedConfig::text(const FlightFacts& f) {
  std::string inputs = inputs_but_seed(f);
  if (inputs == inputs_ && seed_length_ > 0) {
    const std::string seed = std::to_string(f.seed);
    text_.replace(seed_at_, seed_length_, seed);
    seed_length_ = seed.size();
    return text_;
  }
  text_ = resolved_config_yaml(f);
  inputs_ = std::move(inputs);
  // the top-level key is the only "seed: " at the start of a line (nested keys are indented)
  const std::string line = "\nseed: " + std::to_string(f.seed) + "\n";
  const std::size_t at = text_.find(line);
  const bool unique = at != std::string::npos && text_.find("\nseed: ", at + 1) == std::string::npos;
  seed_at_ = unique ? at + 7 : 0;
  seed_length_ = unique ? line.size() - 8 : 0;
  return text_;
}

}  // namespace tern::core
