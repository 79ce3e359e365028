#include "host.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <ctime>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <thread>
#include <bit>
#include <fstream>
#if defined(__x86_64__)
#include <x86intrin.h>
#endif

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/sinks/dist_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "elf_check.hpp"
#include "error.hpp"
#include "flight_log.hpp"
#include "replay.hpp"

namespace tern::core {

namespace {

std::atomic<int> g_stop_signal{0};

extern "C" void tern_on_signal(int sig) { request_stop(sig); }

std::int64_t thread_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

std::int64_t wall_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Step timing clock: the CPU's invariant TSC where there is one (a read costs about half of
// clock_gettime's), else steady_clock. Calibrated once per process against steady_clock.
struct CycleClock {
  bool tsc = false;
  double ns_per_cycle = 1.0;
  CycleClock() {
#if defined(__x86_64__)
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string line;
    bool constant = false, nonstop = false;
    while (std::getline(cpuinfo, line) && line.rfind("flags", 0) != 0) {}
    constant = line.find(" constant_tsc") != std::string::npos;
    nonstop = line.find(" nonstop_tsc") != std::string::npos;
    if (constant && nonstop) {
      const std::int64_t w0 = wall_ns();
      const std::uint64_t c0 = __rdtsc();
      while (wall_ns() - w0 < 2'000'000) {}
      const std::int64_t w1 = wall_ns();
      const std::uint64_t c1 = __rdtsc();
      if (c1 > c0) {
        tsc = true;
        ns_per_cycle = static_cast<double>(w1 - w0) / static_cast<double>(c1 - c0);
      }
    }
#endif
  }
  std::int64_t now() const {
#if defined(__x86_64__)
    if (tsc) return static_cast<std::int64_t>(__rdtsc());
#endif
    return wall_ns();
  }
  Nanos to_ns(std::int64_t cycles) const { return tsc ? static_cast<Nanos>(static_cast<double>(cycles) * ns_per_cycle) : cycles; }
};

const CycleClock& cycle_clock() {
  static const CycleClock c;
  return c;
}

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

std::uint64_t fnv1a(const std::string& s) {
  reflect::Fnv1a f;
  f.bytes(s);
  return f.h;
}

std::string port_id(const Instance& inst, const PortBase& p) { return inst.cfg.name + "." + p.name(); }

YAML::Node to_yaml(const ParamValue& v) {
  YAML::Node n;
  std::visit([&](const auto& x) {
    using T = std::decay_t<decltype(x)>;
    if constexpr (std::is_same_v<T, std::vector<double>>) {
      n = YAML::Node(YAML::NodeType::Sequence);
      for (double d : x) n.push_back(d);
      n.SetStyle(YAML::EmitterStyle::Flow);
    } else {
      n = x;
    }
  }, v);
  return n;
}

std::string param_text(const ParamValue& v) {
  if (std::holds_alternative<std::string>(v)) return std::get<std::string>(v);
  return to_string(v);
}

std::string fmt_ns(double ns) {
  if (ns < 1e3) return fmt::format("{:.0f} ns", ns);
  if (ns < 1e6) return fmt::format("{:.1f} us", ns / 1e3);
  return fmt::format("{:.2f} ms", ns / 1e6);
}

}  // namespace

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

// ---- step statistics ------------------------------------------------------------------------

void StepStats::add(Nanos dt) {
  ++steps;
  total_ns += dt;
  max_ns = std::max(max_ns, dt);
  if (budget_ns > 0 && dt > budget_ns) ++overruns;
  // bucket = 4 log2(dt), from the bit width and the next two bits: no floating point
  const auto u = static_cast<std::uint64_t>(dt < 1 ? 1 : dt);
  const int w = std::bit_width(u);
  const std::size_t frac = w >= 3 ? static_cast<std::size_t>((u >> (w - 3)) & 3u) : 0;
  const std::size_t b = std::min<std::size_t>(histogram.size() - 1, 4 * static_cast<std::size_t>(w - 1) + frac);
  ++histogram[b];
}

Nanos StepStats::percentile(double p) const {
  if (steps == 0) return 0;
  const double target = p * static_cast<double>(steps);
  double cum = 0;
  for (std::size_t b = 0; b < histogram.size(); ++b) {
    cum += histogram[b];
    if (cum >= target) {  // upper edge of the bucket
      const std::size_t w = b / 4, frac = b % 4;
      return static_cast<Nanos>((std::uint64_t{4} + frac + 1) << w) / 4;
    }
  }
  return max_ns;
}

// ---- the context each instance sees ---------------------------------------------------------

class InstanceContext final : public Context {
 public:
  InstanceContext(const Host& host, const InstanceConfig& cfg, std::uint64_t seed, std::shared_ptr<spdlog::logger> log,
                  bool describing)
      : host_(host), cfg_(cfg), seed_(seed), log_(std::move(log)), describing_(describing) {}

  const std::string& instance_name() const override { return cfg_.name; }
  std::optional<ParamValue> configured_value(const std::string& param, const ParamSpec& spec) const override {
    auto it = cfg_.params.find(param);
    last_param_ = param;
    if (it == cfg_.params.end()) return std::nullopt;
    used_.insert(param);
    ParamValue v = to_param_value(it->second.node, it->second.file, it->second.field);
    if (spec.is_path && std::holds_alternative<std::string>(v)) {
      fs::path p(std::get<std::string>(v));
      if (p.is_relative()) v = (it->second.file.parent_path() / p).lexically_normal().string();
    }
    return v;
  }
  std::uint64_t seed() const override { return seed_; }
  std::shared_ptr<spdlog::logger> logger() const override { return log_; }
  std::filesystem::path config_dir() const override { return host_.config().dir; }
  const YAML::Node& mission() const override { return host_.config().mission; }
  std::filesystem::path aircraft_file() const override { return host_.config().aircraft; }
  bool describing() const override { return describing_; }

  const std::string& last_param() const { return last_param_; }
  const std::set<std::string>& used() const { return used_; }

