#include "tern/testing/harness.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace tern::testing {

Harness::Harness(std::unique_ptr<Plugin> plugin, std::map<std::string, ParamValue> params, Options options)
    : params_(std::move(params)), options_(std::move(options)), plugin_(std::move(plugin)) {
  logger_ = spdlog::get("harness." + options_.instance);
  if (!logger_) logger_ = spdlog::stderr_color_mt("harness." + options_.instance);
  plugin_->attach(this);
  plugin_->configure();
  for (const auto& [name, value] : params_) {
    if (plugin_->find_param(name) == nullptr) throw ParamError("harness: plugin has no parameter '" + name + "'");
  }
}

Harness::~Harness() {
  // The plugin's inputs point at the feeders: unbind before anything is destroyed.
  for (auto* in : plugin_->inputs()) in->bind(nullptr);
  plugin_.reset();
}

std::optional<ParamValue> Harness::configured_value(const std::string& param, const ParamSpec& spec) const {
  auto it = params_.find(param);
  if (it == params_.end()) return std::nullopt;
  if (spec.is_path && std::holds_alternative<std::string>(it->second) && !options_.config_dir.empty()) {
    std::filesystem::path p(std::get<std::string>(it->second));
    if (!p.empty() && p.is_relative()) return ParamValue((options_.config_dir / p).lexically_normal().string());  // "": none
  }
  return it->second;
}

void Harness::start() {
  if (!started_) plugin_->start();
  started_ = true;
}

void Harness::step(Nanos now) {
  start();
  plugin_->step(now);
  for (auto* in : plugin_->inputs()) in->mark_seen();
}

void Harness::reset() {
  plugin_->reset();
  // as the host does between flights: every output empty, and the inputs hear nothing of the
  // last flight until a test publishes again
  for (OutputBase* out : plugin_->outputs()) out->clear();
  for (auto& [port, feeder] : feeders_) {
    feeder->clear();
    plugin_->find_input(port)->bind(feeder.get());
  }
}

void Harness::stop() {
  if (started_) plugin_->stop();
  started_ = false;
}

std::uint64_t Harness::published(const std::string& port) const {
  const OutputBase* out = plugin_->find_output(port);
  if (out == nullptr) throw std::logic_error("harness: plugin has no output port '" + port + "'");
  return out->sequence();
}

void Harness::set_param(const std::string& name, const ParamValue& value) {
  ParamBase* p = plugin_->find_param(name);
  if (p == nullptr) throw ParamError("harness: plugin has no parameter '" + name + "'");
  p->set(value);
}

void Harness::check_type(const PortBase& port, const MsgType& want) {
  if (port.type().fingerprint != want.fingerprint || port.type().name != want.name) {
    throw std::logic_error("harness: port '" + port.name() + "' carries " + std::string(port.type().name) + ", not " +
                           std::string(want.name));
  }
}

}  // namespace tern::testing
