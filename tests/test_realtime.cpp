// A paced flight's real-time figures and thread settings (core/host/graph/realtime.hpp): the
// statistics on hand-made ticks, the settings the system refuses as one line, and `tern fly
// --realtime` reporting them in summary.json and on the console (no timing thresholds here: the
// figures of this machine are bench material, docs/companion-computer.md).
#include <chrono>

#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include "graph/realtime.hpp"
#include "test_process.hpp"
#include "test_util.hpp"

using namespace tern::core;

TEST_CASE("real time: ticks, misses, wake-up latency and work from hand-made ticks") {
  RealtimeStats s;
  s.begin(0);
  // tick 1: 100 us of work, its end at 2.5 ms, woken 60 us late
  CHECK_FALSE(s.work_done(100'000, 2'500'000));
  s.woke(2'560'000, 2'500'000);
  // tick 2: 3 ms of work from 2.56 ms: past its end at 5 ms, a miss, no sleep
  CHECK(s.work_done(5'560'000, 5'000'000));
  // tick 3: starts at 5.56 ms, 40 us of work, woken 20 us late at 7.5 ms
  CHECK_FALSE(s.work_done(5'600'000, 7'500'000));
  s.woke(7'520'000, 7'500'000);
  s.end();
  CHECK(s.ticks() == 3);
  CHECK(s.misses() == 1);
  CHECK(s.work().max_ns == 3'000'000);
  CHECK(s.wake_up().steps == 2);
  CHECK(s.wake_up().max_ns == 60'000);
  const auto j = s.to_json(RealtimeOptions{});
  CHECK(j["ticks"] == 3);
  CHECK(j["deadline_misses"] == 1);
  CHECK(j["deadline_miss_share"].get<double>() == doctest::Approx(1.0 / 3.0));
  CHECK(j["wake_up_latency"]["max_us"].get<double>() == doctest::Approx(60.0));
  CHECK(j["work_per_tick"]["max_us"].get<double>() == doctest::Approx(3000.0));
  CHECK(j["scheduling"] == "SCHED_OTHER, any CPU, memory not locked");
  CHECK(s.line(RealtimeOptions{}).find("3 ticks, 1 deadline misses (33.333 %)") != std::string::npos);
}

TEST_CASE("real time: a setting the system refuses is one line naming the option") {
  RealtimeOptions cpu;
  cpu.cpu = 100000;
  CHECK(apply_realtime(cpu).rfind("--cpu 100000: ", 0) == 0);
  RealtimeOptions prio;
  prio.priority = 100;
  CHECK(apply_realtime(prio).rfind("--rt-priority 100: SCHED_FIFO priorities on this system are 1..99", 0) == 0);
  CHECK(apply_realtime(RealtimeOptions{}).empty());
  CHECK(describe(prio) == "SCHED_FIFO 100, any CPU, memory not locked");
}

TEST_CASE("real time: tern fly --realtime reports the figures in summary.json and on the console; an unpaced flight does not") {
  const std::string mission = std::string(TERN_TEST_CONFIG_DIR) + "/../../configs/missions/default.yaml";
  const fs::path out = test_dir() / "rt.out";
  REQUIRE(run_tern({"fly", mission, "--duration", "1", "--realtime", "--log-dir", (test_dir() / "rt_runs").string()}, out) == 0);
  const std::string text = read_file(out);
  CHECK(text.find("real time: SCHED_OTHER, any CPU, memory not locked; 401 ticks, ") != std::string::npos);
  fs::path run;
  for (const auto& e : fs::directory_iterator(test_dir() / "rt_runs")) run = e.path();
  const auto s = nlohmann::json::parse(read_file(run / "summary.json"));
  REQUIRE(s.contains("realtime"));
  const auto& rt = s["realtime"];
  CHECK(rt["ticks"] == 401);
  CHECK(rt["deadline_misses"].get<int>() <= 401);
  CHECK(rt["wake_up_latency"]["samples"].get<int>() + rt["deadline_misses"].get<int>() == 401);
  CHECK(rt["wake_up_latency"]["p50_us"].get<double>() <= rt["wake_up_latency"]["max_us"].get<double>() * 1.19 + 1e-9);
  CHECK(rt["page_faults_major"].get<long>() >= 0);
  // an affinity the system refuses: the flight does not start, and says why in one line
  const fs::path bad = test_dir() / "rt_bad.out";
  CHECK(run_tern({"fly", mission, "--duration", "1", "--realtime", "--cpu", "1000", "-q", "--log-dir", (test_dir() / "rt_bad").string()},
                 bad) == 1);
  CHECK(read_file(bad).find("error: realtime: --cpu 1000: pthread_setaffinity_np failed") != std::string::npos);
  // without --realtime: no options, no figures
  CHECK(run_tern({"fly", mission, "--duration", "1", "--cpu", "0"}, test_dir() / "rt_no.out") != 0);
  REQUIRE(run_tern({"fly", mission, "--duration", "1", "-q", "--log-dir", (test_dir() / "plain").string()}, test_dir() / "plain.out") == 0);
  for (const auto& e : fs::directory_iterator(test_dir() / "plain")) run = e.path();
  CHECK_FALSE(nlohmann::json::parse(read_file(run / "summary.json")).contains("realtime"));
}

TEST_CASE("real time: --speed paces flight time at a multiple of wall time (PX4_SIM_SPEED_FACTOR); it needs --realtime") {
  const std::string mission = std::string(TERN_TEST_CONFIG_DIR) + "/../../configs/missions/default.yaml";
  const fs::path out = test_dir() / "speed.out";
  const auto t0 = std::chrono::steady_clock::now();
  REQUIRE(run_tern({"fly", mission, "--duration", "5", "--realtime", "--speed", "10", "--log-dir", (test_dir() / "speed_runs").string()},
                   out) == 0);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(read_file(out).find("real time: SCHED_OTHER, any CPU, memory not locked, 10x wall time; 2001 ticks, ") != std::string::npos);
  // paced: the last tick cannot end before 5 s / 10 of wall time (a lower bound only: no timing threshold)
  CHECK(wall_s >= 0.5);
  CHECK(run_tern({"fly", mission, "--duration", "1", "--speed", "10"}, test_dir() / "speed_alone.out") != 0);
  CHECK(run_tern({"fly", mission, "--duration", "1", "--realtime", "--speed", "0"}, test_dir() / "speed_zero.out") != 0);
}