 private:
  const Host& host_;
  const InstanceConfig& cfg_;
  std::uint64_t seed_;
  std::shared_ptr<spdlog::logger> log_;
  bool describing_;
  mutable std::string last_param_;
  mutable std::set<std::string> used_;
};

// ---- topics -----------------------------------------------------------------------------------

struct Host::Topic {
  std::string name;
  std::string type_name;
  std::uint64_t fingerprint = 0;
  std::size_t msg_size = 0;
  std::vector<reflect::Column> columns;
  std::vector<std::pair<std::size_t, OutputBase*>> writers;  // (instance, port)
  std::vector<std::pair<std::size_t, InputBase*>> readers;
  bool routed = false;
  const OutputBase* host_writer = nullptr;  // written by the host itself (mission_edit)
  const OutputBase* current = nullptr;  // the writer readers are bound to
  // logging
  std::size_t log_index = SIZE_MAX;
  const OutputBase* logged_src = nullptr;
  std::uint64_t logged_seq = 0;
  Nanos log_interval = 0;   // minimum flight time between two logged messages
  Nanos logged_t = 0;
};

// ---- host -------------------------------------------------------------------------------------

Host::Host(MissionConfig config, HostOptions options) : config_(std::move(config)), options_(std::move(options)) {
  created_ns_ = wall_ns();
  (void)cycle_clock();  // calibrate before anything is timed
  seed_ = options_.seed.value_or(config_.seed);
  auto console = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  console->set_level(options_.quiet ? spdlog::level::warn : spdlog::level::info);
  console->set_pattern("%^[%l]%$ %n: %v");
  auto dist = std::make_shared<spdlog::sinks::dist_sink_mt>();
  dist->add_sink(console);
  extra_sinks_.push_back(dist);
  logger_ = std::make_shared<spdlog::logger>("tern", dist);
  logger_->set_level(spdlog::level::info);
}

Host::~Host() {
  // 1. nobody reads anybody any more
  for (auto& inst : instances_)
    if (inst->plugin)
      for (auto* in : inst->plugin->inputs()) in->bind(nullptr);
  for (auto& t : topics_) {
    t->current = nullptr;
    t->logged_src = nullptr;
  }
  topics_.clear();
  // 2. instances (code in the .so) before their libraries
  for (auto& inst : instances_) {
    inst->plugin.reset();
    inst->ctx.reset();
  }
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

void Host::swap(const std::string& instance, const fs::path& so_in) {
  if (flying_) throw ConfigError("swap refused: a flight is in progress; swap between flights");
  std::size_t idx = SIZE_MAX;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    if (!instances_[i]->builtin) names.push_back(instances_[i]->cfg.name);
    if (instances_[i]->cfg.name == instance && !instances_[i]->builtin) idx = i;
  }
  if (idx == SIZE_MAX) throw ConfigError("swap: no plugin instance named '" + instance + "'" + did_you_mean(instance, names));
  fs::path so = so_in;
  if (so.string().find('/') == std::string::npos && so.extension() != ".so") so = find_plugin(so.string(), plugin_search_path(config_.plugin_path));
  so = fs::absolute(so).lexically_normal();
  if (!fs::exists(so)) throw ConfigError("swap: '" + so.string() + "' not found");
  fs::path copy;
  const auto discard_copy = [&] {  // a refused swap leaves no file behind
    std::error_code ec;
    if (!copy.empty()) fs::remove(copy, ec);
    if (!swap_dir_.empty() && fs::remove(swap_dir_, ec)) swap_dir_.clear();  // only when empty
  };
  auto fresh = std::make_unique<Instance>();
  fresh->cfg = instances_[idx]->cfg;
  fresh->source = so;
  try {
    check_elf(so);  // before the copy: the error names the file as given
    // a private copy: a rebuild at the same path must not resolve to the library already mapped
    if (swap_dir_.empty()) {
      swap_dir_ = fs::temp_directory_path() / fmt::format("tern-swap-{}-{}", ::getpid(), reinterpret_cast<std::uintptr_t>(this));
      fs::create_directories(swap_dir_);
    }
    copy = swap_dir_ / fmt::format("{}-{}", ++swaps_, so.filename().string());
    fs::copy_file(so, copy, fs::copy_options::overwrite_existing);
    fresh->lib = open_plugin(copy);
    fresh->info = fresh->lib->info();
    fresh->plugin = fresh->lib->create();
    configure_instance(*fresh);
  } catch (const std::exception& e) {  // ConfigError, or a filesystem error of the copy
    fresh->plugin.reset();
    fresh->ctx.reset();
    fresh->lib.reset();
    discard_copy();
    throw ConfigError("swap " + instance + " <- " + so.string() + " refused, '" + instances_[idx]->info.name + "' keeps flying: " + e.what());
  }
  std::swap(instances_[idx], fresh);  // `fresh` is now the old instance
  try {
    rebuild_graph();
  } catch (const ConfigError& e) {
    std::swap(instances_[idx], fresh);
    rebuild_graph();
    fresh->plugin.reset();
    fresh->ctx.reset();
    fresh->lib.reset();
    discard_copy();
    throw ConfigError("swap " + instance + " <- " + so.string() + " refused (its ports do not fit the graph), the old plugin keeps flying: " + e.what());
  }
  if (idx == phase_machine_idx_) phase_machine_ = nullptr;  // (never: built-ins are not swappable)
  const fs::path old_path = fresh->lib ? fresh->lib->info().path : fs::path();
  const bool shared = fresh->lib && fresh->lib.use_count() > 1;
  const std::string old_desc = fmt::format("{} ({})", fresh->info.name, fresh->source.string());
  fresh->plugin.reset();
  fresh->ctx.reset();
  fresh->lib.reset();
  if (!shared && !old_path.empty() && is_loaded(old_path))
    logger_->warn("swap {}: the old library {} is still mapped after unloading it", instance, old_path.string());
  if (!old_path.empty() && old_path.parent_path() == swap_dir_ && !shared) fs::remove(old_path);
  logger_->info("swapped {}: {} -> {} ({})", instance, old_desc, instances_[idx]->info.name, so.string());
}

void Host::set_phases(const std::map<msg::Phase, std::string>& phases, const std::optional<std::string>& fallback) {
  if (flying_) throw ConfigError("phases refused: a flight is in progress; change the table between flights");
  if (!phase_machine_) throw ConfigError("phases: this mission has no 'phases:' table (and so no phase machine) to change");
  for (auto p : {msg::Phase::takeoff, msg::Phase::climb, msg::Phase::cruise})
    if (!phases.count(p)) throw ConfigError("phases: no controller for phase '" + std::string(msg::phase_name(p)) + "'");
  std::vector<std::string> names;
  for (const auto& inst : instances_)
    if (!inst->builtin) names.push_back(inst->cfg.name);
  auto check = [&](const std::string& n) {
    if (std::find(names.begin(), names.end(), n) == names.end())
      throw ConfigError("phases: no plugin instance named '" + n + "'" + did_you_mean(n, names));
  };
  for (const auto& [p, n] : phases) check(n);
  if (fallback) check(*fallback);
  const auto old_phases = config_.phases;
  const auto old_fallback = config_.fallback;
  config_.phases = phases;
  if (fallback) config_.fallback = fallback;
  try {
    rebuild_graph();
  } catch (const ConfigError& e) {
    config_.phases = old_phases;
    config_.fallback = old_fallback;
    rebuild_graph();
    throw ConfigError(std::string("phases refused, the old table stays: ") + e.what());
  }
  std::string table;
  for (const auto& [p, n] : config_.phases) table += fmt::format("{}{}={}", table.empty() ? "" : ", ", msg::phase_name(p), n);
  logger_->info("phase table: {}{}", table, config_.fallback ? ", fallback=" + *config_.fallback : "");
}

void Host::build() {
  load_instances();
  rebuild_graph();
  if (!options_.replay_dir) {  // a replay flies a subset of the flight's instances
    std::vector<std::string> published;
    for (const auto& t : topics()) published.push_back(t.name);
    check_log_topics(config_, published);
  }
  built_ = true;
}

void Host::update_routing_roles() {
  std::set<std::string> routed;
  for (const auto& [phase, name] : config_.phases) routed.insert(name);
  if (config_.fallback) routed.insert(*config_.fallback);
  for (auto& inst : instances_) inst->routed = !inst->builtin && routed.count(inst->cfg.name) > 0;
  fallback_.reset();
  active_.reset();
  if (config_.phases.empty()) return;
  for (std::size_t i = 0; i < instances_.size(); ++i)
    if (config_.fallback && instances_[i]->cfg.name == *config_.fallback) fallback_ = i;
  if (!fallback_) {
    for (std::size_t i = 0; i < instances_.size(); ++i)
      if (instances_[i]->routed && instances_[i]->info.name == "control_slc") {
        fallback_ = i;
        break;
      }
  }
}

void Host::rebuild_graph() {
  for (auto& inst : instances_)
    if (inst->plugin)
      for (auto* in : inst->plugin->inputs()) in->bind(nullptr);
  topics_.clear();
  edges_.clear();
  order_.clear();
  update_routing_roles();
  resolve_rates();
  bind_ports();
  order_schedule();
}

void Host::load_instances() {
  const auto search = plugin_search_path(config_.plugin_path);
  std::map<fs::path, std::shared_ptr<PluginLibrary>> libs;
  const fs::path& f = config_.file;
  if (options_.replay_dir) {
    auto inst = std::make_unique<Instance>();
    inst->cfg.index = config_.plugins.size() + 2;
    inst->cfg.name = "replay";
    inst->cfg.plugin = "replay (built in)";
    inst->cfg.rate = config_.base_rate.value_or(400.0);
    inst->builtin = true;
    inst->info = PluginInfo{"replay", PluginKind::io, "recorded sensor and truth topics of a flight log", {}};
    auto rp = std::make_unique<ReplaySource>(*options_.replay_dir);
    replay_ = rp.get();
    inst->plugin = std::move(rp);
    configure_instance(*inst);
    instances_.push_back(std::move(inst));
  }
  for (const auto& ic : config_.plugins) {
    const std::string field = "plugins[" + std::to_string(ic.index) + "]";
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
      throw ConfigError(where(f, ic.node["plugin"]) + field + ".plugin: " + path.string() + " registers plugin '" +
                        inst->info.name + "', not '" + ic.plugin + "'");
    if (options_.replay_dir && inst->info.kind != PluginKind::estimator) continue;  // replay: estimators only
    inst->plugin = inst->lib->create();
    configure_instance(*inst);
    instances_.push_back(std::move(inst));
  }
  // The host's built-in instances (phase machine, flight metrics): reserved names, triggered by
  // `state`, parameters from their own config section.
  const auto add_builtin = [&](std::size_t index, const std::string& name, const std::string& description,
                               const std::map<std::string, ParamSetting>& params, std::unique_ptr<Plugin> plugin) {
    for (const auto& other : instances_)
      if (other->cfg.name == name)
        throw ConfigError(where(f, other->cfg.node) + "instance name '" + name + "' is reserved for " + description);
    auto inst = std::make_unique<Instance>();
    inst->cfg.index = index;
    inst->cfg.name = name;
    inst->cfg.plugin = name + " (built in)";
    inst->cfg.trigger = "state";
    inst->cfg.params = params;
    if (config_.root[name]) inst->cfg.node = config_.root[name];
    inst->builtin = true;
    inst->info = PluginInfo{name, PluginKind::generic, description, {}};
    inst->plugin = std::move(plugin);
    configure_instance(*inst);
    instances_.push_back(std::move(inst));
  };
  if (!config_.phases.empty()) {
    auto pm = std::make_unique<PhaseMachine>();
    phase_machine_ = pm.get();
    phase_machine_idx_ = instances_.size();
    add_builtin(config_.plugins.size(), "phase_machine", "the host's flight-phase machine", config_.phase_params,
                std::move(pm));
  }
  bool has_state = false;
  for (const auto& other : instances_)
    for (const auto* o : other->plugin->outputs()) has_state = has_state || o->topic() == "state";
  if (has_state) {
    auto m = std::make_unique<FlightMetrics>();
    metrics_ = m.get();
    add_builtin(config_.plugins.size() + 1, "metrics", "the host's flight metrics (estimation and tracking RMSE)",
                config_.metrics_params, std::move(m));
  }
}

void Host::configure_instance(Instance& inst) {
  const fs::path& f = config_.file;
  const std::uint64_t iseed = splitmix64(seed_ ^ fnv1a(inst.cfg.name));
  auto log = std::make_shared<spdlog::logger>(inst.cfg.name, extra_sinks_.begin(), extra_sinks_.end());
  log->set_level(spdlog::level::info);
  inst.ctx = std::make_unique<InstanceContext>(*this, inst.cfg, iseed, log, options_.describing);
  inst.plugin->attach(inst.ctx.get());
  const std::string field = inst.builtin ? inst.cfg.name : "plugins[" + std::to_string(inst.cfg.index) + "]";
  try {
    inst.plugin->configure();
  } catch (const ParamError& e) {
    const std::string& p = inst.ctx->last_param();
    auto it = inst.cfg.params.find(p);
    if (it != inst.cfg.params.end())
      throw ConfigError(where(it->second.file, it->second.node) + it->second.field + ": " + e.what());
    throw ConfigError(where(f, inst.cfg.node) + field + " (" + inst.cfg.name + "): " + e.what());
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw ConfigError(where(f, inst.cfg.node) + field + " (" + inst.cfg.name + "): configure failed: " + e.what());
  }
  // parameters the config sets but the plugin does not have
  std::vector<std::string> declared;
  for (const auto* p : inst.plugin->params()) declared.push_back(p->name());
  for (const auto& [name, setting] : inst.cfg.params) {
    if (inst.ctx->used().count(name)) continue;
    const std::string msg = "unknown parameter '" + name + "' of plugin '" + inst.info.name + "'" + did_you_mean(name, declared);
    if (setting.strict) {
      // find the key node for a precise location
      throw ConfigError(where(setting.file, setting.node) + setting.field + ": " + msg);
    }
    logger_->warn("{}{}: {} (ignored: shared ROS 2 parameter file)", where(setting.file, setting.node), setting.field, msg);
  }
  // remaps
  for (const auto& [port, topic] : inst.cfg.remap) {
    PortBase* p = inst.plugin->find_input(port);
    if (p == nullptr) p = inst.plugin->find_output(port);
    if (p == nullptr) {
      std::vector<std::string> ports;
      for (auto* i : inst.plugin->inputs()) ports.push_back(i->name());
      for (auto* o : inst.plugin->outputs()) ports.push_back(o->name());
      throw ConfigError(where(f, inst.cfg.node["remap"]) + field + ".remap: plugin '" + inst.info.name + "' has no port '" +
                        port + "'" + did_you_mean(port, ports));
    }
    p->set_topic(topic);
  }
  if (inst.cfg.trigger) {
    inst.trigger = inst.plugin->find_input(*inst.cfg.trigger);
    if (inst.trigger == nullptr) {
      std::vector<std::string> ports;
      for (auto* i : inst.plugin->inputs()) ports.push_back(i->name());
      throw ConfigError(where(f, inst.builtin ? inst.cfg.node : inst.cfg.node["trigger"]) + field + ".trigger: plugin '" +
                        inst.info.name + "' has no input port '" + *inst.cfg.trigger + "'" + did_you_mean(*inst.cfg.trigger, ports));
    }
  }
}

void Host::resolve_rates() {
  const fs::path& f = config_.file;
  double base = 0;
  if (config_.base_rate) {
    base = *config_.base_rate;
  } else {
    for (const auto& inst : instances_)
      if (inst->cfg.rate) base = std::max(base, *inst->cfg.rate);
  }
  if (base <= 0) throw ConfigError(f.string() + ": base_rate: no instance has a rate and no base_rate is given");
  try {
    base_period_ = period_from_hz(base);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(where(f, config_.root["base_rate"]) + "base_rate: " + e.what());
  }
  for (auto& inst : instances_) {
    if (!inst->cfg.rate) {
      inst->stats.budget_ns = base_period_;
      continue;
    }
    const double r = *inst->cfg.rate;
    const std::string field = "plugins[" + std::to_string(inst->cfg.index) + "].rate";
    const YAML::Node node = inst->cfg.node["rate"];
    const double ratio = base / r;
    const double rounded = std::round(ratio);
    Nanos period = 0;
    try {
      period = period_from_hz(r);
    } catch (const std::invalid_argument&) {
    }
    if (r > base || rounded < 1 || std::fabs(ratio - rounded) > 1e-9 * rounded || period == 0 ||
        period != base_period_ * static_cast<Nanos>(rounded)) {
      throw ConfigError(where(f, node) + field + ": " + fmt::format("{} Hz cannot be served by the base rate {} Hz", r, base) +
                        fmt::format(" (the base rate must be a whole multiple of every rate: {} / {} = {:.4g}); use a rate that divides {} Hz or `trigger:`",
                                    base, r, ratio, base));
    }
    inst->divisor = static_cast<std::int64_t>(rounded);
    inst->stats.budget_ns = period;
  }
  for (auto& inst : instances_)
    if (inst->cfg.budget_us) inst->stats.budget_ns = static_cast<Nanos>(*inst->cfg.budget_us * 1e3);
}

void Host::bind_ports() {
  const fs::path& f = config_.file;
  std::map<std::string, std::size_t> by_name;
  auto topic_of = [&](const std::string& name) -> Topic& {
    auto it = by_name.find(name);
    if (it == by_name.end()) {
      auto t = std::make_unique<Topic>();
      t->name = name;
      topics_.push_back(std::move(t));
      it = by_name.emplace(name, topics_.size() - 1).first;
    }
    return *topics_[it->second];
  };
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    for (auto* out : instances_[i]->plugin->outputs()) topic_of(out->topic()).writers.emplace_back(i, out);
    for (auto* in : instances_[i]->plugin->inputs()) topic_of(in->topic()).readers.emplace_back(i, in);
  }
  std::vector<std::string> written;
  for (const auto& t : topics_)
    if (!t->writers.empty()) written.push_back(t->name);

