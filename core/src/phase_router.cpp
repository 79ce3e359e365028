#include "phase_router.hpp"

#include <cmath>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include "error.hpp"
#include "phase_machine.hpp"

namespace tern::core {

PhaseRouter::PhaseRouter(const std::vector<std::unique_ptr<Instance>>& instances, PortGraph& graph,
                         std::shared_ptr<spdlog::logger> log)
    : instances_(instances), graph_(graph), log_(std::move(log)) {}

// ---- the table --------------------------------------------------------------------------------

std::optional<std::size_t> PhaseRouter::index_of(const std::string& instance) const {
  for (std::size_t i = 0; i < instances_.size(); ++i)
    if (instances_[i]->cfg.name == instance) return i;
  return std::nullopt;
}

// `node`: where the config names `instance` (located only if it still says so: a table set
// between flights has no place in the file).
void PhaseRouter::require_controller(const MissionConfig& config, const std::string& instance, const std::string& field,
                                     const YAML::Node& node) const {
  const auto idx = index_of(instance);
  if (!idx) return;  // not loaded: a replay keeps the estimators only
  const Instance& inst = *instances_[*idx];
  if (inst.info.kind == PluginKind::controller) return;
  std::vector<std::string> controllers;
  for (const auto& other : instances_)
    if (other->info.kind == PluginKind::controller) controllers.push_back(other->cfg.name);
  const std::string at = node && node.IsScalar() && node.Scalar() == instance ? where(config.file, node) : "";
  throw ConfigError(fmt::format("{}{}: '{}' is not a controller: it runs plugin '{}' ({}); {}", at, field, instance, inst.info.name,
                                kind_name(inst.info.kind),
                                controllers.empty() ? std::string("this mission has no controller instance")
                                                    : fmt::format("name one of: {}", fmt::join(controllers, ", "))));
}

void PhaseRouter::assign(const MissionConfig& config, PhaseMachine* phase_machine) {
  const YAML::Node phases_node = config.root["phases"];
  for (const auto& [phase, name] : config.phases) {
    const std::string key(msg::phase_name(phase));
    require_controller(config, name, "phases." + key, phases_node && phases_node.IsMap() ? phases_node[key] : YAML::Node());
  }
  if (config.fallback) require_controller(config, *config.fallback, "fallback", config.root["fallback"]);
  phase_machine_ = phase_machine;
  table_ = config.phases;
  std::set<std::string> routed;
  for (const auto& [phase, name] : table_) routed.insert(name);
  if (config.fallback) routed.insert(*config.fallback);
  for (const auto& inst : instances_) inst->routed = !inst->builtin && routed.count(inst->cfg.name) > 0;
  fallback_.reset();
  active_.reset();
  if (table_.empty()) return;
  const auto cruise = table_.find(msg::Phase::cruise);
  if (config.fallback) fallback_ = index_of(*config.fallback);
  else if (cruise != table_.end()) fallback_ = index_of(cruise->second);
  if (const auto takeoff = table_.find(msg::Phase::takeoff); takeoff != table_.end()) active_ = index_of(takeoff->second);
}

bool PhaseRouter::may_step(std::size_t idx) const { return !instances_[idx]->routed || (active_ && *active_ == idx); }

// ---- a flight ---------------------------------------------------------------------------------

void PhaseRouter::prepare_flight() {
  handovers_.clear();
  fallback_engaged_ = false;
  last_good_ = msg::Actuators{};
}

void PhaseRouter::start_flight() {
  if (phase_machine_) phase_seen_ = phase_machine_->outputs().front()->sequence();
  if (phase_machine_ && phase_machine_->phase() == msg::Phase::preflight)
    route_none(0, "preflight: on the ground until the arming checks pass");
  actuators_ = find_actuators();
}

std::string PhaseRouter::fallback_reason(const Instance& c, const std::string& step_error) const {
  if (!step_error.empty()) return fmt::format("{}.step threw: {}", c.cfg.name, step_error);
  const auto* a = actuators_ ? static_cast<const msg::Actuators*>(actuators_->data()) : nullptr;
  if (a == nullptr) return "";
  if (!(std::isfinite(a->delta_a) && std::isfinite(a->delta_e) && std::isfinite(a->delta_r) && std::isfinite(a->delta_t)))
    return fmt::format("{} commanded a non-finite actuator value (delta_a {}, delta_e {}, delta_r {}, delta_t {})", c.cfg.name,
                       a->delta_a, a->delta_e, a->delta_r, a->delta_t);
  if (phase_machine_) {
    const double lim = phase_machine_->max_deflection();
    if (std::fabs(a->delta_a) > lim || std::fabs(a->delta_e) > lim || std::fabs(a->delta_r) > lim || a->delta_t < 0.0 || a->delta_t > 1.0)
      return fmt::format("{} commanded outside the actuator limits (delta_a {:.3f}, delta_e {:.3f}, delta_r {:.3f} rad: max {} rad; "
                         "delta_t {:.3f}: 0..1)", c.cfg.name, a->delta_a, a->delta_e, a->delta_r, lim, a->delta_t);
  }
  return "";
}

std::string PhaseRouter::after_controller_step(Nanos now, std::size_t idx, const std::string& step_error, const StepFn& step) {
  const std::string why = fallback_reason(*instances_[idx], step_error);
  if (why.empty()) {
    if (actuators_) last_good_ = *static_cast<const msg::Actuators*>(actuators_->data());
    return "";
  }
  if (!fallback_ || fallback_engaged_ || *fallback_ == idx) return "error: " + why + " (no fallback controller left)";
  engage_fallback(now, why);
  Instance& fb = *instances_[*fallback_];
  if (const std::string err = step(fb); !err.empty()) return fmt::format("error: fallback {}.step threw: {}", fb.cfg.name, err);
  return "";
}

void PhaseRouter::follow_phase(Nanos now) {
  const OutputBase* po = phase_machine_->outputs().front();
  if (po->sequence() == phase_seen_) return;
  phase_seen_ = po->sequence();
  if (fallback_engaged_) return;
  const msg::Phase p = phase_machine_->phase();
  auto it = table_.find(p);
  if (it == table_.end()) it = table_.find(msg::Phase::cruise);
  if (phase_machine_->disarmed()) route_none(now, "disarmed: waiting for the FCU to be armed and error-free");
  else if (p == msg::Phase::preflight) route_none(now, "preflight: on the ground until the arming checks pass");
  else if (it != table_.end())
    if (const auto idx = index_of(it->second)) route_to(*idx, now, fmt::format("phase {}", msg::phase_name(p)), false);
}

// ---- handovers --------------------------------------------------------------------------------

void PhaseRouter::route_to(std::size_t idx, Nanos now, const std::string& reason, bool from_failure) {
  if (active_ && *active_ == idx) return;
  const std::string from = active_ ? instances_[*active_]->cfg.name : "(none)";
  Instance& target = *instances_[idx];
  log_->log(from_failure ? spdlog::level::warn : spdlog::level::info, "t={:.3f} s: controller {} -> {}: {}", to_seconds(now), from,
            target.cfg.name, reason);
  handovers_.push_back({now, from, target.cfg.name, reason});
  active_ = idx;
  graph_.route(active_);
  actuators_ = find_actuators();
  try {
    target.plugin->take_over(last_good_);
  } catch (const std::exception& e) {
    if (!from_failure && fallback_ && idx != *fallback_) engage_fallback(now, fmt::format("{}.take_over threw: {}", target.cfg.name, e.what()));
    else log_->error("{}.take_over threw: {}", target.cfg.name, e.what());
  }
}

void PhaseRouter::route_none(Nanos now, const std::string& reason) {
  if (!active_) return;
  log_->info("t={:.3f} s: controller {} -> (none): {}", to_seconds(now), instances_[*active_]->cfg.name, reason);
  handovers_.push_back({now, instances_[*active_]->cfg.name, "(none)", reason});
  active_.reset();
  graph_.route(active_);
  actuators_ = nullptr;
}

void PhaseRouter::engage_fallback(Nanos now, const std::string& why) {
  fallback_engaged_ = true;
  route_to(*fallback_, now, "fallback for the rest of the flight: " + why, true);
}

const OutputBase* PhaseRouter::find_actuators() const {
  if (!active_) return nullptr;
  for (auto* o : instances_[*active_]->plugin->outputs())
    if (o->topic() == "actuators" && o->type().fingerprint == reflect::fingerprint<msg::Actuators>()) return o;
  return nullptr;
}

}  // namespace tern::core
