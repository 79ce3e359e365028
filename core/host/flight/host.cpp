#include "flight/host.hpp"

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "config/cli_overrides.hpp"
#include "graph/elf_check.hpp"
#include "config/error.hpp"
#include "record/flight_recorder.hpp"
#include "record/status_line.hpp"

namespace tern::core {

namespace {

std::atomic<int> g_stop_signal{0};

extern "C" void tern_on_signal(int sig) { request_stop(sig); }

// The host's log goes to the console (warnings only when quiet) and, while flying, to tern.log.
std::shared_ptr<spdlog::sinks::dist_sink_mt> console_sinks(bool quiet, const std::string& prefix) {
  auto console = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  console->set_level(quiet ? spdlog::level::warn : spdlog::level::info);
  console->set_pattern(prefix.empty() ? "%^[%l]%$ %n: %v" : "%^[%l]%$ " + prefix + "/%n: %v");
  auto dist = std::make_shared<spdlog::sinks::dist_sink_mt>();
  dist->add_sink(console);
  return dist;
}

std::shared_ptr<spdlog::logger> host_logger(std::shared_ptr<spdlog::sinks::dist_sink_mt> sinks) {
  auto log = std::make_shared<spdlog::logger>("tern", std::move(sinks));
  log->set_level(spdlog::level::info);
  return log;
}

}  // namespace

// A flight between begin_flight() and end_flight(): its log, result and clock.
struct Host::Running {
  Running(const fs::path& run_dir, std::shared_ptr<spdlog::sinks::dist_sink_mt> sinks, FlightLog::ErrorHandler on_error,
          FlightLog::Format format, double duration_s)
      : recorder(run_dir, std::move(sinks), std::move(on_error), format), duration(duration_s) {}
  FlightRecorder recorder;
  FlightResult r;
  double duration;
  std::unique_ptr<Scheduler> clock;  // from the first tick on
  std::unique_ptr<StatusLine> status;
  bool aborted = false;
  bool ended = false;  // tick() returned false
};

int stop_signal() { return g_stop_signal.load(); }

void request_stop(int sig) { g_stop_signal.store(sig == 0 ? SIGINT : sig); }

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = tern_on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGHUP, &sa, nullptr);  // the terminal went away (an SSH drop): end the flight cleanly
  std::signal(SIGXFSZ, SIG_IGN);    // a file-size limit fails the log's writes (EFBIG), not the flight
}

// ---- life of a host ---------------------------------------------------------------------------

Host::Host(MissionConfig config, HostOptions options)
    : config_(std::move(config)),
      options_(std::move(options)),
      sinks_(console_sinks(options_.quiet, options_.console_prefix)),
      logger_(host_logger(sinks_)),
      created_ns_(wall_ns()) {
  calibrate_step_clock();  // before anything is timed
  seed_ = options_.seed.value_or(config_.seed);
  failsafes_.configure(config_.failsafes);
}

Host::~Host() {
  // 1. nobody reads anybody any more
  for (auto& inst : instances_)
    if (inst->plugin)
      for (auto* in : inst->plugin->inputs()) in->bind(nullptr);
  graph_ = PortGraph();
  // 2. instances (code in the .so) before their libraries
  for (auto& inst : instances_) inst->drop_plugin();
  phase_machine_ = nullptr;
  metrics_ = nullptr;
  replay_ = nullptr;
  for (auto& inst : instances_) inst->lib.reset();
  instances_.clear();
  if (!swap_dir_.empty()) {
    std::error_code ec;
    fs::remove_all(swap_dir_, ec);
  }
}

void Host::build() {
  LoadedInstances loaded = load_instances(setup(), options_.replay);
  instances_ = std::move(loaded.list);
  phase_machine_ = loaded.phase_machine;
  phase_machine_idx_ = loaded.phase_machine_index;
  metrics_ = loaded.metrics;
  replay_ = loaded.replay;
  if (options_.check_instances) options_.check_instances(instances_);
  rebuild_graph();
  if (!options_.replay) {  // a replay flies a subset of the flight's instances
    std::vector<std::string> published;
    for (const auto& t : topics()) published.push_back(t.name);
    check_log_topics(config_, published);
  }
  built_ = true;
}