  for (auto& tp : topics_) {
    Topic& t = *tp;
    if (t.writers.size() > 1) {
      bool all_routed = true;
      for (auto& [i, o] : t.writers) all_routed = all_routed && instances_[i]->routed;
      if (!all_routed) {
        std::vector<std::string> names;
        for (auto& [i, o] : t.writers) names.push_back(port_id(*instances_[i], *o));
        throw ConfigError(fmt::format("{}: topic '{}' has {} writers: {} (only controllers behind the phase router, "
                                      "named in 'phases:', may share a topic; remap one of them)",
                                      f.string(), t.name, names.size(), fmt::join(names, ", ")));
      }
      t.routed = true;
    } else if (t.writers.size() == 1 && instances_[t.writers[0].first]->routed) {
      t.routed = true;
    }
    if (!t.writers.empty()) {
      const OutputBase* w0 = t.writers[0].second;
      t.type_name = std::string(w0->type().name);
      t.fingerprint = w0->type().fingerprint;
      t.msg_size = w0->type().size;
      t.columns = w0->type().columns();
      for (auto& [i, o] : t.writers) {
        if (o->type().fingerprint != t.fingerprint)
          throw ConfigError(fmt::format("{}: topic '{}': writers disagree on the message type: {} publishes {} ({:016x}), {} publishes {} ({:016x})",
                                        f.string(), t.name, port_id(*instances_[t.writers[0].first], *w0), t.type_name, t.fingerprint,
                                        port_id(*instances_[i], *o), o->type().name, o->type().fingerprint));
      }
    }
    for (auto& [i, in] : t.readers) {
      const std::string who = port_id(*instances_[i], *in);
      if (t.writers.empty()) {
        if (in->need() == Need::optional) continue;
        throw ConfigError(fmt::format("{}: input '{}' (topic '{}', {}) has no producer: no instance publishes '{}'{}; "
                                      "add a plugin that does or remap the input",
                                      f.string(), who, t.name, in->type().name, t.name, did_you_mean(t.name, written)));
      }
      if (in->type().fingerprint != t.fingerprint) {
        const bool same_name = in->type().name == t.type_name;
        throw ConfigError(fmt::format("{}: input '{}' expects {} ({:016x}) but topic '{}' carries {} ({:016x}) from '{}'{}",
                                      f.string(), who, in->type().name, in->type().fingerprint, t.name, t.type_name, t.fingerprint,
                                      port_id(*instances_[t.writers[0].first], *t.writers[0].second),
                                      same_name ? ": same type name, different layout; rebuild both against the same SDK" : ""));
      }
    }
  }
  // the host publishes runtime mission edits when a plugin reads them and no plugin writes them
  for (auto& tp : topics_) {
    if (tp->name != "mission_edit" || !tp->writers.empty() || tp->readers.empty()) continue;
    mission_edit_out_ = std::make_unique<Output<msg::MissionEdit>>();
    mission_edit_out_->set_identity("mission_edit", "runtime mission edits (command line, DDS)");
    for (auto& [i, in] : tp->readers)
      if (in->type().fingerprint != mission_edit_out_->type().fingerprint)
        throw ConfigError(fmt::format("{}: input '{}' on topic 'mission_edit' expects {}, the host publishes {}", f.string(),
                                      port_id(*instances_[i], *in), in->type().name, mission_edit_out_->type().name));
    tp->type_name = std::string(mission_edit_out_->type().name);
    tp->fingerprint = mission_edit_out_->type().fingerprint;
    tp->msg_size = mission_edit_out_->type().size;
    tp->columns = mission_edit_out_->type().columns();
    tp->host_writer = mission_edit_out_.get();
  }
  // initial routing: the takeoff controller
  if (!config_.phases.empty()) {
    const std::string& first = config_.phases.at(msg::Phase::takeoff);
    for (std::size_t i = 0; i < instances_.size(); ++i)
      if (instances_[i]->cfg.name == first) active_ = i;
  }
  for (auto& tp : topics_) {
    Topic& t = *tp;
    if (t.host_writer) {
      t.current = t.host_writer;
      for (auto& [i, in] : t.readers) in->bind(t.host_writer);
      continue;
    }
    if (t.writers.empty()) continue;
    const OutputBase* src = t.writers[0].second;
    if (t.routed) {
      src = nullptr;
      for (auto& [i, o] : t.writers)
        if (active_ && i == *active_) src = o;
    }
    t.current = src;
    for (auto& [i, in] : t.readers) in->bind(src);
  }
}

