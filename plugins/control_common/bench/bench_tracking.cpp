// bench_tracking: the ROSplane 2.0 paper's table "RMS errors between the commanded trajectory
// and the estimated state" (issue 5), flown in sim_aero as `tern fly` flies it:
//   configs/missions/default.yaml  successive loop closure (control_slc) in every phase
//   configs/missions/tecs.yaml     total energy control (control_tecs) in cruise
// Both: the RMRC Anaconda on the hourglass mission (fixedwing_mission.yaml) in 5 m/s wind from
// the south-east plus light turbulence, the EKF in the loop. The errors are the host's flight
// metrics (summary.json, instances.metrics.track_rmse_*): samples in cruise after the first
// loop; position from the estimated position to the closest point of the commanded segment,
// split into north and east; angles and airspeed: command minus estimate.
// Target: at most half of each ROSplane 2.0 hardware figure, for SLC and for TECS.
// Prints the table and writes bench/results/bench_tracking.json.
// Usage: bench_tracking [DEFAULT_CONFIG TECS_CONFIG]
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace fs = std::filesystem;

namespace {

struct Quantity {
  const char* name;  ///< row label
  const char* key;   ///< summary.json: instances.metrics.<key>
  const char* unit;
  double hardware;  ///< ROSplane 2.0 on hardware (the paper's table)
};

constexpr Quantity kQuantities[] = {
    {"north", "track_rmse_north_m", "m", 3.05},           {"east", "track_rmse_east_m", "m", 3.29},
    {"altitude", "track_rmse_altitude_m", "m", 1.19},     {"roll", "track_rmse_roll_deg", "deg", 7.55},
    {"pitch", "track_rmse_pitch_deg", "deg", 3.04},       {"course", "track_rmse_course_deg", "deg", 8.51},
    {"airspeed", "track_rmse_airspeed_mps", "m/s", 0.58},
};

/// Flies `config` with `tern fly` into a fresh directory under `logs`; returns the run's
/// summary.json, or nothing (with a message) when the flight failed.
std::optional<nlohmann::json> fly(const std::string& config, const fs::path& logs) {
  const pid_t pid = fork();
  if (pid < 0) {
    std::fprintf(stderr, "bench_tracking: fork failed\n");
    return std::nullopt;
  }
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    execl(TERN_BIN, TERN_BIN, "fly", config.c_str(), "--log-dir", logs.c_str(), "-q", static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::fprintf(stderr, "bench_tracking: tern fly %s failed (status %d)\n", config.c_str(), status);
    return std::nullopt;
  }
  fs::path run;
  for (const auto& e : fs::directory_iterator(logs))
    if (e.is_directory()) run = e.path();
  std::ifstream in(run / "summary.json");
  if (run.empty() || !in) {
    std::fprintf(stderr, "bench_tracking: no summary.json under %s\n", logs.c_str());
    return std::nullopt;
  }
  return nlohmann::json::parse(in);
}

double metric(const nlohmann::json& summary, const char* key) {
  const auto& m = summary["instances"]["metrics"];
  return m.contains(key) && m[key].is_number() ? m[key].get<double>() : std::nan("");
}

}  // namespace

int main(int argc, char** argv) {
  const std::string missions = std::string(TERN_SOURCE_DIR) + "/configs/missions/";
  const std::string configs[2] = {argc > 2 ? argv[1] : missions + "default.yaml", argc > 2 ? argv[2] : missions + "tecs.yaml"};
  const char* labels[2] = {"SLC", "TECS"};

  std::string tmpl = (fs::temp_directory_path() / "tern_bench_tracking_XXXXXX").string();
  if (::mkdtemp(tmpl.data()) == nullptr) {
    std::fprintf(stderr, "bench_tracking: mkdtemp failed in %s\n", fs::temp_directory_path().c_str());
    return 1;
  }
  const fs::path logs = tmpl;
  nlohmann::json summaries[2];
  for (int i = 0; i < 2; ++i) {
    const fs::path dir = logs / labels[i];
    fs::create_directories(dir);
    auto s = fly(configs[i], dir);
    if (!s) {
      fs::remove_all(logs);
      return 1;
    }
    summaries[i] = std::move(*s);
  }
  fs::remove_all(logs);

  nlohmann::ordered_json j;
  j["source"] = "ROSplane 2.0 paper, RMS errors between the commanded trajectory and the estimated state (hardware)";
  j["conditions"] = "Anaconda, hourglass mission, 5 m/s wind from the south-east, light turbulence, EKF in the loop";
  for (int i = 0; i < 2; ++i) {
    const auto& m = summaries[i]["instances"]["metrics"];
    j["flights"][labels[i]] = {{"config", configs[i]},
                               {"seed", summaries[i]["seed"]},
                               {"duration_s", summaries[i]["duration_s"]},
                               {"loops", m.value("loops", 0.0)},
                               {"window_start_s", m.value("window_start_s", std::nan(""))},
                               {"fallback_engaged", summaries[i].value("fallback_engaged", false)}};
  }
  std::printf("RMS tracking errors, cruise after the first loop (%s, %g loops; %s, %g loops)\n\n", labels[0],
              j["flights"]["SLC"]["loops"].get<double>(), labels[1], j["flights"]["TECS"]["loops"].get<double>());
  std::printf("%-14s %22s %14s %10s %10s %6s\n", "quantity", "ROSplane 2.0 hardware", "target (half)", "SLC", "TECS", "met");
  bool all_met = true;
  for (const auto& q : kQuantities) {
    const double target = q.hardware / 2.0;
    const double v[2] = {metric(summaries[0], q.key), metric(summaries[1], q.key)};
    const bool met = v[0] <= target && v[1] <= target;  // false for NaN
    all_met = all_met && met;
    const std::string label = std::string(q.name) + " [" + q.unit + "]";
    std::printf("%-14s %22.2f %11s%.3f %10.3f %10.3f %6s\n", label.c_str(), q.hardware, "<= ", target, v[0], v[1], met ? "yes" : "NO");
    j["quantities"][q.name] = {{"unit", q.unit},
                               {"hardware", q.hardware},
                               {"target", target},
                               {"SLC", v[0]},
                               {"TECS", v[1]},
                               {"met", met},
                               {"SLC_margin", target - v[0]},
                               {"TECS_margin", target - v[1]}};
  }
  j["all_met"] = all_met;
  std::printf("\nall targets met: %s\n", all_met ? "yes" : "NO");
  const fs::path out = fs::path(TERN_SOURCE_DIR) / "bench" / "results";
  fs::create_directories(out);
  std::ofstream(out / "bench_tracking.json") << j.dump(2) << "\n";
  return 0;
}