// Routing roles, rates, port graph and initial binding, from the instances' ports and the config.
void Host::rebuild_graph() {
  for (auto& inst : instances_)
    if (inst->plugin)
      for (auto* in : inst->plugin->inputs()) in->bind(nullptr);
  graph_ = PortGraph();
  router_.assign(config_, phase_machine_);
  std::vector<const InstanceConfig*> cfgs;
  for (const auto& inst : instances_) cfgs.push_back(&inst->cfg);
  const Rates rates = resolve_rates(config_.base_rate, config_.root["base_rate"], cfgs, config_.file);
  base_period_ = rates.base_period;
  std::vector<PortNode> nodes;
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    Instance& inst = *instances_[i];
    inst.divisor = rates.divisors[i];
    inst.stats.budget_ns = rates.budgets[i];
    if (inst.idle)
      nodes.push_back({inst.cfg.name, false, false, {}, {}});  // writes and reads nothing
    else
      nodes.push_back({inst.cfg.name, inst.info.kind == PluginKind::io, inst.routed, inst.plugin->outputs(), inst.plugin->inputs()});
  }
  const OutputBase* edits = remote_.renew_mission_edit_output();
  const OutputBase* pilot = remote_.renew_pilot_output();
  std::vector<const OutputBase*> offered{edits, pilot};
  offered.insert(offered.end(), options_.external_outputs.begin(), options_.external_outputs.end());
  graph_ = PortGraph(nodes, offered, config_.file, options_.producers);
  remote_.keep_mission_edit_output(graph_.offers(edits));
  remote_.keep_pilot_output(graph_.offers(pilot));
  graph_.bind(router_.active());
}

bool Host::abort_flight() {
  if (!flying_.load()) return false;
  abort_.store(true);
  return true;
}

// ---- requests from other threads --------------------------------------------------------------

void Host::request_param(const std::string& qualified, const ParamValue& value, const std::string& source) {
  const auto dot = qualified.find('.');
  std::vector<std::string> all;
  for (const auto& [name, p] : parameters()) all.push_back(name);
  ParamBase* target = nullptr;
  if (dot != std::string::npos) {
    for (const auto& inst : instances_)
      if (inst->cfg.name == qualified.substr(0, dot)) target = inst->plugin->find_param(qualified.substr(dot + 1));
  }
  if (target == nullptr) throw ConfigError("unknown parameter '" + qualified + "'" + did_you_mean(qualified, all));
  const ParamValue checked = target->validate(value);  // throws ParamError
  if (!target->spec().live && flying_)
    throw ParamError("parameter '" + qualified + "' is read when a flight starts: refused in flight, it takes effect next flight " +
                     "(set it between flights)");
  remote_.request_param(*target, qualified, checked, source);
}

void Host::edit_mission(const msg::MissionEdit& edit, bool own) {
  if (!remote_.takes_mission_edits())
    throw ConfigError(config_.file.string() + ": no plugin instance reads topic 'mission_edit' (add a path_planner)");
  remote_.edit_mission(edit, own);
}

void Host::go_around(const std::string& source) {
  if (phase_machine_ == nullptr)
    throw ConfigError(config_.file.string() + ": no phase machine (the config has no phases:): nothing to go around");
  remote_.request_go_around(source);
}

// At the start of a tick: the operator's go-around, if one was asked for, to the phase machine.
void Host::take_go_around(Nanos now) {
  const std::optional<std::string> source = remote_.take_go_around();
  if (!source || phase_machine_ == nullptr) return;
  if (const std::string why = phase_machine_->request_go_around(*source); !why.empty())
    logger_->warn("t={:.3f} s: go-around ({}) not taken: {}", to_seconds(now), *source, why);
  else
    logger_->info("t={:.3f} s: go-around commanded ({})", to_seconds(now), *source);
}

void Host::set_pilot(const msg::Rc& rc) {
  if (!remote_.takes_pilot())
    throw ConfigError(config_.file.string() + ": no plugin instance reads topic 'pilot' (fly the simulator, sim_aero)");
  remote_.set_pilot(rc);
}

// ---- what the host holds ------------------------------------------------------------------------

Nanos Host::replay_end() const {
  if (!replay_ || base_period_ <= 0) return 0;
  const Nanos last = replay_->end_time();
  return (last + base_period_ - 1) / base_period_ * base_period_;  // a sample between two ticks: the next one plays it
}

std::vector<Host::TopicInfo> Host::topics() const {
  std::vector<TopicInfo> out;
  for (const auto& t : graph_.topics())
    if (t.written()) out.push_back({t.name, t.type_name, t.fingerprint});
  return out;
}