void Host::order_schedule() {
  const std::size_t n = instances_.size();
  edges_.clear();
  for (const auto& tp : topics_)
    for (auto& [w, o] : tp->writers)
      for (auto& [r, in] : tp->readers)
        if (w != r) edges_.push_back({w, r, tp->name, false});
  std::vector<bool> placed(n, false);
  order_.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (instances_[i]->info.kind == PluginKind::io) {
      order_.push_back(i);
      placed[i] = true;
    }
  while (order_.size() < n) {
    std::optional<std::size_t> pick;
    for (std::size_t i = 0; i < n && !pick; ++i) {
      if (placed[i]) continue;
      bool ready = true;
      for (const auto& e : edges_)
        if (e.to == i && !placed[e.from]) ready = false;
      if (ready) pick = i;
    }
    if (!pick) {  // a cycle: the earliest instance in the config goes first, its open inputs are feedback
      for (std::size_t i = 0; i < n && !pick; ++i)
        if (!placed[i]) pick = i;
    }
    placed[*pick] = true;
    order_.push_back(*pick);
  }
  std::vector<std::size_t> pos(n);
  for (std::size_t k = 0; k < n; ++k) pos[order_[k]] = k;
  for (auto& e : edges_) e.feedback = pos[e.from] > pos[e.to];
}

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
  std::lock_guard lk(param_mu_);
  param_requests_.push_back({target, qualified, checked, source});
  param_pending_.store(true, std::memory_order_release);
}

void Host::apply_start_only_requests(FlightLog& log) {
  std::lock_guard lk(param_mu_);
  const auto first = std::stable_partition(param_requests_.begin(), param_requests_.end(),
                                           [](const ParamRequest& rq) { return rq.param->spec().live; });
  for (auto rq = first; rq != param_requests_.end(); ++rq) {
    try {
      rq->param->set(rq->value);
      log.param(0, rq->name, param_text(rq->param->value()), rq->source);
      logger_->info("{} = {} ({}, before the start)", rq->name, to_string(rq->param->value()), rq->source);
    } catch (const std::exception& e) {
      logger_->error("{} not changed: {}", rq->name, e.what());
    }
  }
  param_requests_.erase(first, param_requests_.end());
}

Nanos Host::replay_end() const { return replay_ ? replay_->end_time() : 0; }

std::vector<Host::TopicInfo> Host::topics() const {
  std::vector<TopicInfo> out;
  for (const auto& t : topics_)
    if (!t->writers.empty() || t->host_writer) out.push_back({t->name, t->type_name, t->fingerprint});
  return out;
}

const OutputBase* Host::topic_source(const std::string& topic) const {
  for (const auto& t : topics_)
    if (t->name == topic) return t->current;
  return nullptr;
}

void Host::edit_mission(const msg::MissionEdit& edit) {
  if (!mission_edit_out_) throw ConfigError(config_.file.string() + ": no plugin instance reads topic 'mission_edit' (add a path_planner)");
  std::lock_guard lk(param_mu_);
  mission_edits_.push_back(edit);
  param_pending_.store(true, std::memory_order_release);
}

std::vector<std::string> Host::schedule() const {
  std::vector<std::string> out;
  for (auto i : order_) out.push_back(instances_[i]->cfg.name);
  return out;
}

std::vector<std::pair<std::string, const ParamBase*>> Host::parameters() const {
  std::vector<std::pair<std::string, const ParamBase*>> out;
  for (const auto& inst : instances_)
    for (const auto* p : inst->plugin->params()) out.emplace_back(inst->cfg.name + "." + p->name(), p);
  return out;
}

