#include "fleet/separation.hpp"

#include <algorithm>
#include <cmath>

namespace tern::core {

namespace {

void keep_closest(SeparationMonitor::Closest& c, double d, std::size_t a, std::size_t b, Nanos t) {
  if (d < c.distance) c = {d, a, b, t};
}

}  // namespace

SeparationMonitor::SeparationMonitor(std::vector<std::string> names, SeparationConfig config)
    : names_(std::move(names)), config_(config), open_(names_.size() * names_.size(), -1) {}

std::vector<std::pair<std::size_t, std::size_t>> SeparationMonitor::observe(Nanos t, const Positions& estimated, const Positions& truth) {
  std::vector<std::pair<std::size_t, std::size_t>> started;
  const std::size_t n = names_.size();
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = a + 1; b < n; ++b) {
      if (a < truth.size() && b < truth.size() && truth[a] && truth[b]) keep_closest(truth_, (*truth[a] - *truth[b]).norm(), a, b, t);
      if (!estimated[a] || !estimated[b]) continue;
      const double d = (*estimated[a] - *estimated[b]).norm();
      if (!std::isfinite(d)) continue;
      keep_closest(est_, d, a, b, t);
      int& open = open_[pair_index(a, b)];
      if (open >= 0) {
        conflicts_[static_cast<std::size_t>(open)].closest = std::min(conflicts_[static_cast<std::size_t>(open)].closest, d);
        if (d > 1.1 * config_.min_distance) open = -1;
      } else if (d < config_.min_distance) {
        open = static_cast<int>(conflicts_.size());
        conflicts_.push_back({a, b, t, d});
        started.emplace_back(a, b);
      }
    }
  }
  return started;
}

nlohmann::ordered_json SeparationMonitor::closest_json(const Closest& c) const {
  if (!c.valid()) return nullptr;
  return {{"distance_m", c.distance}, {"pair", {names_[c.a], names_[c.b]}}, {"t_s", to_seconds(c.t)}};
}

nlohmann::ordered_json SeparationMonitor::report() const {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const auto& c : conflicts_)
    list.push_back({{"pair", {names_[c.a], names_[c.b]}}, {"t_s", to_seconds(c.start)}, {"closest_m", c.closest}});
  const Closest& quoted = truth_.valid() ? truth_ : est_;  // the truth in simulation
  return {{"min_distance_m", config_.min_distance},
          {"response", config_.response == SeparationConfig::Response::hold ? "hold" : "report"},
          {"closest_approach_m", quoted.valid() ? nlohmann::ordered_json(quoted.distance) : nlohmann::ordered_json(nullptr)},
          {"pair", quoted.valid() ? nlohmann::ordered_json{names_[quoted.a], names_[quoted.b]} : nlohmann::ordered_json(nullptr)},
          {"t_s", quoted.valid() ? nlohmann::ordered_json(to_seconds(quoted.t)) : nlohmann::ordered_json(nullptr)},
          {"from", truth_.valid() ? "truth" : "estimates"},
          {"closest_approach", {{"true", closest_json(truth_)}, {"estimated", closest_json(est_)}}},
          {"conflicts", conflicts_.size()},
          {"conflict_list", list}};
}

}  // namespace tern::core