void Host::hold_message(const std::string& topic, const std::vector<std::pair<std::string, double>>& fields) {
  const GraphTopic* t = graph_.find(topic);
  if (t == nullptr || t->writers.empty()) {
    std::vector<std::string> written;
    for (const auto& w : graph_.topics())
      if (!w.writers.empty()) written.push_back(w.name);
    throw ConfigError(
        fmt::format("topic '{}': no plugin of mission '{}' publishes it (a held message replaces a plugin's output); "
                    "its plugins publish: {}",
                    topic, config_.name, fmt::join(written, ", ")));
  }
  held_.hold(topic, t->writers.front().second->type(), fields);
}

const OutputBase* Host::topic_source(const std::string& topic) const {
  const GraphTopic* t = graph_.find(topic);
  return t ? t->current : nullptr;
}

std::vector<std::string> Host::schedule() const {
  std::vector<std::string> out;
  for (auto i : graph_.order()) out.push_back(instances_[i]->cfg.name);
  return out;
}

std::vector<std::pair<std::string, const ParamBase*>> Host::parameters() const {
  std::vector<std::pair<std::string, const ParamBase*>> out;
  for (const auto& inst : instances_)
    for (const auto* p : inst->plugin->params()) out.emplace_back(inst->cfg.name + "." + p->name(), p);
  return out;
}

std::map<std::string, std::string> Host::param_sources() const {
  std::map<std::string, std::string> out;
  for (const auto& inst : instances_)
    for (const auto& [name, setting] : inst->cfg.params) out[inst->cfg.name + "." + name] = setting.source();
  for (const auto& [name, source] : requested_sources_) out[name] = source;
  return out;
}

RemoteQueue::ParamRecorder Host::param_recorder(Running& f) {
  return [this, &f](Nanos t, const std::string& name, const ParamBase& p, const std::string& source) {
    requested_sources_[name] = source;
    f.recorder.param(t, name, p, source);
  };
}

std::string Host::graph_text() const {
  std::string s = fmt::format("mission '{}' ({}), base rate {} Hz, seed {}\n", config_.name, config_.file.string(),
                              1e9 / static_cast<double>(base_period_), seed_);
  s += "schedule (each tick, in this order):\n";
  for (std::size_t k = 0; k < graph_.order().size(); ++k) {
    const std::size_t idx = graph_.order()[k];
    const auto& inst = *instances_[idx];
    std::string when =
        inst.trigger ? "on " + inst.trigger->name() : fmt::format("{} Hz", 1e9 / static_cast<double>(base_period_ * inst.divisor));
    std::string route;
    if (inst.routed) {
      std::vector<std::string> phases;
      for (const auto& [p, name] : config_.phases)
        if (name == inst.cfg.name) phases.emplace_back(msg::phase_name(p));
      if (router_.fallback() == idx) phases.emplace_back("fallback");
      route = fmt::format("  [phase router: {}]", fmt::join(phases, ", "));
    } else if (inst.idle) {
      route = "  (not routed: idle, never steps, writes nothing)";
    }
    s += fmt::format("  {}. {} ({}, {}) {}{}\n", k + 1, inst.cfg.name, inst.info.name, kind_name(inst.info.kind), when, route);
    if (inst.info.name == "external")  // ports on DDS topics (external_plugin.hpp): which ones
      for (const std::vector<PortBase*>& ports : {std::vector<PortBase*>(inst.plugin->inputs().begin(), inst.plugin->inputs().end()),
                                                  std::vector<PortBase*>(inst.plugin->outputs().begin(), inst.plugin->outputs().end())})
        for (const PortBase* p : ports) s += fmt::format("       {} [{}]: {}\n", p->topic(), p->type().name, p->description());
  }
  return s + "topics:\n" + graph_.describe_topics();
}

std::string Host::graph_dot() const {
  std::string s = "digraph tern {\n  rankdir=LR;\n  node [shape=box];\n";
  for (std::size_t i = 0; i < instances_.size(); ++i)
    s += fmt::format("  \"{}\" [label=\"{}\\n{}{}\"{}];\n", instances_[i]->cfg.name, instances_[i]->cfg.name, instances_[i]->info.name,
                     instances_[i]->idle ? "\\n(not routed: idle)" : "",
                     instances_[i]->info.kind == PluginKind::io ? ", style=bold"
                     : instances_[i]->idle                      ? ", style=dashed"
                                                                : "");
  for (const auto& e : graph_.edges())
    s += fmt::format("  \"{}\" -> \"{}\" [label=\"{}\"{}];\n", instances_[e.from]->cfg.name, instances_[e.to]->cfg.name, e.topic,
                     e.feedback ? ", style=dashed" : "");
  s += "}\n";
  return s;
}

