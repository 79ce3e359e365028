#include "fleet/fleet.hpp"

#include <chrono>
#include <cstdio>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/sinks/stdout_color_sinks.h>

#include "config/error.hpp"
#include "graph/instances.hpp"
#include "record/flight_recorder.hpp"
#include "tern/msg/all.hpp"
#include "tern/random.hpp"

namespace tern::core {

namespace {

/// A host-side output of the standard message type named `type_name` (a mirror), or nullptr.
std::unique_ptr<OutputBase> make_output(std::string_view type_name) {
#define TERN_FLEET_OUTPUT_(T) \
  if (type_name == T::type_name) return std::make_unique<Output<T>>();
  TERN_STANDARD_MESSAGES(TERN_FLEET_OUTPUT_)
#undef TERN_FLEET_OUTPUT_
  return nullptr;
}

std::pair<std::string, std::string> split_topic(const std::string& topic) {
  const auto slash = topic.find('/');
  if (slash == std::string::npos) return {"", topic};
  return {topic.substr(0, slash), topic.substr(slash + 1)};
}

std::shared_ptr<spdlog::logger> fleet_logger(bool quiet) {
  auto sink = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  sink->set_level(quiet ? spdlog::level::warn : spdlog::level::info);
  sink->set_pattern("%^[%l]%$ %n: %v");
  return std::make_shared<spdlog::logger>("fleet", sink);
}

}  // namespace

bool FleetResult::ok() const {
  for (const auto& [name, r] : vehicles)
    if (!r.ok) return false;
  return !coordination || coordination->ok;
}

Fleet::Fleet(FleetConfig config, FleetOptions options)
    : config_(std::move(config)), options_(std::move(options)), log_(fleet_logger(options_.quiet)) {
  seed_ = options_.seed.value_or(config_.seed);
}

Fleet::~Fleet() {
  coordination_.reset();  // its inputs read the mirrors
  mirrors_.clear();
  vehicles_.clear();
}

// ---- build ------------------------------------------------------------------------------------

void Fleet::build() {
  if (!options_.describing) run_dir_ = new_run_dir(options_.log_dir ? fs::absolute(*options_.log_dir) : config_.log.dir, config_.name);
  vehicles_.resize(config_.vehicles.size());
  for (std::size_t i = 0; i < vehicles_.size(); ++i) build_vehicle(i);
  const Nanos period = vehicles_.front().host->base_period();
  for (std::size_t i = 1; i < vehicles_.size(); ++i)
    if (vehicles_[i].host->base_period() != period)
      throw ConfigError(fmt::format("{}: {} ({}): base rate {} Hz, {}'s is {} Hz: the vehicles of a fleet fly one clock (set base_rate:)",
                                    config_.file.string(), config_.vehicles[i].field, vehicles_[i].name,
                                    1e9 / static_cast<double>(vehicles_[i].host->base_period()), vehicles_[0].name,
                                    1e9 / static_cast<double>(period)));
  make_mirrors();
  if (config_.coordination) build_coordination();
  std::vector<std::string> names;
  for (const auto& v : vehicles_) names.push_back(v.name);
  separation_ = std::make_unique<SeparationMonitor>(names, config_.separation);
}

void Fleet::build_vehicle(std::size_t i) {
  Vehicle& v = vehicles_[i];
  v.name = config_.vehicles[i].name;
  HostOptions o;
  o.seed = derive_seed(seed_, v.name);
  o.duration = options_.duration;
  o.quiet = options_.quiet;
  o.describing = options_.describing;
  o.realtime = options_.realtime;
  o.console_prefix = v.name;
  if (!options_.describing) o.run_dir = run_dir_ / v.name;
  v.host = std::make_unique<Host>(config_.vehicles[i].config, o);
  try {
    v.host->build();
  } catch (const ConfigError& e) {
    throw ConfigError(std::string(e.what()) + " (vehicle " + v.name + ")");
  }
}

// Every topic a vehicle publishes, as "<vehicle>/<topic>" for the coordination's port graph.
void Fleet::make_mirrors() {
  for (std::size_t i = 0; i < vehicles_.size(); ++i) {
    for (const auto& t : vehicles_[i].host->topics()) {
      auto out = make_output(t.type_name);
      if (!out) continue;  // not a standard message: a coordination plugin could not declare it either
      out->set_identity(vehicles_[i].name + "/" + t.name, "vehicle " + vehicles_[i].name + "'s " + t.name);
      mirrors_.push_back({i, t.name, std::move(out)});
    }
  }
}

void Fleet::build_coordination() {
  MissionConfig c = *config_.coordination;
  c.base_rate = 1e9 / static_cast<double>(vehicles_.front().host->base_period());  // the vehicles' clock
  HostOptions o;
  o.seed = derive_seed(seed_, "coordination");
  o.duration = options_.duration;
  o.quiet = options_.quiet;
  o.describing = options_.describing;
  o.console_prefix = "coordination";
  if (!options_.describing) o.run_dir = run_dir_ / "coordination";
  for (const auto& m : mirrors_) o.external_outputs.push_back(m.out.get());
  o.check_instances = [this](const std::vector<std::unique_ptr<Instance>>& list) { check_coordination_ports(list); };
  c.log.all_topics = false;  // its own topics only: the vehicles' are in their logs
  coordination_ = std::make_unique<Host>(std::move(c), o);
  coordination_->build();
  for (const auto& inst : coordination_->instances()) {
    for (const auto* in : inst->plugin->inputs())
      for (auto& m : mirrors_) m.read = m.read || in->source() == m.out.get();
    for (const auto* out : inst->plugin->outputs()) {
      const auto [vehicle, topic] = split_topic(out->topic());
      for (std::size_t i = 0; i < vehicles_.size(); ++i)
        if (vehicles_[i].name == vehicle) edits_.push_back({i, out});
    }
  }
}

// Ports "<vehicle>/<topic>": the vehicle exists; an input reads one of its topics; an output is
// its mission_edit, which it reads.
void Fleet::check_coordination_ports(const std::vector<std::unique_ptr<Instance>>& list) const {
  std::vector<std::string> names;
  for (const auto& v : vehicles_) names.push_back(v.name);
  for (const auto& inst : list) {
    const std::string who = config_.file.string() + ": " + inst->cfg.label() + " (" + inst->cfg.name + ")";
    const auto vehicle_of = [&](const PortBase& p) -> const Vehicle* {
      const auto [vehicle, topic] = split_topic(p.topic());
      if (vehicle.empty()) return nullptr;
      for (const auto& v : vehicles_)
        if (v.name == vehicle) return &v;
      throw ConfigError(who + ": port '" + p.name() + "' (topic '" + p.topic() + "') names an unknown vehicle '" + vehicle + "'" +
                        did_you_mean(vehicle, names));
    };
    for (const auto* in : inst->plugin->inputs())
      if (const Vehicle* v = vehicle_of(*in); v && !v->host->topic_source(split_topic(in->topic()).second))
        throw ConfigError(who + ": input '" + in->topic() + "': vehicle " + v->name + " publishes no topic '" +
                          split_topic(in->topic()).second + "'");
    for (const auto* out : inst->plugin->outputs()) {
      const Vehicle* v = vehicle_of(*out);
      if (v == nullptr) continue;
      if (split_topic(out->topic()).second != "mission_edit")
        throw ConfigError(who + ": output '" + out->topic() + "': a vehicle takes only <vehicle>/mission_edit from coordination");
      if (!v->host->takes_mission_edits())
        throw ConfigError(who + ": output '" + out->topic() + "': vehicle " + v->name + " has no path planner reading mission_edit");
    }
  }
}

// ---- fly --------------------------------------------------------------------------------------

FleetResult Fleet::fly() {
  FleetResult r;
  r.run_dir = run_dir_;
  log_->info("fleet '{}': {} vehicles{}, seed {}, log {}", config_.name, vehicles_.size(), coordination_ ? " and coordination" : "", seed_,
             run_dir_.string());
  for (auto& v : vehicles_) {
    v.active = v.host->begin_flight();
    if (!v.active) v.result = v.host->end_flight();
  }
  const auto t0 = std::chrono::steady_clock::now();
  bool coordinating = coordination_ && coordination_->begin_flight();
  std::optional<FlightResult> coord_result;
  if (coordination_ && !coordinating) coord_result = coordination_->end_flight();
  for (;;) {
    bool any = false;
    Nanos now = 0;
    for (auto& v : vehicles_) {
      if (!v.active) continue;
      if (v.host->tick()) {
        any = true;
        now = v.host->now();
      } else {
        v.active = false;
        v.result = v.host->end_flight();
      }
    }
    if (!any) break;
    tick_world(now);
    if (coordinating && !coordination_->tick()) {
      coordinating = false;
      coord_result = coordination_->end_flight();
      log_->warn("t={:.3f} s: the coordination's flight ended ({}); the vehicles fly on without it", to_seconds(now),
                 coord_result->end_reason);
    }
    if (coordinating) forward_edits();
  }
  if (coordinating) coord_result = coordination_->end_flight("vehicles_ended");
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (auto& v : vehicles_) r.vehicles.emplace_back(v.name, v.result);
  r.coordination = coord_result;
  r.summary = summary(r);
  write_documents(r);
  return r;
}

void Fleet::tick_world(Nanos now) {
  copy_mirrors();
  watch_separation(now);
}

void Fleet::copy_mirrors() {
  for (auto& m : mirrors_) {
    if (!m.read) continue;
    const OutputBase* src = vehicles_[m.vehicle].host->topic_source(m.topic);
    if (src != nullptr && src->sequence() != 0 && src->sequence() != m.out->sequence()) m.out->publish_copy(src->data(), src->sequence());
  }
}

void Fleet::forward_edits() {
  for (auto& e : edits_) {
    if (e.out->sequence() == e.seen) continue;
    e.seen = e.out->sequence();
    Vehicle& v = vehicles_[e.vehicle];
    if (v.active) v.host->edit_mission(*static_cast<const msg::MissionEdit*>(e.out->data()), /*own=*/true);
  }
}

}  // namespace tern::core
