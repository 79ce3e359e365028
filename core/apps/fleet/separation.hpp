// core/apps/fleet/separation.hpp: the minimum-distance monitor of a multi-vehicle flight.
//
// Every tick it takes each vehicle's position in one frame (the world's NED, m) twice: as the
// vehicle estimates it (what a conflict response may act on) and, in simulation, the truth (what
// the report quotes as what really happened). For every pair it keeps the closest approach (3-D
// distance, the pair, the flight time) and counts conflicts: a pair's estimated distance falling
// below `min_distance` starts one, rising above 1.1 min_distance ends it (the 10 % keeps one
// pass from counting many times). Plain C++: no host types.
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "fleet/fleet_config.hpp"
#include "tern/time.hpp"

namespace tern::core {

class SeparationMonitor {
 public:
  struct Closest {
    double distance = std::numeric_limits<double>::infinity();  ///< m, 3-D
    std::size_t a = 0, b = 0;                                   ///< the pair (vehicle indices, a < b)
    Nanos t = 0;                                                ///< flight time
    bool valid() const { return distance < std::numeric_limits<double>::infinity(); }
  };
  struct Conflict {
    std::size_t a = 0, b = 0;
    Nanos start = 0;
    double closest = 0;  ///< m, estimated, while it lasted
  };
  using Positions = std::vector<std::optional<Eigen::Vector3d>>;  ///< per vehicle; nullopt: none yet

  SeparationMonitor(std::vector<std::string> names, SeparationConfig config);
  /// One instant. Returns the conflicts that started now (pairs a < b).
  std::vector<std::pair<std::size_t, std::size_t>> observe(Nanos t, const Positions& estimated, const Positions& truth);
  const Closest& closest_estimated() const { return est_; }
  const Closest& closest_true() const { return truth_; }
  const std::vector<Conflict>& conflicts() const { return conflicts_; }
  /// summary.json's "separation": min_distance_m, response, conflicts, closest_approach (true
  /// and estimated: distance_m, pair, t_s), the conflicts' list.
  nlohmann::ordered_json report() const;

 private:
  std::size_t pair_index(std::size_t a, std::size_t b) const { return a * names_.size() + b; }
  nlohmann::ordered_json closest_json(const Closest& c) const;

  std::vector<std::string> names_;
  SeparationConfig config_;
  Closest est_, truth_;
  std::vector<Conflict> conflicts_;
  std::vector<int> open_;  ///< per pair: index into conflicts_ of the one going on, -1 none
};

}  // namespace tern::core