FlightFacts Host::facts(double duration_s) const {
  return {config_,
          seed_,
          duration_s,
          flights_,
          base_period_,
          instances_,
          phase_machine_,
          router_,
          metrics_,
          start_to_first_tick_ms_,
          failsafes_.events()};
}

double Host::flight_duration() const { return duration_override_ ? *duration_override_ : options_.duration.value_or(config_.duration); }

// ---- a flight ---------------------------------------------------------------------------------

namespace {
/// The flight log's files as log.* asks, and its 3-D scene from the aircraft file (scene_channels.hpp).
FlightLog::Format log_format(const MissionConfig& config, spdlog::logger& logger) {
  FlightLog::Format f = FlightRecorder::format_of(config.log);
  if (!f.mcap || !f.mcap_ros_channels) return f;
  try {
    f.scene = scene_options(config.aircraft.string(), config.fleet_part);
  } catch (const std::exception& e) {  // the simulator names the file's problem too; the log goes on without a model
    logger.warn("flight log: no aircraft model in the 3-D scene: {}", e.what());
    f.scene = scene_options("", config.fleet_part);
  }
  return f;
}
}  // namespace

FlightResult Host::fly() {
  if (begin_flight())
    while (tick()) {
    }
  return end_flight();
}

Nanos Host::now() const { return running_ && running_->clock ? running_->clock->now() : 0; }

bool Host::begin_flight() {
  const std::int64_t fly_entry = wall_ns();
  if (!built_) build();
  if (flying_.exchange(true)) throw ConfigError("a flight is already in progress");
  try {
    if (flights_ > 0) reset_for_next_flight();
    ++flights_;
    g_stop_signal.store(0);
    abort_.store(false);
    const double duration = flight_duration();
    const fs::path run_dir = options_.run_dir
                                 ? fs::absolute(*options_.run_dir)
                                 : new_run_dir(options_.log_dir ? fs::absolute(*options_.log_dir) : config_.log.dir, config_.name);
    running_ = std::make_unique<Running>(
        run_dir, sinks_, [this](const std::string& line) { logger_->error("{}", line); }, log_format(config_, *logger_), duration);
  } catch (...) {
    flying_.store(false);
    throw;
  }
  Running& f = *running_;
  f.r.run_dir = f.recorder.dir();
  // asked for between flights: in force from the start, so config.yaml, params.csv's first rows
  // (with the request's source) and the plugins' start() all see it
  remote_.apply_before_start(
      [this](Nanos, const std::string& name, const ParamBase&, const std::string& source) { requested_sources_[name] = source; }, *logger_);
  f.recorder.start(resolved_config_.text(facts(f.duration)), parameters(), param_sources());
  f.recorder.choose_topics(graph_, config_.log, config_.file, *logger_);
  logger_->info("flight '{}': {} instances, base rate {} Hz, {} s, seed {}, log {}", config_.name, instances_.size(),
                1e9 / static_cast<double>(base_period_), f.duration, seed_, f.r.run_dir.string());
  if (!config_.overrides.empty()) logger_->info("command line: {}", fmt::join(config_.overrides, " "));
  remote_.take_go_around();  // one asked for between flights is not for this flight
  router_.prepare_flight();
  held_.new_flight();
  for (auto& inst : instances_) inst->take_end_request();  // a request from between flights does not end this one
  if (!apply_realtime_options(f.r) || !start_instances(f.r)) return false;
  router_.start_flight();
  failsafes_.start_flight(config_.failsafes, graph_);
  f.status = std::make_unique<StatusLine>(graph_, options_.progress);
  f.clock = std::make_unique<Scheduler>(base_period_, from_seconds(f.duration), options_.realtime, options_.rt.speed);
  start_to_first_tick_ms_ = static_cast<double>(f.clock->wall_start() - created_ns_) * 1e-6;
  flight_start_ms_ = static_cast<double>(f.clock->wall_start() - fly_entry) * 1e-6;
  watchdog_.arm(
      config_.watchdog, [] { return g_stop_signal.load(); },
      [this](const std::string& reason, const std::string& detail, const std::string& running) {
        Running& g = *running_;
        g.r.ok = reason != "watchdog";
        g.r.end_reason = reason;
        g.r.end_detail = detail;
        g.r.stuck_instance = running;
        g.r.flown = g.clock->now();
        g.r.wall_s = g.clock->wall_s();
        emergency_end(g.recorder, g.r, g.duration);
      });
  return true;
}