std::string Host::graph_text() const {
  std::string s = fmt::format("mission '{}' ({}), base rate {} Hz, seed {}\n", config_.name, config_.file.string(),
                              1e9 / static_cast<double>(base_period_), seed_);
  s += "schedule (each tick, in this order):\n";
  for (std::size_t k = 0; k < order_.size(); ++k) {
    const auto& inst = *instances_[order_[k]];
    std::string when = inst.trigger ? "on " + inst.trigger->name()
                                    : fmt::format("{} Hz", 1e9 / static_cast<double>(base_period_ * inst.divisor));
    std::string route;
    if (inst.routed) {
      std::vector<std::string> phases;
      for (const auto& [p, name] : config_.phases)
        if (name == inst.cfg.name) phases.emplace_back(msg::phase_name(p));
      if (fallback_ && instances_[*fallback_].get() == &inst) phases.emplace_back("fallback");
      route = fmt::format("  [phase router: {}]", fmt::join(phases, ", "));
    }
    s += fmt::format("  {}. {} ({}, {}) {}{}\n", k + 1, inst.cfg.name, inst.info.name, kind_name(inst.info.kind), when, route);
  }
  s += "topics:\n";
  for (const auto& tp : topics_) {
    const Topic& t = *tp;
    std::vector<std::string> w, r;
    for (auto& [i, o] : t.writers) w.push_back(port_id(*instances_[i], *o));
    if (t.host_writer) w.push_back("host (tern mission edits)");
    for (auto& [i, in] : t.readers) {
      bool fb = false;
      for (const auto& e : edges_)
        if (e.to == i && e.topic == t.name && e.feedback) fb = true;
      r.push_back(port_id(*instances_[i], *in) + (fb ? " (feedback: previous tick)" : "") +
                  (t.writers.empty() && !t.host_writer ? " (optional, unconnected)" : ""));
    }
    s += fmt::format("  {} [{}]{}: {} -> {}\n", t.name, t.writers.empty() ? std::string(t.readers[0].second->type().name) : t.type_name,
                     t.routed ? " (routed)" : "", w.empty() ? "(none)" : fmt::format("{}", fmt::join(w, ", ")),
                     r.empty() ? "(not read)" : fmt::format("{}", fmt::join(r, ", ")));
  }
  return s;
}

std::string Host::graph_dot() const {
  std::string s = "digraph tern {\n  rankdir=LR;\n  node [shape=box];\n";
  for (std::size_t i = 0; i < instances_.size(); ++i)
    s += fmt::format("  \"{}\" [label=\"{}\\n{}\"{}];\n", instances_[i]->cfg.name, instances_[i]->cfg.name, instances_[i]->info.name,
                     instances_[i]->info.kind == PluginKind::io ? ", style=bold" : "");
  for (const auto& e : edges_)
    s += fmt::format("  \"{}\" -> \"{}\" [label=\"{}\"{}];\n", instances_[e.from]->cfg.name, instances_[e.to]->cfg.name, e.topic,
                     e.feedback ? ", style=dashed" : "");
  s += "}\n";
  return s;
}

bool Host::step_instance(Instance& inst, Nanos now, std::string& error) {
  // One clock read per step: the end of a step is the start of the next one in the same tick
  // (the few ns spent deciding that an instance is not due count towards the next step).
  const CycleClock& clock = cycle_clock();
  try {
    inst.plugin->step(now);
  } catch (const std::exception& e) {
    error = e.what();
  } catch (...) {
    error = "unknown exception";
  }
  const std::int64_t t1 = clock.now();
  inst.stats.add(clock.to_ns(t1 - step_clock_));
  step_clock_ = t1;
  for (auto* in : inst.plugin->inputs()) in->mark_seen();
  return error.empty();
}

void Host::route_to(std::size_t idx, Nanos now, const std::string& reason, bool from_failure) {
  if (active_ && *active_ == idx) return;
  const std::string from = active_ ? instances_[*active_]->cfg.name : "(none)";
  Instance& target = *instances_[idx];
  logger_->log(from_failure ? spdlog::level::warn : spdlog::level::info, "t={:.3f} s: controller {} -> {}: {}", to_seconds(now), from,
               target.cfg.name, reason);
  handovers_.push_back({now, from, target.cfg.name, reason});
  active_ = idx;
  for (auto& tp : topics_) {
    if (!tp->routed) continue;
    const OutputBase* src = nullptr;
    for (auto& [i, o] : tp->writers)
      if (i == idx) src = o;
    tp->current = src;
    for (auto& [i, in] : tp->readers) in->bind(src);
  }
  try {
    target.plugin->take_over(last_good_);
  } catch (const std::exception& e) {
    if (!from_failure && fallback_ && idx != *fallback_) engage_fallback(now, fmt::format("{}.take_over threw: {}", target.cfg.name, e.what()));
    else logger_->error("{}.take_over threw: {}", target.cfg.name, e.what());
  }
}

void Host::route_none(Nanos now, const std::string& reason) {
  if (!active_) return;
  logger_->info("t={:.3f} s: controller {} -> (none): {}", to_seconds(now), instances_[*active_]->cfg.name, reason);
  handovers_.push_back({now, instances_[*active_]->cfg.name, "(none)", reason});
  active_.reset();
  for (auto& tp : topics_) {
    if (!tp->routed) continue;
    tp->current = nullptr;
    for (auto& [i, in] : tp->readers) in->bind(nullptr);
  }
}

void Host::engage_fallback(Nanos now, const std::string& why) {
  fallback_engaged_ = true;
  route_to(*fallback_, now, "fallback for the rest of the flight: " + why, true);
}

