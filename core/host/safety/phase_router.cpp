#include "safety/phase_router.hpp"

#include <cmath>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include "config/error.hpp"
#include "safety/phase_machine.hpp"

namespace tern::core {

PhaseRouter::PhaseRouter(const std::vector<std::unique_ptr<Instance>>& instances, PortGraph& graph, std::shared_ptr<spdlog::logger> log)
    : instances_(instances), graph_(graph), log_(std::move(log)) {
  recovery_out_.set_identity("actuators", "the state-loss recovery's command");
}

// ---- the table --------------------------------------------------------------------------------

std::optional<std::size_t> PhaseRouter::index_of(const std::string& instance) const {
  for (std::size_t i = 0; i < instances_.size(); ++i)
    if (instances_[i]->cfg.name == instance) return i;
  return std::nullopt;
}

// `at`: where the table names `instance` ("file:line:col: phases.cruise", or the option that set it).
void PhaseRouter::require_controller(const std::string& instance, const std::string& at) const {
  const auto idx = index_of(instance);
  if (!idx) return;  // not loaded: a replay keeps the estimators only
  const Instance& inst = *instances_[*idx];
  if (inst.info.kind == PluginKind::controller) return;
  std::vector<std::string> controllers;
  for (const auto& other : instances_)
    if (other->info.kind == PluginKind::controller) controllers.push_back(other->cfg.name);
  throw ConfigError(fmt::format("{}: '{}' is not a controller: it runs plugin '{}' ({}); {}", at, instance, inst.info.name,
                                kind_name(inst.info.kind),
                                controllers.empty() ? std::string("this mission has no controller instance")
                                                    : fmt::format("name one of: {}", fmt::join(controllers, ", "))));
}

namespace {
// Where the config names `instance` under `field` (located only if it still says so: a table set
// between flights or on the command line has no place in the file).
std::string location(const MissionConfig& config, const std::string& option, const std::string& field, const YAML::Node& node,
                     const std::string& instance) {
  if (!option.empty()) return option + ": " + field;
  const bool in_file = node && node.IsScalar() && node.Scalar() == instance;
  return (in_file ? where(config.file, node) : "") + field;
}
}  // namespace

void PhaseRouter::assign(const MissionConfig& config, PhaseMachine* phase_machine) {
  const YAML::Node phases_node = config.root["phases"];
  for (const auto& [phase, name] : config.phases) {
    const std::string key(msg::phase_name(phase));
    require_controller(name, location(config, config.phases_option, "phases." + key,
                                      phases_node && phases_node.IsMap() ? phases_node[key] : YAML::Node(), name));
  }
  if (config.fallback)
    require_controller(*config.fallback, location(config, config.fallback_option, "fallback", config.root["fallback"], *config.fallback));
  phase_machine_ = phase_machine;
  table_ = config.phases;
  std::set<std::string> routed;
  for (const auto& [phase, name] : table_) routed.insert(name);
  if (config.fallback) routed.insert(*config.fallback);
  for (const auto& inst : instances_) {
    inst->routed = !inst->builtin && routed.count(inst->cfg.name) > 0;
    inst->idle = !inst->builtin && !inst->routed && !table_.empty() && inst->info.kind == PluginKind::controller;
  }
  fallback_.reset();
  active_.reset();
  if (table_.empty()) return;
  const auto cruise = table_.find(msg::Phase::cruise);
  if (config.fallback)
    fallback_ = index_of(*config.fallback);
  else if (cruise != table_.end())
    fallback_ = index_of(cruise->second);
  if (const auto takeoff = table_.find(msg::Phase::takeoff); takeoff != table_.end()) active_ = index_of(takeoff->second);
}

bool PhaseRouter::may_step(std::size_t idx) const {
  const Instance& inst = *instances_[idx];
  return !inst.idle && (!inst.routed || (active_ && *active_ == idx));
}

// ---- a flight ---------------------------------------------------------------------------------

void PhaseRouter::prepare_flight() {
  handovers_.clear();
  fallback_engaged_ = hand_back_ = false;
  safety_logged_.clear();
  monitor_.restart();
  last_good_ = msg::Actuators{};
  recovery_out_.clear();  // a new flight has heard nothing of the last one's recovery
}

void PhaseRouter::start_flight() {
  imu_ = graph_.writer_of<msg::Imu>("imu");
  imu_seen_ = imu_ ? imu_->sequence() : 0;
  recovery_.restart();
  if (phase_machine_) phase_seen_ = phase_machine_->outputs().front()->sequence();
  if (phase_machine_ && phase_machine_->phase() == msg::Phase::preflight)
    route_none(0, "preflight: on the ground until the arming checks pass");
  actuators_ = find_actuators();
  actuators_seen_ = actuators_ ? actuators_->sequence() : 0;
}

PhaseRouter::Cause PhaseRouter::fallback_reason(const Instance& c, const std::string& step_error, Nanos now) {
  if (std::string failed = c.failure(); !failed.empty()) return {failed};  // an isolated child died or hung
  if (!step_error.empty()) return {fmt::format("{}.step threw: {}", c.cfg.name, step_error)};
  const auto* a = actuators_ ? static_cast<const msg::Actuators*>(actuators_->data()) : nullptr;
  if (a != nullptr && !(std::isfinite(a->delta_a) && std::isfinite(a->delta_e) && std::isfinite(a->delta_r) && std::isfinite(a->delta_t) &&
                        std::isfinite(a->brake)))
    return {fmt::format("{} commanded a non-finite actuator value (delta_a {}, delta_e {}, delta_r {}, delta_t {}, brake {})", c.cfg.name,
                        a->delta_a, a->delta_e, a->delta_r, a->delta_t, a->brake)};
  if (a != nullptr && phase_machine_) {
    const double lim = phase_machine_->max_deflection();
    if (std::fabs(a->delta_a) > lim || std::fabs(a->delta_e) > lim || std::fabs(a->delta_r) > lim || a->delta_t < 0.0 || a->delta_t > 1.0 ||
        a->brake < 0.0 || a->brake > 1.0)
      return {
          fmt::format("{} commanded outside the actuator limits (delta_a {:.3f}, delta_e {:.3f}, delta_r {:.3f} rad: max {} rad; "
                      "delta_t {:.3f}, brake {:.3f}: 0..1)",
                      c.cfg.name, a->delta_a, a->delta_e, a->delta_r, lim, a->delta_t, a->brake)};
  }
  if (recovery_.active()) return {};  // the estimate is invalid: nothing to judge the controller by
  if (std::string why = safety_cause(now); !why.empty()) return {fmt::format("{}: safety monitor: {}", c.cfg.name, why), true};
  return {};
}

std::string PhaseRouter::safety_cause(Nanos now) {
  if (!phase_machine_ || fallback_engaged_) return "";
  SafetyInputs in;
  in.now = now;
  in.phase = phase_machine_->phase();
  in.published = !actuators_ || actuators_->sequence() != actuators_seen_;  // (no actuators output: nothing to miss)
  if (actuators_) actuators_seen_ = actuators_->sequence();
  in.actuators = actuators_ && actuators_->sequence() > 0 ? static_cast<const msg::Actuators*>(actuators_->data()) : nullptr;
  in.state = phase_machine_->estimate();
  in.h_c = phase_machine_->commanded_altitude();
  in.Va_c = phase_machine_->commanded_airspeed();
  monitor_.set_limits(phase_machine_->safety_limits());  // each step: live parameter edits apply
  return monitor_.check(in);
}

void PhaseRouter::log_unanswered(Nanos now, const std::string& why) {
  const std::string kind = why.substr(0, why.find(':', why.find("monitor: ") + 9));
  if (kind == safety_logged_) return;
  safety_logged_ = kind;
  log_->warn("t={:.3f} s: {} (no other controller to hand over to: it flies on)", to_seconds(now), why);
}

std::string PhaseRouter::after_controller_step(Nanos now, std::size_t idx, const std::string& step_error, const StepFn& step) {
  update_recovery(now);
  const Cause cause = fallback_reason(*instances_[idx], step_error, now);
  const bool no_fallback = !fallback_ || fallback_engaged_ || *fallback_ == idx;
  if (cause.why.empty() || (cause.safety && no_fallback)) {
    if (!cause.why.empty()) log_unanswered(now, cause.why);
    if (actuators_ && actuators_->sequence() > 0 && !recovery_.active()) {
      last_good_ = *static_cast<const msg::Actuators*>(actuators_->data());
      recovery_.observe(now, last_good_, phase_machine_ ? phase_machine_->estimate() : nullptr);
    }
    return "";
  }
  if (no_fallback) return "error: " + cause.why + " (no fallback controller left)";
  engage_fallback(now, cause.why, cause.safety);
  Instance& fb = *instances_[*fallback_];
  if (const std::string err = step(fb); !err.empty()) return fmt::format("error: fallback {}.step threw: {}", fb.cfg.name, err);
  return "";
}

// ---- the state-loss recovery --------------------------------------------------------------------

void PhaseRouter::update_recovery(Nanos now) {
  if (!phase_machine_) return;
  const msg::State* s = phase_machine_->estimate();
  const msg::Phase p = phase_machine_->phase();
  const bool lost =
      phase_machine_->state_loss_recovery() && s != nullptr && !s->valid && (p == msg::Phase::climb || p == msg::Phase::cruise);
  const std::string active = active_ ? instances_[*active_]->cfg.name : "(none)";
  const bool starting = lost && !recovery_.active();
  if (starting) {
    recovery_.set_gains(phase_machine_->recovery_gains());
    recovery_.begin(now);
    log_->warn("t={:.3f} s: controller {} -> state_loss_recovery: the estimate is invalid (status {})", to_seconds(now), active,
               static_cast<int>(s->status));
    handovers_.push_back({now, active, "state_loss_recovery", "the estimate is invalid"});
  } else if (!lost && recovery_.active()) {
    recovery_.end();
    log_->warn("t={:.3f} s: controller state_loss_recovery -> {}: the estimate is valid again", to_seconds(now), active);
    handovers_.push_back({now, "state_loss_recovery", active, "the estimate is valid again"});
    rebind();
    try {
      if (active_) instances_[*active_]->plugin->take_over(recovery_out_.last());
    } catch (const std::exception& e) {
      log_->error("{}.take_over threw: {}", active, e.what());
    }
    return;
  }
  if (!recovery_.active()) return;
  const bool fresh = imu_ != nullptr && imu_->sequence() != imu_seen_;
  if (imu_ != nullptr) imu_seen_ = imu_->sequence();
  recovery_out_.publish(recovery_.command(now, fresh ? static_cast<const msg::Imu*>(imu_->data()) : nullptr));
  if (starting) rebind();  // (published first: the readers never see an empty command)
}

void PhaseRouter::rebind() {
  graph_.route(active_);
  if (recovery_.active()) graph_.route_topic("actuators", &recovery_out_);
}

void PhaseRouter::follow_phase(Nanos now) {
  const OutputBase* po = phase_machine_->outputs().front();
  if (po->sequence() == phase_seen_) return;
  phase_seen_ = po->sequence();
  if (fallback_engaged_ && !hand_back_) return;
  const msg::Phase p = phase_machine_->phase();
  auto it = table_.find(p);
  if (it == table_.end()) it = table_.find(msg::Phase::cruise);
  if (fallback_engaged_) {  // hand_back_: the safety engagement ends with this phase change
    fallback_engaged_ = hand_back_ = false;
    log_->info("t={:.3f} s: safety_hand_back: phase {}, the phase's controller flies again", to_seconds(now), msg::phase_name(p));
  }
  if (phase_machine_->disarmed())
    route_none(now, "disarmed: waiting for the FCU to be armed and error-free");
  else if (p == msg::Phase::preflight)
    route_none(now, "preflight: on the ground until the arming checks pass");
  else if (p == msg::Phase::stopped)
    route_none(now, "stopped: landed and at rest, motor off");
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
  rebind();
  actuators_ = find_actuators();
  actuators_seen_ = actuators_ ? actuators_->sequence() : 0;
  monitor_.restart();
  try {
    target.plugin->take_over(last_good_);
  } catch (const std::exception& e) {
    if (!from_failure && fallback_ && idx != *fallback_)
      engage_fallback(now, fmt::format("{}.take_over threw: {}", target.cfg.name, e.what()));
    else
      log_->error("{}.take_over threw: {}", target.cfg.name, e.what());
  }
}

void PhaseRouter::route_none(Nanos now, const std::string& reason) {
  if (!active_) return;
  log_->info("t={:.3f} s: controller {} -> (none): {}", to_seconds(now), instances_[*active_]->cfg.name, reason);
  handovers_.push_back({now, instances_[*active_]->cfg.name, "(none)", reason});
  active_.reset();
  rebind();
  actuators_ = nullptr;
}

void PhaseRouter::engage_fallback(Nanos now, const std::string& why, bool may_hand_back) {
  fallback_engaged_ = true;
  hand_back_ = may_hand_back && phase_machine_ && phase_machine_->safety_hand_back();
  route_to(*fallback_, now, (hand_back_ ? "fallback until the next phase change: " : "fallback for the rest of the flight: ") + why, true);
}

const OutputBase* PhaseRouter::find_actuators() const {
  if (!active_) return nullptr;
  // Its msg::Actuators output: on `actuators`, or remapped (a signal generator adds an excitation
  // to it and publishes `actuators`): the checks and the monitor watch the controller's own command.
  const OutputBase* remapped = nullptr;
  for (auto* o : instances_[*active_]->plugin->outputs())
    if (o->type().fingerprint == reflect::fingerprint<msg::Actuators>()) {
      if (o->topic() == "actuators") return o;
      if (!remapped) remapped = o;
    }
  return remapped;
}

}  // namespace tern::core