bool Host::tick() {
  Running& f = *running_;
  Scheduler& clock = *f.clock;
  if (f.ended || !clock.next(g_stop_signal.load(std::memory_order_relaxed))) return !(f.ended = true);
  remote_.apply(clock.now(), param_recorder(f), *logger_);
  take_go_around(clock.now());
  const EndRequest end = run_tick(clock);
  failsafes_.tick(clock.now(), phase_machine_, remote_, graph_);
  f.recorder.capture(graph_, clock.now());
  notify_observer(clock.now());
  if (!end.reason.empty()) {
    f.r.ok = end.ok;
    f.r.end_reason = end.reason;
    f.r.end_detail = end.ok ? "" : end.detail;
    if (end.ok)
      logger_->info("{}: {}", end.reason, end.detail);
    else
      logger_->error("{}{}", end.reason, end.detail.empty() ? "" : ": " + end.detail);
    return !(f.ended = true);
  }
  if (clock.wall_check_due()) {
    f.recorder.flush_if_due(*logger_);
    f.status->draw(clock.now());
    clock.pace();
  }
  if (abort_.load(std::memory_order_relaxed)) f.aborted = f.ended = true;  // after a complete tick: the log ends with it
  return !f.ended;
}

FlightResult Host::end_flight(const std::string& reason) {
  struct FlyingGuard {
    std::atomic<bool>& f;
    std::unique_ptr<Running>& running;
    ~FlyingGuard() {
      running.reset();
      f.store(false);
    }
  } guard{flying_, running_};
  Running& f = *running_;
  FlightResult& r = f.r;
  if (!f.clock) {  // ended before its first tick (realtime options, a start() that threw)
    f.recorder.close(r);
    return r;
  }
  watchdog_.disarm();
  f.status->finish();
  if (r.ok && r.end_reason.empty()) r.end_reason = f.aborted ? "aborted" : f.ended ? f.clock->end_reason() : reason;
  r.flown = f.clock->now();
  r.wall_s = f.clock->wall_s();
  r.flight_cpu_s = f.clock->cpu_s();
  if (RealtimeStats* rt = f.clock->realtime_stats()) {
    rt->end();
    r.realtime = rt->to_json(options_.rt);
    r.realtime_line = rt->line(options_.rt);
  }
  finish_flight(f.recorder, r, f.duration);
  return r;
}

// A new flight from the mission's initial state, as a fresh host would fly it: every plugin
// reset (its per-flight state replaced), every output empty (sequence 0, a default message: the
// first consumers of a tick see no message from the last flight), inputs rebound, routing back
// to takeoff, step statistics cleared.
void Host::reset_for_next_flight() {
  rebuild_graph();
  for (auto idx : graph_.order()) {
    try {
      instances_[idx]->plugin->reset();
    } catch (const std::exception& e) {
      logger_->error("{}.reset failed: {}", instances_[idx]->cfg.name, e.what());
    }
    const Nanos budget = instances_[idx]->stats.budget_ns;
    instances_[idx]->stats = StepStats{};
    instances_[idx]->stats.budget_ns = budget;
  }
  for (auto& inst : instances_)
    if (inst->plugin)
      for (auto* out : inst->plugin->outputs()) out->clear();
}

// The flight thread's scheduling for a paced flight (realtime.hpp): every flight, on the thread
// that flies it; a setting the system refuses ends the flight before it starts, in one line.
bool Host::apply_realtime_options(FlightResult& r) {
  if (!options_.realtime || !options_.rt.any()) return true;
  if (const std::string err = apply_realtime(options_.rt); !err.empty()) {
    r.ok = false;
    r.end_reason = "error: realtime: " + err;
    logger_->error("{}", r.end_reason);
    return false;
  }
  logger_->info("real time: {}", describe(options_.rt));
  return true;
}

bool Host::start_instances(FlightResult& r) {
  for (auto idx : graph_.order()) {
    try {
      instances_[idx]->plugin->start();
    } catch (const std::exception& e) {
      r.ok = false;
      r.end_reason = fmt::format("error: {}.start failed: {}", instances_[idx]->cfg.name, e.what());
      logger_->error("{}", r.end_reason);
      return false;
    }
  }
  return true;
}

