// tests/e2e_util.hpp: the shipped missions as the end-to-end tests fly and edit them.
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_util.hpp"

namespace tern::core {
inline const fs::path kMissions = fs::path(TERN_SOURCE_DIR) / "configs" / "missions";

inline FlightResult fly_mission(const std::string& mission, const std::string& logdir, std::optional<double> duration = {}) {
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / logdir;
  o.duration = duration;
  Host h(load_config(kMissions / mission), o);
  h.build();
  return h.fly();
}

/// configs/missions/<name> with its relative paths made absolute (so that it can be written
/// anywhere) and each (from, to) replacement applied once; a missing `from` fails.
inline std::string mission_with(const std::string& name, const std::vector<std::pair<std::string, std::string>>& edits) {
  std::string text = read_file(kMissions / name);
  const std::vector<std::pair<std::string, std::string>> paths = {
      {"../aircraft/", (kMissions / "../aircraft/").lexically_normal().string()},
      {"../gains/", (kMissions / "../gains/").lexically_normal().string()},
      {"file: fixedwing_mission.yaml", "file: " + (kMissions / "fixedwing_mission.yaml").string()}};
  for (const auto& [from, to] : paths) {
    const auto at = text.find(from);
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  for (const auto& [from, to] : edits) {
    const auto at = text.find(from);
    REQUIRE_MESSAGE(at != std::string::npos, name << " has no '" << from << "'");
    text.replace(at, from.size(), to);
  }
  return text;
}

/// configs/missions/default.yaml as mission_with gives it.
inline std::string default_mission_with(const std::vector<std::pair<std::string, std::string>>& edits) {
  return mission_with("default.yaml", edits);
}

/// `text` (default.yaml as mission_with gives it) without its landing: the mission section's
/// `loops:` line through its land item, so that the mission file flies alone (e.g. a file that ends
/// with a return_home, after which no land item is reached).
inline std::string without_landing(std::string text) {
  const auto from = text.find("  loops: ");
  const auto land = text.find("type: land", from);
  REQUIRE_MESSAGE((from != std::string::npos && land != std::string::npos), "default.yaml has no loops: and land item");
  text.erase(from, text.find('\n', land) + 1 - from);
  return text;
}

// default.yaml's estimator installation (the realistic profile's lever arms), and the rosflight
// profile's (IMU and antenna at the CG): a test that flies the rosflight profile swaps them.
inline const std::string kLeverArms = "      gnss_antenna_position: [-0.1, 0.0, -0.08]\n      imu_position: [0.05, 0.0, 0.02]\n";
inline const std::string kNoLeverArms = "      gnss_antenna_position: [0.0, 0.0, 0.0]\n      imu_position: [0.0, 0.0, 0.0]\n";

inline nlohmann::json summary(const FlightResult& r) { return nlohmann::json::parse(read_file(r.run_dir / "summary.json")); }

/// Writes `text` as the mission file `file` and flies it for `duration` s (quiet; logs under
/// test_dir() / logdir).
inline FlightResult fly_text(const std::string& text, const std::string& file, const std::string& logdir, double duration) {
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / logdir;
  o.duration = duration;
  Host h(load_config(write_file(file, text)), o);
  h.build();
  return h.fly();
}

/// The horizontal wind estimate's RMSE of a flight, m/s (summary.json's metrics).
inline double estimated_wind_rmse(const FlightResult& r) {
  const auto m = summary(r)["instances"]["metrics"];
  return std::hypot(m["est_rmse_wind_north_mps"].get<double>(), m["est_rmse_wind_east_mps"].get<double>());
}

}  // namespace tern::core
