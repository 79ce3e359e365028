#include "graph/instances.hpp"

#include <map>
#include <set>
#include <utility>

#include <spdlog/spdlog.h>

#include "config/error.hpp"
#include "tern/random.hpp"

namespace tern::core {

// ---- the context each instance sees ---------------------------------------------------------

class InstanceContext final : public Context {
 public:
  InstanceContext(const MissionConfig& config, const InstanceConfig& cfg, std::uint64_t seed, std::shared_ptr<spdlog::logger> log,
                  bool describing, bool replaying)
      : config_(config), cfg_(cfg), seed_(seed), log_(std::move(log)), describing_(describing), replaying_(replaying) {}

  const std::string& instance_name() const override { return cfg_.name; }
  std::optional<ParamValue> configured_value(const std::string& param, const ParamSpec& spec) const override {
    auto it = cfg_.params.find(param);
    last_param_ = param;
    if (it == cfg_.params.end()) return std::nullopt;
    used_.insert(param);
    ParamValue v = to_param_value(it->second.node, it->second.file, it->second.field);
    if (spec.is_path && std::holds_alternative<std::string>(v)) {
      fs::path p(std::get<std::string>(v));
      if (!p.empty() && p.is_relative()) v = (it->second.file.parent_path() / p).lexically_normal().string();  // "": none
    }
    return v;
  }
  std::uint64_t seed() const override { return seed_; }
  std::shared_ptr<spdlog::logger> logger() const override { return log_; }
  std::filesystem::path config_dir() const override { return config_.dir; }
  const YAML::Node& mission() const override { return config_.mission; }
  std::filesystem::path aircraft_file() const override { return config_.aircraft; }
  std::vector<std::string> vehicles() const override { return config_.vehicles; }
  bool describing() const override { return describing_; }
  bool replaying() const override { return replaying_; }
  void end_flight(const std::string& reason, const std::string& detail) override {
    if (!end_) end_ = EndRequest{reason, detail};
  }

  /// The instance's seed for the flights from now on (reseed_instance).
  void set_seed(std::uint64_t seed) { seed_ = seed; }
  std::optional<EndRequest> take_end_request() { return std::exchange(end_, std::nullopt); }
  const std::string& last_param() const { return last_param_; }
  const std::set<std::string>& used() const { return used_; }

 private:
  const MissionConfig& config_;
  const InstanceConfig& cfg_;
  std::uint64_t seed_;
  std::shared_ptr<spdlog::logger> log_;
  bool describing_, replaying_;
  mutable std::string last_param_;
  mutable std::set<std::string> used_;
  std::optional<EndRequest> end_;
};

Instance::Instance() = default;
Instance::~Instance() = default;

std::optional<EndRequest> Instance::take_end_request() { return ctx ? ctx->take_end_request() : std::nullopt; }

Context& Instance::context() { return *ctx; }

void Instance::drop_plugin() {
  isolated = nullptr;
  plugin.reset();
  ctx.reset();
}

// ---- configure ------------------------------------------------------------------------------

namespace {

void run_configure(Instance& inst, const fs::path& f, const std::string& field) {
  try {
    inst.plugin->configure();
  } catch (const ParamError& e) {
    // The parameter the message names ("parameter 'inst.p': ..."), else the last one declared.
    std::string p = inst.ctx->last_param();
    const std::string what = e.what(), named = "parameter '" + inst.cfg.name + ".";
    if (const auto at = what.find(named); at != std::string::npos) {
      const auto from = at + named.size(), to = what.find('\'', from);
      if (to != std::string::npos && inst.cfg.params.count(what.substr(from, to - from))) p = what.substr(from, to - from);
    }
    auto it = inst.cfg.params.find(p);
    if (it != inst.cfg.params.end()) throw ConfigError(it->second.location() + ": " + e.what());
    throw ConfigError(where(f, inst.cfg.node) + field + " (" + inst.cfg.name + "): " + e.what());
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw ConfigError(where(f, inst.cfg.node) + field + " (" + inst.cfg.name + "): configure failed: " + e.what());
  }
}

// parameters the config sets but the plugin does not have
void check_unknown_params(const Instance& inst, spdlog::logger& log) {
  std::vector<std::string> declared;
  for (const auto* p : inst.plugin->params()) declared.push_back(p->name());
  for (const auto& [name, setting] : inst.cfg.params) {
    if (inst.ctx->used().count(name)) continue;
    const std::string msg = "unknown parameter '" + name + "' of plugin '" + inst.info.name + "'" + did_you_mean(name, declared);
    if (setting.strict) throw ConfigError(setting.location() + ": " + msg);
    log.warn("{}: {} (ignored: shared ROS 2 parameter file)", setting.location(), msg);
  }
}

void apply_remaps_and_trigger(Instance& inst, const fs::path& f, const std::string& field) {
  for (const auto& [port, topic] : inst.cfg.remap) {
    PortBase* p = inst.plugin->find_input(port);
    if (p == nullptr) p = inst.plugin->find_output(port);
    if (p == nullptr) {
      std::vector<std::string> ports;
      for (auto* i : inst.plugin->inputs()) ports.push_back(i->name());
      for (auto* o : inst.plugin->outputs()) ports.push_back(o->name());
      throw ConfigError(where(f, inst.cfg.node["remap"]) + field + ".remap: plugin '" + inst.info.name + "' has no port '" + port + "'" +
                        did_you_mean(port, ports));
    }
    p->set_topic(topic);
  }
  if (inst.cfg.trigger) {
    inst.trigger = inst.plugin->find_input(*inst.cfg.trigger);
    if (inst.trigger == nullptr) {
      std::vector<std::string> ports;
      for (auto* i : inst.plugin->inputs()) ports.push_back(i->name());
      throw ConfigError(where(f, inst.builtin ? inst.cfg.node : inst.cfg.node["trigger"]) + field + ".trigger: plugin '" + inst.info.name +
                        "' has no input port '" + *inst.cfg.trigger + "'" + did_you_mean(*inst.cfg.trigger, ports));
    }
  }
}

}  // namespace

void configure_instance(Instance& inst, const InstanceSetup& setup) {
  const std::uint64_t iseed = derive_seed(setup.seed, inst.cfg.name);
  auto log = std::make_shared<spdlog::logger>(inst.cfg.name, setup.sink);
  log->set_level(spdlog::level::info);
  inst.ctx = std::make_unique<InstanceContext>(setup.config, inst.cfg, iseed, log, setup.describing, setup.replaying);
  inst.plugin->attach(inst.ctx.get());
  const std::string field = inst.builtin ? inst.cfg.name : inst.cfg.label();
  run_configure(inst, setup.config.file, field);
  check_unknown_params(inst, setup.log);
  apply_remaps_and_trigger(inst, setup.config.file, field);
}

void reseed_instance(Instance& inst, std::uint64_t flight_seed) { inst.ctx->set_seed(derive_seed(flight_seed, inst.cfg.name)); }

}  // namespace tern::core
