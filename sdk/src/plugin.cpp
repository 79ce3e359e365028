#include "tern/plugin.hpp"

#include <spdlog/spdlog.h>

namespace tern {

PortBase::~PortBase() = default;
OutputBase::~OutputBase() = default;
InputBase::~InputBase() = default;
Context::~Context() = default;

void Context::end_flight(const std::string& reason, const std::string& detail) {
  if (auto l = logger()) l->warn("{}: end of flight ({}) asked outside a flight, ignored: {}", instance_name(), reason, detail);
}

Plugin::Plugin() = default;
Plugin::~Plugin() = default;

Context& Plugin::context() const {
  if (ctx_ == nullptr) throw std::logic_error("tern::Plugin used before the host attached a context");
  return *ctx_;
}

spdlog::logger& Plugin::log() const {
  if (ctx_ != nullptr) {
    if (auto l = ctx_->logger()) return *l;
  }
  return *spdlog::default_logger_raw();
}

namespace {
template <class V>
auto find_by_name(const V& v, std::string_view name) -> typename V::value_type {
  for (auto* p : v)
    if (p->name() == name) return p;
  return nullptr;
}
}  // namespace

InputBase* Plugin::find_input(std::string_view name) const { return find_by_name(inputs_, name); }
OutputBase* Plugin::find_output(std::string_view name) const { return find_by_name(outputs_, name); }
ParamBase* Plugin::find_param(std::string_view name) const { return find_by_name(params_, name); }

void Plugin::add_input(InputBase& port, std::string name, std::string description) {
  if (find_input(name) != nullptr || find_output(name) != nullptr) throw std::logic_error("plugin declares port '" + name + "' twice");
  port.set_identity(std::move(name), std::move(description));
  inputs_.push_back(&port);
}

void Plugin::add_output(OutputBase& port, std::string name, std::string description) {
  if (find_input(name) != nullptr || find_output(name) != nullptr) throw std::logic_error("plugin declares port '" + name + "' twice");
  port.set_identity(std::move(name), std::move(description));
  outputs_.push_back(&port);
}

void Plugin::add_param(ParamBase& param, std::string name, ParamValue default_value, ParamSpec spec) {
  if (find_param(name) != nullptr) throw std::logic_error("plugin declares parameter '" + name + "' twice");
  const std::string qualified = (ctx_ != nullptr ? ctx_->instance_name() + "." : std::string()) + name;
  param.set_identity(name, qualified, std::move(spec), default_value);
  // The default itself must satisfy the declared range: a plugin bug otherwise.
  (void)param.validate(default_value);
  params_.push_back(&param);
  if (ctx_ != nullptr) {
    if (auto v = ctx_->configured_value(name, param.spec())) param.set(*v);
  }
}

}  // namespace tern
