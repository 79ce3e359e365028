// bench_flight: the whole stack flying the default mission, as `tern fly` runs it.
//   real-time factor, one core (target >= 1000x)
//   per-instance step cost, median and p99 (target: estimator + controller + path <= 10 us median per IMU tick)
//   peak resident memory of `tern fly` (target <= 50 MB)
// Prints a table and writes bench/results/bench_flight.json.
#include <sched.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  const std::string mission = argc > 1 ? argv[1] : std::string(TERN_SOURCE_DIR) + "/configs/missions/default.yaml";
  std::string tmpl = (fs::temp_directory_path() / "tern_bench_flight_XXXXXX").string();
  if (::mkdtemp(tmpl.data()) == nullptr) {
    std::fprintf(stderr, "bench_flight: mkdtemp failed in %s\n", fs::temp_directory_path().c_str());
    return 1;
  }
  const fs::path logs = tmpl;
  const pid_t pid = fork();
  if (pid == 0) {
    // one core, as the target says
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(0, &set);
    sched_setaffinity(0, sizeof set, &set);
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    execl(TERN_BIN, TERN_BIN, "fly", mission.c_str(), "--log-dir", logs.c_str(), "-q", static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  rusage ru{};
  wait4(pid, &status, 0, &ru);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::fprintf(stderr, "bench_flight: tern fly failed (status %d)\n", status);
    return 1;
  }
  fs::path run;
  for (const auto& e : fs::directory_iterator(logs)) run = e.path();
  std::ifstream tf(run / "timing.json");
  const auto timing = nlohmann::json::parse(tf);
  const double rtf = timing["real_time_factor"].get<double>();
  const double peak_mb = static_cast<double>(ru.ru_maxrss) / 1024.0;

  nlohmann::ordered_json j;
  j["mission"] = mission;
  j["real_time_factor"] = rtf;
  j["wall_s"] = timing["wall_s"];
  // where the one core's time went: the flight thread (plugins, host loop) and the log writer
  const double flight_cpu = timing["flight_thread_cpu_s"].get<double>(), log_cpu = timing["log_writer_cpu_s"].get<double>();
  j["flight_thread_cpu_s"] = flight_cpu;
  j["flight_thread_real_time_factor"] = timing["flight_thread_real_time_factor"];
  j["log_writer_cpu_s"] = log_cpu;
  j["peak_rss_mb"] = peak_mb;
  std::printf("%-24s %10s %10s %10s %12s\n", "instance", "steps", "median", "p99", "mean");
  double per_imu_tick = 0;
  for (auto& [name, s] : timing["instances"].items()) {
    std::printf("%-24s %10llu %8lld ns %8lld ns %10.0f ns\n", name.c_str(), s["steps"].get<unsigned long long>(),
                s["median_ns"].get<long long>(), s["p99_ns"].get<long long>(), s["mean_ns"].get<double>());
    j["instances"][name] = s;
  }
  // estimator + controller + path, per IMU tick: each instance's median cost times its steps per IMU step
  const auto& in = timing["instances"];
  const double imu_steps = in.contains("ekf") ? in["ekf"]["steps"].get<double>() : 1.0;
  for (const char* n : {"ekf", "slc", "tecs", "planner", "manager", "follower"}) {
    if (!in.contains(n)) continue;
    per_imu_tick += in[n]["median_ns"].get<double>() * in[n]["steps"].get<double>() / imu_steps;
  }
  j["estimator_controller_path_ns_per_imu_tick"] = per_imu_tick;
  j["targets"] = {{"real_time_factor", 1000}, {"estimator_controller_path_ns_per_imu_tick", 10000}, {"peak_rss_mb", 50}};
  std::printf("\n%-52s %12s %10s\n", "figure", "measured", "target");
  std::printf("%-52s %11.0fx %10s\n", "real-time factor, default mission, one core", rtf, ">= 1000x");
  std::printf("%-52s %9.2f s  %10s\n", "  of which flight thread CPU (plugins, host loop)", flight_cpu, "");
  std::printf("%-52s %9.2f s  %10s\n", "  of which log writer CPU (CSV rows, writes)", log_cpu, "");
  std::printf("%-52s %11.0fx %10s\n", "flight thread alone (log writer on another core)",
              timing["flight_thread_real_time_factor"].get<double>(), "");
  std::printf("%-52s %9.0f ns %10s\n", "estimator + controller + path per IMU tick (median)", per_imu_tick, "<= 10 us");
  std::printf("%-52s %9.1f MB %10s\n", "peak memory of tern fly", peak_mb, "<= 50 MB");
  fs::create_directories(fs::path(TERN_SOURCE_DIR) / "bench" / "results");
  std::ofstream(fs::path(TERN_SOURCE_DIR) / "bench" / "results" / "bench_flight.json") << j.dump(2) << "\n";
  fs::remove_all(logs);
  return 0;
}