FlightResult Host::fly() {
  const std::int64_t fly_entry = wall_ns();
  if (!built_) build();
  if (flying_.exchange(true)) throw ConfigError("a flight is already in progress");
  struct FlyingGuard {
    std::atomic<bool>& f;
    ~FlyingGuard() { f.store(false); }
  } flying_guard{flying_};
  if (flights_ > 0) {
    // a new flight from the mission's initial state: clean plugins, routing back to takeoff
    rebuild_graph();
    for (auto idx : order_) {
      try {
        instances_[idx]->plugin->reset();
      } catch (const std::exception& e) {
        logger_->error("{}.reset failed: {}", instances_[idx]->cfg.name, e.what());
      }
      const Nanos budget = instances_[idx]->stats.budget_ns;
      instances_[idx]->stats = StepStats{};
      instances_[idx]->stats.budget_ns = budget;
    }
  }
  ++flights_;
  FlightResult r;
  g_stop_signal.store(0);
  // ---- log directory
  {
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", &tm);
    const fs::path parent = options_.log_dir ? fs::absolute(*options_.log_dir) : config_.log.dir;
    fs::path dir = parent / (std::string(stamp) + "-" + config_.name);
    for (int k = 2; fs::exists(dir); ++k) dir = parent / fmt::format("{}-{}-{}", stamp, config_.name, k);
    r.run_dir = dir;
  }
  FlightLog log(r.run_dir, [this](const std::string& line) { logger_->error("{}", line); });
  auto file_sink = log.text_sink("tern.log");
  auto* dist = static_cast<spdlog::sinks::dist_sink_mt*>(extra_sinks_.front().get());
  dist->add_sink(file_sink);
  struct SinkGuard {
    spdlog::sinks::dist_sink_mt* d;
    std::shared_ptr<spdlog::sinks::sink> s;
    ~SinkGuard() { d->remove_sink(s); s->flush(); }
  } guard{dist, file_sink};

  log.write_file("config.yaml", resolved_config_yaml());
  for (const auto& [name, p] : parameters()) {
    const bool set = !(p->value() == p->default_value());
    log.param(0, name, param_text(p->value()), set ? "config" : "default");
  }
  // topics to log
  std::set<std::string> wanted(config_.log.topics.begin(), config_.log.topics.end());
  for (auto& tp : topics_) {
    if (tp->writers.empty() && !tp->host_writer) continue;
    if (!config_.log.all_topics && !wanted.count(tp->name)) continue;
    tp->log_index = log.add_topic(tp->name, tp->columns, tp->msg_size);
    tp->logged_src = nullptr;
    tp->logged_seq = 0;
    // raw sensor topics (and the actuators, an input of the estimator's side-force model) are
    // logged in full by default, so that a flight can be replayed
    static const std::set<std::string> kReplayInputs = {"imu", "gnss", "baro", "diff_pressure", "mag", "rc", "fcu_status", "actuators"};
    auto rate_it = config_.log.rates.find(tp->name);
    const double max_rate = rate_it != config_.log.rates.end() ? rate_it->second
                            : kReplayInputs.count(tp->name)        ? 0.0
                                                              : config_.log.max_rate;
    tp->log_interval = max_rate > 0 ? static_cast<Nanos>(std::llround(1e9 / max_rate)) : 0;
    tp->logged_t = std::numeric_limits<Nanos>::min() / 2;
  }
  for (const auto& w : wanted) {
    bool found = false;
    for (auto& tp : topics_) found = found || (tp->name == w && !tp->writers.empty());
    if (!found) logger_->warn("{}: log.topics: no instance publishes topic '{}'", config_.file.string(), w);
  }

  const double duration = duration_override_ ? *duration_override_ : options_.duration.value_or(config_.duration);
  const Nanos end = from_seconds(duration);
  logger_->info("flight '{}': {} instances, base rate {} Hz, {} s, seed {}, log {}", config_.name, instances_.size(),
                1e9 / static_cast<double>(base_period_), duration, seed_, r.run_dir.string());

  apply_start_only_requests(log);  // asked for between flights: before the plugins read them
  // ---- start
  handovers_.clear();
  fallback_engaged_ = false;
  last_good_ = msg::Actuators{};
  for (auto idx : order_) {
    try {
      instances_[idx]->plugin->start();
    } catch (const std::exception& e) {
      r.ok = false;
      r.end_reason = fmt::format("error: {}.start failed: {}", instances_[idx]->cfg.name, e.what());
      logger_->error("{}", r.end_reason);
      log.close();
      r.log_error = log.error();
      return r;
    }
  }
  if (phase_machine_) phase_seen_ = phase_machine_->outputs().front()->sequence();
  if (phase_machine_ && phase_machine_->phase() == msg::Phase::preflight)
    route_none(0, "preflight: on the ground until the arming checks pass");

  // status line sources
  const msg::State* st = nullptr;
  const msg::FlightPhase* ph = nullptr;
  const msg::CurrentPath* cp = nullptr;
  for (auto& tp : topics_) {
    if (!tp->current) continue;
    if (tp->name == "state" && tp->fingerprint == reflect::fingerprint<msg::State>()) st = static_cast<const msg::State*>(tp->current->data());
    if (tp->name == "flight_phase" && tp->fingerprint == reflect::fingerprint<msg::FlightPhase>()) ph = static_cast<const msg::FlightPhase*>(tp->current->data());
    if (tp->name == "current_path" && tp->fingerprint == reflect::fingerprint<msg::CurrentPath>()) cp = static_cast<const msg::CurrentPath*>(tp->current->data());
  }
  const bool progress = options_.progress && isatty(STDOUT_FILENO);
  const OutputBase* actuators_src = nullptr;  // active controller's actuators (checked for NaN)
  auto find_actuators = [&]() -> const OutputBase* {
    if (!active_) return nullptr;
    for (auto* o : instances_[*active_]->plugin->outputs())
      if (o->topic() == "actuators" && o->type().fingerprint == reflect::fingerprint<msg::Actuators>()) return o;
    return nullptr;
  };
  actuators_src = find_actuators();

  const std::int64_t wall0 = wall_ns(), cpu0 = thread_cpu_ns();
  start_to_first_tick_ms_ = static_cast<double>(wall0 - created_ns_) * 1e-6;
  flight_start_ms_ = static_cast<double>(wall0 - fly_entry) * 1e-6;
  std::int64_t last_flush = wall0, last_progress = wall0;
  std::int64_t tick = 0;
  Nanos now = 0;
  r.end_reason = "duration";
  for (;; ++tick) {
    now = tick * base_period_;
    if (now > end) {
      now = (tick - 1) * base_period_;
      break;
    }
    if (const int sig = g_stop_signal.load(std::memory_order_relaxed)) {
      r.end_reason = sig == SIGTERM ? "SIGTERM" : sig == SIGHUP ? "SIGHUP" : "SIGINT";
      now = tick > 0 ? (tick - 1) * base_period_ : 0;
      break;
    }
    if (param_pending_.load(std::memory_order_acquire)) {
      std::vector<ParamRequest> reqs;
      std::vector<msg::MissionEdit> edits;
      {
        std::lock_guard lk(param_mu_);
        reqs.swap(param_requests_);
        edits.swap(mission_edits_);
        param_pending_.store(false, std::memory_order_relaxed);
      }
      // one edit per tick reaches the planner (a port holds the latest message): keep the rest queued
      if (!edits.empty()) {
        msg::MissionEdit e = edits.front();
        e.stamp = now;
        mission_edit_out_->publish(e);
        logger_->info("t={:.3f} s: mission edit #{} (op {})", to_seconds(now), e.id, static_cast<int>(e.op));
        if (edits.size() > 1) {
          std::lock_guard lk(param_mu_);
          mission_edits_.insert(mission_edits_.begin(), edits.begin() + 1, edits.end());
          param_pending_.store(true, std::memory_order_relaxed);
        }
      }
      for (auto& rq : reqs) {
        try {
          rq.param->set(rq.value);
          log.param(now, rq.name, param_text(rq.param->value()), rq.source);
          logger_->info("t={:.3f} s: {} = {} ({})", to_seconds(now), rq.name, to_string(rq.param->value()), rq.source);
        } catch (const std::exception& e) {
          logger_->error("t={:.3f} s: {} not changed: {}", to_seconds(now), rq.name, e.what());
        }
      }
    }
    bool failed = false;
    step_clock_ = cycle_clock().now();
    for (auto idx : order_) {
      Instance& inst = *instances_[idx];
      if (inst.routed && (!active_ || *active_ != idx)) continue;
      const bool due = inst.trigger ? inst.trigger->updated() : (tick % inst.divisor == 0);
      if (!due) continue;
      std::string err;
      const bool ok = step_instance(inst, now, err);
      if (inst.routed) {
        const auto* a = actuators_src ? static_cast<const msg::Actuators*>(actuators_src->data()) : nullptr;
        std::string why;
        if (!ok) {
          why = fmt::format("{}.step threw: {}", inst.cfg.name, err);
        } else if (a && !(std::isfinite(a->delta_a) && std::isfinite(a->delta_e) && std::isfinite(a->delta_r) && std::isfinite(a->delta_t))) {
          why = fmt::format("{} commanded a non-finite actuator value (delta_a {}, delta_e {}, delta_r {}, delta_t {})", inst.cfg.name,
                            a->delta_a, a->delta_e, a->delta_r, a->delta_t);
        } else if (a && phase_machine_) {
          const double lim = phase_machine_->max_deflection();
          if (std::fabs(a->delta_a) > lim || std::fabs(a->delta_e) > lim || std::fabs(a->delta_r) > lim || a->delta_t < 0.0 ||
              a->delta_t > 1.0)
            why = fmt::format("{} commanded outside the actuator limits (delta_a {:.3f}, delta_e {:.3f}, delta_r {:.3f} rad: max {} rad; "
                              "delta_t {:.3f}: 0..1)", inst.cfg.name, a->delta_a, a->delta_e, a->delta_r, lim, a->delta_t);
        }
        if (!why.empty()) {
          if (fallback_ && !fallback_engaged_ && *fallback_ != idx) {
            engage_fallback(now, why);
            actuators_src = find_actuators();
            Instance& fb = *instances_[*fallback_];
            std::string err2;
            if (!step_instance(fb, now, err2)) {
              r.end_reason = fmt::format("error: fallback {}.step threw: {}", fb.cfg.name, err2);
              failed = true;
              break;
            }
          } else {
            r.end_reason = "error: " + why + " (no fallback controller left)";
            failed = true;
            break;
          }
        } else if (a) {
          last_good_ = *a;
        }
        continue;
      }
      if (!ok) {
        r.end_reason = fmt::format("error: {}.step threw at t={:.3f} s: {}", inst.cfg.name, to_seconds(now), err);
        failed = true;
        break;
      }
      if (idx == phase_machine_idx_ && !phase_machine_->failure().empty()) {
        r.end_reason = phase_machine_->failure();
        failed = true;
        break;
      }
      if (idx == phase_machine_idx_) {
        const OutputBase* po = phase_machine_->outputs().front();
        if (po->sequence() != phase_seen_) {
          phase_seen_ = po->sequence();
          if (!fallback_engaged_) {
            const msg::Phase p = phase_machine_->phase();
            auto it = config_.phases.find(p);
            if (it == config_.phases.end()) it = config_.phases.find(msg::Phase::cruise);
            if (phase_machine_->disarmed()) route_none(now, "disarmed: waiting for the FCU to be armed and error-free");
            else if (p == msg::Phase::preflight) route_none(now, "preflight: on the ground until the arming checks pass");
            else
              for (std::size_t i = 0; i < instances_.size(); ++i)
                if (instances_[i]->cfg.name == it->second) route_to(i, now, fmt::format("phase {}", msg::phase_name(p)), false);
            actuators_src = find_actuators();
          }
        }
      }
    }
    // log what was published this tick
    for (auto& tp : topics_) {
      if (tp->log_index == SIZE_MAX || tp->current == nullptr) continue;
      const std::uint64_t seq = tp->current->sequence();
      if (seq == 0 || (tp->current == tp->logged_src && seq == tp->logged_seq)) continue;
      if (now - tp->logged_t < tp->log_interval) continue;
      tp->logged_src = tp->current;
      tp->logged_seq = seq;
      tp->logged_t = now;
      log.capture(tp->log_index, now, tp->current->data());
    }
    if (tick_observer_) {
      try {
        tick_observer_(now);
      } catch (const std::exception& e) {
        logger_->error("t={:.3f} s: tick observer failed, removed: {}", to_seconds(now), e.what());
        tick_observer_ = nullptr;
      }
    }
    if (failed) {
      r.ok = false;
      logger_->error("{}", r.end_reason);
      break;
    }
    if ((tick & 63) == 0 || options_.realtime) {
      const std::int64_t w = wall_ns();
      if (w - last_flush > FlightLog::kFlushPeriodNs) {
        log.flush();
        logger_->flush();
        last_flush = w;
      }
      if (progress && w - last_progress > 250'000'000) {
        last_progress = w;
        std::string line = fmt::format("\r t {:8.2f} s", to_seconds(now));
        if (ph) line += fmt::format("  {:<8}", msg::phase_name(ph->phase));
        if (st) line += fmt::format("  h {:7.1f} m  Va {:5.1f} m/s", -st->p_d, st->Va);
        if (cp) line += fmt::format("  wp {:>3}", cp->waypoint_index);
        line += "   ";
        std::fwrite(line.data(), 1, line.size(), stdout);
        std::fflush(stdout);
      }
      if (options_.realtime) {
        const std::int64_t deadline = wall0 + now + base_period_;
        const std::int64_t wait = deadline - wall_ns();
        if (wait > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
      }
    }
  }
  if (progress) std::fputs("\n", stdout);
  r.flown = now;
  r.wall_s = static_cast<double>(wall_ns() - wall0) * 1e-9;
  r.flight_cpu_s = static_cast<double>(thread_cpu_ns() - cpu0) * 1e-9;
  for (auto it = order_.rbegin(); it != order_.rend(); ++it) {
    try {
      instances_[*it]->plugin->stop();
    } catch (const std::exception& e) {
      logger_->error("{}.stop failed: {}", instances_[*it]->cfg.name, e.what());
    }
  }
  if (r.end_reason == "SIGINT" || r.end_reason == "SIGTERM" || r.end_reason == "SIGHUP")
    logger_->warn("flight ended by {} at t={:.3f} s; the log is complete", r.end_reason, to_seconds(now));
  log.write_file("summary.json", summary_json(r));
  log.close();
  r.log_cpu_s = log.writer_cpu_s();
  log.write_file("timing.json", timing_json(r));
  r.log_error = log.error();
  if (!options_.quiet) print_summary(r);
  return r;
}

std::string Host::resolved_config_yaml() const {
  YAML::Node root = YAML::Clone(config_.root);
  // paths made absolute: the resolved config lives in the run directory, not beside the original
  if (!config_.aircraft.empty()) root["aircraft"] = config_.aircraft.string();
  if (root["plugin_path"]) {
    YAML::Node pp(YAML::NodeType::Sequence);
    for (const auto& d : config_.plugin_path) pp.push_back(d.string());
    root["plugin_path"] = pp;
  }
  if (root["log"] && root["log"]["dir"]) root["log"]["dir"] = config_.log.dir.string();
  if (root["mission"] && root["mission"].IsMap() && root["mission"]["file"] && root["mission"]["file"].IsScalar()) {
    const fs::path mf(root["mission"]["file"].Scalar());
    if (mf.is_relative()) root["mission"]["file"] = (config_.dir / mf).lexically_normal().string();
  }
  root["name"] = config_.name;
  root["seed"] = seed_;
  root["duration"] = duration_override_ ? *duration_override_ : options_.duration.value_or(config_.duration);
  for (const auto& inst : instances_) {
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
  return std::string("# resolved from ") + config_.file.string() + "\n" + e.c_str() + "\n";
}

// The simulator's sensor profile (the first instance with a `sensor_profile` parameter; in a
// replay, the recorded config.yaml's, which holds every effective value), "" if none.
std::string Host::sensor_profile() const {
  for (const auto& inst : instances_) {
    if (const ParamBase* p = inst->plugin->find_param("sensor_profile"); p != nullptr) {
      const ParamValue v = p->value();
      if (const auto* name = std::get_if<std::string>(&v)) return *name;
    }
  }
  for (const auto& inst : config_.plugins) {
    const auto it = inst.params.find("sensor_profile");
    if (it != inst.params.end() && it->second.node.IsScalar()) return it->second.node.as<std::string>();
  }
  return {};
}

std::string Host::summary_json(const FlightResult& r) const {
  nlohmann::ordered_json j;
  j["mission"] = config_.name;
  j["flight"] = flights_;
  j["seed"] = seed_;
  j["duration_s"] = to_seconds(r.flown);
  j["end_reason"] = r.end_reason;
  j["base_rate_hz"] = 1e9 / static_cast<double>(base_period_);
  if (const std::string profile = sensor_profile(); !profile.empty()) j["sensor_profile"] = profile;
  if (phase_machine_) {
    auto phases = nlohmann::ordered_json::array();
    phases.push_back({{"phase", std::string(msg::phase_name(phase_machine_->first_phase()))}, {"start_s", 0.0}, {"reason", "start of flight"}});
    for (const auto& t : phase_machine_->transitions()) {
      phases.push_back({{"phase", std::string(msg::phase_name(t.to))}, {"start_s", to_seconds(t.t)}, {"reason", t.reason}});
      if (t.from == msg::Phase::preflight && t.to == msg::Phase::takeoff && !j.contains("preflight_s"))
        j["preflight_s"] = to_seconds(t.t);  // how long the alignment and arming checks took
    }
    j["phases"] = phases;
    auto h = nlohmann::ordered_json::array();
    for (const auto& x : handovers_) h.push_back({{"t_s", to_seconds(x.t)}, {"from", x.from}, {"to", x.to}, {"reason", x.reason}});
    j["controller_handovers"] = h;
    j["fallback_engaged"] = fallback_engaged_;
  }
  auto inst_j = nlohmann::ordered_json::object();
  for (const auto& inst : instances_) {
    nlohmann::ordered_json x;
    x["plugin"] = inst->info.name;
    if (!inst->builtin) {
      x["library"] = inst->source.string();
      std::ifstream lib(inst->info.path, std::ios::binary);
      reflect::Fnv1a h;
      std::string bytes((std::istreambuf_iterator<char>(lib)), std::istreambuf_iterator<char>());
      h.bytes(bytes);
      x["library_fnv1a"] = fmt::format("{:016x}", h.h);
    }
    x["steps"] = inst->stats.steps;
    for (const auto& [k, v] : inst->plugin->summary()) x[k] = v;
    inst_j[inst->cfg.name] = x;
  }
  j["instances"] = inst_j;
  if (metrics_) {
    nlohmann::ordered_json m;
    m["loops"] = metrics_->loops();
    m["max_cross_track_m"] = metrics_->max_cross_track();
    m["max_altitude_error_m"] = metrics_->max_altitude_error();
    m["window_start_s"] = metrics_->window_start() < 0 ? nlohmann::ordered_json() : nlohmann::ordered_json(to_seconds(metrics_->window_start()));
    auto passages = nlohmann::ordered_json::array();
    for (const auto& p : metrics_->passages()) passages.push_back({{"t_s", to_seconds(p.t)}, {"waypoint", p.index}});
    m["waypoint_passages"] = passages;
    auto rms = [](const FlightMetrics::Rms& r) { return r.n ? nlohmann::ordered_json(r.value()) : nlohmann::ordered_json(); };
    if (metrics_->has_truth()) {
      m["estimation_frame"] = "truth (the estimator's origin mapped to the simulator's)";
      nlohmann::ordered_json e;
      for (int i = 0; i < FlightMetrics::kEst; ++i) e[FlightMetrics::kEstNames[i]] = rms(metrics_->estimation()[i]);
      m["estimation_rmse"] = e;
      if (metrics_->has_gnss()) {
        nlohmann::ordered_json g;
        for (int i = 0; i < FlightMetrics::kGnss; ++i) g[FlightMetrics::kEstNames[i]] = rms(metrics_->raw_gnss()[i]);
        m["raw_gnss_rmse"] = g;
      }
    }
    nlohmann::ordered_json t;
    for (int i = 0; i < FlightMetrics::kTrk; ++i) t[FlightMetrics::kTrkNames[i]] = rms(metrics_->tracking()[i]);
    m["tracking_rmse"] = t;
    j["metrics"] = m;
  }
  return j.dump(2) + "\n";
}

std::string Host::timing_json(const FlightResult& r) const {
  nlohmann::ordered_json j;
  j["wall_s"] = r.wall_s;
  j["real_time_factor"] = r.wall_s > 0 ? to_seconds(r.flown) / r.wall_s : 0.0;
  j["start_to_first_tick_ms"] = start_to_first_tick_ms_;
  // where the time went: the flight thread (plugins and host loop) and the log writer thread
  j["flight_thread_cpu_s"] = r.flight_cpu_s;
  j["flight_thread_real_time_factor"] = r.flight_cpu_s > 0 ? to_seconds(r.flown) / r.flight_cpu_s : 0.0;
  j["log_writer_cpu_s"] = r.log_cpu_s;
  auto inst_j = nlohmann::ordered_json::object();
  for (const auto& inst : instances_) {
    const auto& s = inst->stats;
    inst_j[inst->cfg.name] = {{"steps", s.steps},
                              {"mean_ns", s.steps ? static_cast<double>(s.total_ns) / static_cast<double>(s.steps) : 0.0},
                              {"median_ns", s.percentile(0.5)},
                              {"p99_ns", s.percentile(0.99)},
                              {"max_ns", s.max_ns},
                              {"budget_ns", s.budget_ns},
                              {"overruns", s.overruns}};
  }
  j["instances"] = inst_j;
  return j.dump(2) + "\n";
}

void Host::print_summary(const FlightResult& r) const {
  std::string s = fmt::format("\nflight '{}' ended ({}) at t = {:.2f} s after {:.2f} s wall ({:.0f}x real time)\n", config_.name,
                              r.end_reason, to_seconds(r.flown), r.wall_s, r.wall_s > 0 ? to_seconds(r.flown) / r.wall_s : 0.0);
  if (phase_machine_) {
    s += fmt::format("phases: {} @ 0.00 s", msg::phase_name(phase_machine_->first_phase()));
    for (const auto& t : phase_machine_->transitions()) s += fmt::format(", {} @ {:.2f} s", msg::phase_name(t.to), to_seconds(t.t));
    s += "\n";
  }
  s += fmt::format("  {:<16} {:>9} {:>10} {:>10} {:>10} {:>9}\n", "instance", "steps", "median", "p99", "max", "overruns");
  for (const auto& inst : instances_) {
    const auto& st = inst->stats;
    s += fmt::format("  {:<16} {:>9} {:>10} {:>10} {:>10} {:>9}\n", inst->cfg.name, st.steps, fmt_ns(st.percentile(0.5)),
                     fmt_ns(st.percentile(0.99)), fmt_ns(st.max_ns), st.overruns);
    if (inst->plugin.get() != metrics_)
      for (const auto& [k, v] : inst->plugin->summary()) s += fmt::format("      {} = {:.6g}\n", k, v);
  }
  if (metrics_) {
    auto v = [](const FlightMetrics::Rms& x) { return x.n ? fmt::format("{:.2f}", x.value()) : std::string("-"); };
    const auto& t = metrics_->tracking();
    bool tracked = false;
    for (const auto& x : t) tracked = tracked || x.n > 0;
    if (tracked) {
    s += fmt::format("\nRMS tracking error, command vs estimate ({} loops; window from {}):\n", metrics_->loops(),
                     metrics_->window_start() < 0 ? std::string("never: no full loop") : fmt::format("{:.1f} s", to_seconds(metrics_->window_start())));
    const std::string row7 = "  {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}";
    s += fmt::format(fmt::runtime(row7 + "\n"), "north m", "east m", "altitude m", "roll deg", "pitch deg", "course deg", "airspeed m/s");
    s += fmt::format(fmt::runtime(row7 + "   tern\n"), v(t[0]), v(t[1]), v(t[2]), v(t[3]), v(t[4]), v(t[5]), v(t[6]));
    s += fmt::format(fmt::runtime(row7 + "   ROSplane 2.0 flight test\n"), "3.05", "3.29", "1.19", "7.55", "3.04", "8.51", "0.58");
    }
    if (metrics_->has_truth()) {
      const auto& e = metrics_->estimation();
      const std::string profile = sensor_profile();
      s += fmt::format("RMS estimation error, estimate vs truth in the simulator's frame (sensor profile: {}):\n",
                       profile.empty() ? "not a tern simulator" : profile);
      const std::string row8 = "  {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}";
      s += fmt::format(fmt::runtime(row8 + "\n"), "north m", "east m", "altitude m", "roll deg", "pitch deg", "heading deg", "course deg", "airspeed m/s");
      s += fmt::format(fmt::runtime(row8 + "   tern\n"), v(e[0]), v(e[1]), v(e[2]), v(e[3]), v(e[4]), v(e[5]), v(e[6]), v(e[7]));
      if (metrics_->has_gnss()) {
        const auto& g = metrics_->raw_gnss();
        s += fmt::format(fmt::runtime(row8 + "   raw GNSS (latest fix vs truth)\n"), v(g[0]), v(g[1]), v(g[2]), "", "", "", "", "");
      }
      s += fmt::format(fmt::runtime(row8 + "   ROSplane 2.0 paper (its estimator, its flight: a reference, not a comparison)\n"),
                       "0.325", "0.258", "0.894", "0.189", "0.074", "-", "0.112", "-");
    }
    s += fmt::format("waypoints reached: {}\n", metrics_->passages().size());
  }
  s += fmt::format("log: {}\n", r.run_dir.string());
  std::fputs(s.c_str(), stdout);
  std::fflush(stdout);
}

}  // namespace tern::core
