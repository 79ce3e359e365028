// core/host/flight/host_between_flights.cpp: what a served host changes between flights (host.hpp):
// a plugin swapped for another .so (or a rebuild of the same), a new phase -> controller table, a
// new seed.
#include <unistd.h>

#include <algorithm>
#include <cstdint>

#include <fmt/format.h>

#include "config/cli_overrides.hpp"
#include "config/error.hpp"
#include "graph/elf_check.hpp"
#include "flight/host.hpp"

namespace tern::core {

SwapReport Host::swap(const std::string& instance, const fs::path& so_in) {
  if (flying_) throw ConfigError("swap refused: a flight is in progress; swap between flights");
  std::size_t idx = SIZE_MAX;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    if (!instances_[i]->builtin) names.push_back(instances_[i]->cfg.name);
    if (instances_[i]->cfg.name == instance && !instances_[i]->builtin) idx = i;
  }
  if (idx == SIZE_MAX) throw ConfigError("swap: no plugin instance named '" + instance + "'" + did_you_mean(instance, names));
  fs::path so = so_in;
  if (so.string().find('/') == std::string::npos && so.extension() != ".so")
    so = find_plugin(so.string(), plugin_search_path(config_.plugin_path));
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
    configure_instance(*fresh, setup());
    if (fresh->cfg.isolate && !options_.describing) isolate_instance(*fresh, setup());
  } catch (const std::exception& e) {  // ConfigError, or a filesystem error of the copy
    fresh->drop_plugin();
    fresh->lib.reset();
    discard_copy();
    throw ConfigError("swap " + instance + " <- " + so.string() + " refused, '" + instances_[idx]->info.name +
                      "' keeps flying: " + e.what());
  }
  std::swap(instances_[idx], fresh);  // `fresh` is now the old instance
  try {
    rebuild_graph();
  } catch (const ConfigError& e) {
    std::swap(instances_[idx], fresh);
    rebuild_graph();
    fresh->drop_plugin();
    fresh->lib.reset();
    discard_copy();
    throw ConfigError("swap " + instance + " <- " + so.string() +
                      " refused (its ports do not fit the graph), the old plugin keeps flying: " + e.what());
  }
  // the new plugin took the config's values: what requests set on the old one is gone
  for (auto it = requested_sources_.lower_bound(instance + "."); it != requested_sources_.end() && it->first.rfind(instance + ".", 0) == 0;)
    it = requested_sources_.erase(it);
  if (idx == phase_machine_idx_) phase_machine_ = nullptr;  // (never: built-ins are not swappable)
  const fs::path old_path = fresh->lib ? fresh->lib->info().path : fs::path();
  const bool shared = fresh->lib && fresh->lib.use_count() > 1;
  const std::string old_desc = fmt::format("{} ({})", fresh->info.name, fresh->source.string());
  const SwapReport report{fresh->info.sha256, instances_[idx]->info.sha256};
  fresh->drop_plugin();
  fresh->lib.reset();
  if (!shared && !old_path.empty() && is_loaded(old_path))
    logger_->warn("swap {}: the old library {} is still mapped after unloading it", instance, old_path.string());
  if (!old_path.empty() && old_path.parent_path() == swap_dir_ && !shared) fs::remove(old_path);
  logger_->info("swapped {}: {} sha256 {} -> {} ({}) sha256 {}", instance, old_desc, report.old_sha256, instances_[idx]->info.name,
                so.string(), report.new_sha256);
  if (report.same())
    logger_->warn("swap {}: same library (sha256 {}) as the one running: did the build fail?", instance, report.new_sha256);
  return report;
}

bool Host::reseed(std::uint64_t seed) {
  if (flying_) throw ConfigError("reseed refused: a flight is in progress; change the seed between flights");
  for (const auto& inst : instances_)
    if (inst->isolated) return false;  // its child process took the seed when it was spawned
  seed_ = seed;
  for (auto& inst : instances_) reseed_instance(*inst, seed);
  return true;
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
    rebuild_graph();  // the router refuses phases and fallbacks that are not controllers
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

}  // namespace tern::core
