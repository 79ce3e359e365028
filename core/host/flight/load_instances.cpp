// core/host/flight/load_instances.cpp: a mission's instances loaded (load_instances.hpp).
#include "flight/load_instances.hpp"

#include <algorithm>
#include <map>
#include <utility>

#include "config/error.hpp"
#include "record/metrics.hpp"
#include "runners/external_plugin.hpp"
#include "runners/isolated_plugin.hpp"
#include "safety/phase_machine.hpp"

namespace tern::core {

// Instance's, here beside isolate_instance(), which sets `isolated`.
std::string Instance::failure() const { return isolated ? isolated->failure() : std::string(); }

void isolate_instance(Instance& inst, const InstanceSetup& setup) {
  const IsolationSpec spec{
      setup.config.file,      inst.cfg.name, inst.lib->info().path, setup.seed, static_cast<Nanos>(setup.config.watchdog.hard_ms * 1e6),
      setup.config.fleet_part};
  try {
    auto proxy = std::make_unique<IsolatedPlugin>(std::move(inst.plugin), inst.context(), spec);
    inst.isolated = proxy.get();
    inst.plugin = std::move(proxy);
  } catch (const ConfigError& e) {
    throw ConfigError(where(setup.config.file, inst.cfg.node["isolate"]) + inst.cfg.label() + ".isolate: " + e.what());
  }
}

// ---- load -----------------------------------------------------------------------------------

namespace {

/// Hz: the replay plays at every tick of the host's base rate: the config's base_rate, else its
/// fastest instance's (the base rate resolve_rates takes then), else 400 Hz (no instance has a rate).
/// A fixed 400 Hz could not be served by the base rate of a flight flown at 1000 Hz.
double replay_rate(const MissionConfig& config) {
  if (config.base_rate) return *config.base_rate;
  double fastest = 0.0;
  for (const auto& ic : config.plugins)
    if (ic.rate) fastest = std::max(fastest, *ic.rate);
  return fastest > 0.0 ? fastest : 400.0;
}

std::unique_ptr<Instance> replay_instance(const InstanceSetup& setup, const RecordedSourceFactory& make, RecordedSource*& replay) {
  const MissionConfig& config = setup.config;
  auto inst = std::make_unique<Instance>();
  inst->cfg.index = config.plugins.size() + 2;
  inst->cfg.name = "replay";
  inst->cfg.plugin = "replay (built in)";
  inst->cfg.rate = replay_rate(config);
  inst->builtin = true;
  inst->info = PluginInfo{"replay", PluginKind::io, "recorded sensor and truth topics of a flight log", {}, {}};
  auto rp = make();
  replay = rp.get();
  inst->plugin = std::move(rp);
  configure_instance(*inst, setup);
  return inst;
}

// `plugin: external`: ports that are DDS topics (external_plugin.hpp), no library.
std::unique_ptr<Instance> external_instance(const InstanceSetup& setup, const InstanceConfig& ic) {
  const fs::path& f = setup.config.file;
  const std::string field = ic.label();
  ExternalSpec spec = parse_external_spec(ic, f);
  spec.lockstep = !setup.realtime;
  if (!external_link_factory())
    throw ConfigError(where(f, ic.node["plugin"]) + field +
                      ".plugin: 'external' needs tern built with DDS (libfastrtps-dev and "
                      "fastddsgen: make deps), and this tern was built without");
  if (ic.isolate) throw ConfigError(where(f, ic.node["isolate"]) + field + ".isolate: an external module runs in its own process already");
  auto inst = std::make_unique<Instance>();
  inst->cfg = ic;
  inst->source = "external";
  inst->info = PluginInfo{"external", spec.kind, "a module in another process, ports on DDS topics", {}};
  std::unique_ptr<ExternalLink> link;
  if (!setup.describing) {
    try {
      link = external_link_factory()(spec, setup.config);
    } catch (const std::exception& e) {
      throw ConfigError(where(f, ic.node["plugin"]) + field + " (" + ic.name + "): external module: " + e.what());
    }
  }
  inst->plugin = std::make_unique<ExternalPlugin>(std::move(spec), std::move(link));
  configure_instance(*inst, setup);
  return inst;
}

// The instances of `plugins:`; nullptr for those a replay leaves out (not estimators).
std::unique_ptr<Instance> config_instance(const InstanceSetup& setup, const InstanceConfig& ic, bool replaying,
                                          const std::vector<fs::path>& search, std::map<fs::path, std::shared_ptr<PluginLibrary>>& libs) {
  const fs::path& f = setup.config.file;
  const std::string field = ic.label();
  if (is_external(ic)) return replaying ? nullptr : external_instance(setup, ic);
  auto inst = std::make_unique<Instance>();
  inst->cfg = ic;
  fs::path path;
  try {
    path = find_plugin(ic.plugin, search);
    auto it = libs.find(path);
    if (it == libs.end()) it = libs.emplace(path, open_plugin(path)).first;
    inst->lib = it->second;
  } catch (const ConfigError& e) {
    throw ConfigError(where(f, ic.node["plugin"]) + field + ".plugin: " + e.what());
  }
  inst->info = inst->lib->info();
  inst->source = path;
  if (ic.plugin.find('/') == std::string::npos && inst->info.name != ic.plugin)
    throw ConfigError(where(f, ic.node["plugin"]) + field + ".plugin: " + path.string() + " registers plugin '" + inst->info.name +
                      "', not '" + ic.plugin + "'");
  if (replaying && inst->info.kind != PluginKind::estimator) return nullptr;
  if ((inst->info.kind == PluginKind::coordination) != !setup.config.vehicles.empty())
    throw ConfigError(where(f, ic.node["plugin"]) + field + ".plugin: '" + inst->info.name + "' is " +
                      (setup.config.vehicles.empty()
                           ? "a coordination plugin: it belongs in a multi-vehicle mission's coordination: list"
                           : std::string("a ") + kind_name(inst->info.kind) +
                                 " plugin: coordination: takes coordination plugins (a vehicle's own go in plugins:)"));
  inst->plugin = inst->lib->create();
  configure_instance(*inst, setup);
  if (ic.isolate && !setup.describing) isolate_instance(*inst, setup);
  return inst;
}

// A built-in instance: reserved name, triggered by `state`, parameters from its own config section.
void add_builtin(const InstanceSetup& setup, std::vector<std::unique_ptr<Instance>>& list, std::size_t index, const std::string& name,
                 const std::string& description, const std::map<std::string, ParamSetting>& params, std::unique_ptr<Plugin> plugin) {
  for (const auto& other : list)
    if (other->cfg.name == name)
      throw ConfigError(where(setup.config.file, other->cfg.node) + "instance name '" + name + "' is reserved for " + description);
  auto inst = std::make_unique<Instance>();
  inst->cfg.index = index;
  inst->cfg.name = name;
  inst->cfg.plugin = name + " (built in)";
  inst->cfg.trigger = "state";
  inst->cfg.params = params;
  if (setup.config.root[name]) inst->cfg.node = setup.config.root[name];
  inst->builtin = true;
  inst->info = PluginInfo{name, PluginKind::generic, description, {}, {}};
  inst->plugin = std::move(plugin);
  configure_instance(*inst, setup);
  list.push_back(std::move(inst));
}

}  // namespace

LoadedInstances load_instances(const InstanceSetup& setup, const RecordedSourceFactory& replay) {
  const MissionConfig& config = setup.config;
  LoadedInstances out;
  if (replay) out.list.push_back(replay_instance(setup, replay, out.replay));
  const auto search = plugin_search_path(config.plugin_path);
  std::map<fs::path, std::shared_ptr<PluginLibrary>> libs;
  for (const auto& ic : config.plugins)
    if (auto inst = config_instance(setup, ic, static_cast<bool>(replay), search, libs)) out.list.push_back(std::move(inst));
  if (!config.phases.empty()) {
    auto pm = std::make_unique<PhaseMachine>();
    out.phase_machine = pm.get();
    out.phase_machine_index = out.list.size();
    add_builtin(setup, out.list, config.plugins.size(), "phase_machine", "the host's flight-phase machine", config.phase_params,
                std::move(pm));
  }
  bool has_state = false;
  for (const auto& other : out.list)
    for (const auto* o : other->plugin->outputs()) has_state = has_state || o->topic() == "state";
  if (has_state) {
    auto m = std::make_unique<FlightMetrics>();
    out.metrics = m.get();
    add_builtin(setup, out.list, config.plugins.size() + 1, "metrics", "the host's flight metrics (estimation and tracking RMSE)",
                config.metrics_params, std::move(m));
  }
  return out;
}

}  // namespace tern::core