// Steps every instance due in this tick, in the graph's order. Returns why the flight ends
// (reason "" while it goes on): an error, the phase machine's failure or a plugin's end_flight.
EndRequest Host::run_tick(Scheduler& clock) {
  const Nanos now = clock.now();
  const auto step = [&clock, this](Instance& inst) {
    watchdog_.enter(inst.cfg.name, clock.now(), inst.isolated == nullptr, clock.step_start_ticks());
    std::string error;
    const Nanos dt = clock.step(*inst.plugin, error);
    watchdog_.leave(inst.stats, inst.failure().empty() ? dt : 0, *logger_);  // a failed child: its own line
    inst.stats.add(dt);  // after leave(), which parks a step the watchdog claimed: its thread reads the stats then
    return error;
  };
  clock.start_steps();
  for (const std::size_t idx : graph_.order()) {
    Instance& inst = *instances_[idx];
    if (!router_.may_step(idx) || !clock.due(inst.divisor, inst.trigger)) continue;
    const std::string error = step(inst);
    if (inst.routed) {
      if (std::string failure = router_.after_controller_step(now, idx, error, step); !failure.empty()) return {failure, ""};
    } else if (const std::string failed = inst.failure(); !failed.empty()) {
      return {"plugin_failed", fmt::format("{} at t={:.3f} s", failed, to_seconds(now))};
    } else if (!error.empty()) {
      return {fmt::format("error: {}.step threw at t={:.3f} s: {}", inst.cfg.name, to_seconds(now), error), ""};
    } else if (idx == phase_machine_idx_) {
      if (!phase_machine_->failure().empty()) return {phase_machine_->failure(), ""};
      if (phase_machine_->landed()) return {"landed", phase_machine_->landed_detail(), true};
      router_.follow_phase(now);
    }
    if (!held_.empty()) held_.apply(graph_);
    if (auto end = inst.take_end_request())
      return {end->reason, fmt::format("{} at t={:.3f} s: {}", inst.cfg.name, to_seconds(now), end->detail)};
  }
  return {};
}

int Host::add_tick_observer(std::function<void(Nanos now)> observer) {
  tick_observers_.emplace_back(next_observer_id_, std::move(observer));
  return next_observer_id_++;
}

void Host::remove_tick_observer(int id) {
  std::erase_if(tick_observers_, [id](const auto& o) { return o.first == id; });
}

void Host::notify_observer(Nanos now) {
  for (auto it = tick_observers_.begin(); it != tick_observers_.end();) {
    try {
      it->second(now);
      ++it;
    } catch (const std::exception& e) {
      logger_->error("t={:.3f} s: tick observer failed, removed: {}", to_seconds(now), e.what());
      it = tick_observers_.erase(it);
    }
  }
}

void Host::finish_flight(FlightRecorder& recorder, FlightResult& r, double duration_s) {
  for (auto it = graph_.order().rbegin(); it != graph_.order().rend(); ++it) {
    try {
      instances_[*it]->plugin->stop();
    } catch (const std::exception& e) {
      logger_->error("{}.stop failed: {}", instances_[*it]->cfg.name, e.what());
    }
  }
  if (r.end_reason == "SIGINT" || r.end_reason == "SIGTERM" || r.end_reason == "SIGHUP")
    logger_->warn("flight ended by {} at t={:.3f} s; the log is complete", r.end_reason, to_seconds(r.flown));
  if (r.end_reason == "aborted") logger_->info("flight aborted at t={:.3f} s; the log is complete", to_seconds(r.flown));
  recorder.finish(facts(duration_s), r);
  r.summary = summary_text(facts(duration_s), r);
  if (!options_.quiet) {
    std::fputs(r.summary.c_str(), stdout);
    std::fflush(stdout);
  }
}

void Host::emergency_end(FlightRecorder& recorder, FlightResult& r, double duration_s) {
  logger_->error("{}: {}", r.end_reason, r.end_detail);
  recorder.finish(facts(duration_s), r);  // summary.json (atomic), the topic files closed, timing.json
  sinks_->flush();
  if (options_.quiet) {
    std::printf("log: %s\n", r.run_dir.c_str());
  } else {
    const std::string text = summary_text(facts(duration_s), r);
    std::fputs(text.c_str(), stdout);
  }
  std::fflush(stdout);
  std::fflush(stderr);
  std::_Exit(exit_status(r));
}

}  // namespace tern::core
