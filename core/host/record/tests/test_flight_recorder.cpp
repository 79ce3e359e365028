// FlightRecorder alone, on a port graph built here (no plugin, no flight): the run directory and
// its files, parameter sources, which messages are logged (sensors in full, other topics thinned
// to log.max_rate by flight time, nothing twice), tern.log taking the host's log only while the
// recorder lives, and durability: captured rows reach the disk (write(2), what a killed process
// keeps) when the recorder flushes, before the flight ends; summary.json and timing.json at the
// end, written whole (no temporary file left); a burst of messages in one tick logged whole.
#include <doctest/doctest.h>

#include <chrono>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>
#include <spdlog/sinks/dist_sink.h>
#include <spdlog/spdlog.h>

#include "record/flight_recorder.hpp"
#include "safety/phase_router.hpp"
#include "test_util.hpp"

using namespace tern;
using namespace tern::core;

namespace {

/// The rows (header excluded) of a CSV file, waiting up to 2 s for `want` of them (the log's
/// writer thread writes them).
std::vector<std::string> rows(const fs::path& csv, std::size_t want) {
  std::vector<std::string> r;
  for (int k = 0; k < 200; ++k) {
    r = lines(read_file(csv));
    if (!r.empty()) r.erase(r.begin());
    if (r.size() >= want) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return r;
}

/// A simulator's outputs in a one-node graph: imu (a sensor: logged in full) and state.
struct Sim {
  Sim() {
    imu.set_identity("imu", "");
    state.set_identity("state", "");
    graph = PortGraph({{"sim", true, false, {&imu, &state}, {}}}, {}, "/missions/m.yaml");
    graph.bind(std::nullopt);
  }
  Output<msg::Imu> imu;
  Output<msg::State> state;
  PortGraph graph;
};

struct Params {
  Params() {
    gain.init(2.0);
    gain.set_identity("gain", "ctl.gain", ParamSpec("", 0.0, 10.0, "set by the config"), 1.0);
    kp.init(0.5);
    kp.set_identity("kp", "ctl.kp", ParamSpec("", 0.0, 10.0, "left at its default"), 0.5);
    ki.init(0.1);
    ki.set_identity("ki", "ctl.ki", ParamSpec("", 0.0, 10.0, "set on the command line"), 0.1);
  }
  std::vector<std::pair<std::string, const ParamBase*>> list() const { return {{"ctl.gain", &gain}, {"ctl.kp", &kp}, {"ctl.ki", &ki}}; }
  Param<double> gain, kp, ki;
};

}  // namespace

TEST_CASE("flight recorder: run directory, config, parameter sources, topics thinned by flight time, tern.log, summary") {
  const fs::path parent = test_dir() / "recorder";
  auto sinks = std::make_shared<spdlog::sinks::dist_sink_mt>();
  auto host_log = std::make_shared<spdlog::logger>("tern", sinks);
  std::string write_error;
  Sim sim;
  Params params;
  MissionConfig config;
  config.name = "unit";
  config.log.level = LogLevel::full;
  config.log.max_rate = 10.0;  // Hz: state at most every 0.1 s of flight time; imu (a sensor) in full
  std::vector<std::unique_ptr<Instance>> no_instances;
  PortGraph no_graph;
  PhaseRouter router(no_instances, no_graph, host_log);
  const std::vector<FailsafeEvent> no_failsafes;
  FlightResult result;
  result.end_reason = "duration";
  result.flown = 400'000'000;
  fs::path dir;
  {
    FlightRecorder rec(new_run_dir(parent, "unit"), sinks, [&](const std::string& line) { write_error = line; });
    dir = rec.dir();
    CHECK(dir.parent_path() == parent);
    CHECK(dir.filename().string().size() > std::string("-unit").size());
    CHECK(dir.filename().string().substr(dir.filename().string().size() - 5) == "-unit");
    {
      FlightRecorder same_second(new_run_dir(parent, "unit"), sinks, {});  // a second run directory, never the same one
      CHECK(same_second.dir() != dir);
      FlightResult closed;
      same_second.close(closed);
    }

    rec.start("name: unit\nseed: 7\n", params.list(), {{"ctl.gain", "unit.yaml:4"}, {"ctl.ki", "--set ctl.ki=0.1"}});
    CHECK(read_file(dir / "config.yaml") == "name: unit\nseed: 7\n");
    rec.choose_topics(sim.graph, config.log, config.file, *host_log);
    host_log->info("while recording");

    for (Nanos k = 0; k < 20; ++k) {  // 20 ticks of 20 ms
      const Nanos now = k * 20'000'000;
      msg::Imu imu;
      imu.stamp = now;
      sim.imu.publish(imu);
      if (k != 7) {  // tick 7 publishes no state: nothing to log for it
        msg::State s;
        s.stamp = now;
        s.p_d = -static_cast<double>(k);
        sim.state.publish(s);
      }
      rec.capture(sim.graph, now);
      rec.capture(sim.graph, now);  // a second capture in the same tick logs nothing twice
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(60));  // past FlightLog::kFlushPeriodNs
    rec.flush_if_due(*host_log);

    // durability: the rows are in the files before the flight ends
    const auto imu_rows = rows(dir / "topics" / "imu.csv", 20);
    CHECK(imu_rows.size() == 20);
    const auto state_rows = rows(dir / "topics" / "state.csv", 4);
    REQUIRE(state_rows.size() == 4);  // t = 0, 0.1, 0.2, 0.3 s
    for (std::size_t i = 0; i < state_rows.size(); ++i) CHECK(std::stod(cells(state_rows[i])[0]) == doctest::Approx(0.1 * i));
    const auto param_rows = rows(dir / "params.csv", 3);
    REQUIRE(param_rows.size() == 3);
    CHECK(cells(param_rows[0])[1] == "ctl.gain");
    CHECK(cells(param_rows[0])[3] == "unit.yaml:4");
    CHECK(cells(param_rows[1])[3] == "default");
    CHECK(cells(param_rows[2])[3] == "--set ctl.ki=0.1");
    CHECK(read_file(dir / "tern.log").find("tern: while recording") != std::string::npos);

    const FlightFacts facts{config, 7, 0.4, 1, 20'000'000, no_instances, nullptr, router, nullptr, 0.0, no_failsafes};
    rec.finish(facts, result);
  }
  host_log->info("after the recorder");
  CHECK(read_file(dir / "tern.log").find("after the recorder") == std::string::npos);

  CHECK(lines(read_file(dir / "topics" / "imu.csv")).size() == 1 + 20);  // closed: every row once
  CHECK(write_error.empty());
  CHECK(result.log_error.empty());
  const auto summary = nlohmann::json::parse(read_file(dir / "summary.json"));
  CHECK(summary["mission"] == "unit");
  CHECK(summary["seed"] == 7);
  CHECK(summary["end_reason"] == "duration");
  CHECK(nlohmann::json::parse(read_file(dir / "timing.json")).contains("wall_s"));
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) files.insert(e.path().filename().string());
  CHECK(files ==
        std::set<std::string>{"config.yaml", "definitions.json", "params.csv", "summary.json", "timing.json", "tern.log", "topics"});
}

TEST_CASE("flight recorder: captured rows stay in memory until a flush hands them to the writer") {
  auto sinks = std::make_shared<spdlog::sinks::dist_sink_mt>();
  spdlog::logger host_log("tern", sinks);
  Sim sim;
  LogConfig log;
  FlightRecorder rec(new_run_dir(test_dir() / "unflushed", "unit"), sinks, {});
  rec.choose_topics(sim.graph, log, "/missions/m.yaml", host_log);
  sim.imu.publish(msg::Imu{});
  rec.capture(sim.graph, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  CHECK(lines(read_file(rec.dir() / "topics" / "imu.csv")).size() == 1);  // the header alone
  rec.flush_if_due(host_log);                                             // more than kFlushPeriodNs since the recorder began
  CHECK(rows(rec.dir() / "topics" / "imu.csv", 1).size() == 1);
}

TEST_CASE("flight recorder: log.level summary writes no topic table") {
  auto sinks = std::make_shared<spdlog::sinks::dist_sink_mt>();
  spdlog::logger host_log("tern", sinks);
  Sim sim;
  LogConfig log;
  log.level = LogLevel::summary;
  FlightRecorder rec(new_run_dir(test_dir() / "summary_only", "unit"), sinks, {});
  rec.choose_topics(sim.graph, log, "/missions/m.yaml", host_log);
  sim.imu.publish(msg::Imu{});
  rec.capture(sim.graph, 0);
  CHECK(fs::is_empty(rec.dir() / "topics"));
}

TEST_CASE("flight recorder: each log level's rate per topic (replay, the default: sensors in full, the rest at plot_rate)") {
  LogConfig log;
  CHECK(log.level == LogLevel::replay);
  CHECK(FlightRecorder::topic_rate(log, "imu") == 0.0);  // every message: what tern replay needs
  CHECK(FlightRecorder::topic_rate(log, "actuators") == 0.0);
  CHECK(FlightRecorder::topic_rate(log, "state") == log.plot_rate);
  CHECK(FlightRecorder::topic_rate(log, "truth") == log.plot_rate);
  log.level = LogLevel::sysid;
  CHECK(FlightRecorder::topic_rate(log, "truth") == 0.0);
  CHECK(FlightRecorder::topic_rate(log, "state") == 0.0);
  CHECK(FlightRecorder::topic_rate(log, "controller_command") == log.plot_rate);
  log.level = LogLevel::full;
  CHECK(FlightRecorder::topic_rate(log, "imu") == 0.0);
  CHECK(FlightRecorder::topic_rate(log, "state") == log.max_rate);
  log.level = LogLevel::decimated;
  CHECK(FlightRecorder::topic_rate(log, "imu") == log.decimated_rate);
  log.rates["imu"] = 5.0;  // an override below the cap stays
  CHECK(FlightRecorder::topic_rate(log, "imu") == 5.0);
  log.level = LogLevel::replay;
  log.rates["state"] = 0.0;
  CHECK(FlightRecorder::topic_rate(log, "state") == 0.0);
  // the ROS-typed copies at the plotting rate at levels replay and sysid, every message otherwise
  CHECK(FlightRecorder::format_of(log).mcap_ros_interval_ns == 100'000'000);
  log.level = LogLevel::full;
  CHECK(FlightRecorder::format_of(log).mcap_ros_interval_ns == 0);
  CHECK(log_level_names() == "summary, decimated, replay, sysid or full");
  CHECK(log_level_from_name("sysid") == LogLevel::sysid);
  CHECK(!log_level_from_name("default"));
}

TEST_CASE("flight recorder: a topic logged in full keeps every message of a burst; more than its writer held makes the log incomplete") {
  auto sinks = std::make_shared<spdlog::sinks::dist_sink_mt>();
  auto host_log = std::make_shared<spdlog::logger>("tern", sinks);
  Sim sim;
  MissionConfig config;
  config.name = "unit";  // log.level replay: imu in full, state at plot_rate
  std::vector<std::unique_ptr<Instance>> no_instances;
  PortGraph no_graph;
  PhaseRouter router(no_instances, no_graph, host_log);
  const std::vector<FailsafeEvent> no_failsafes;
  FlightResult result;
  fs::path dir;
  const std::vector<int> per_tick{3, 1, 0, 2, static_cast<int>(FlightRecorder::kBurstDepth) + 5, 1};
  Nanos stamp = 0;
  {
    FlightRecorder rec(new_run_dir(test_dir() / "bursts", "unit"), sinks, {});
    dir = rec.dir();
    rec.choose_topics(sim.graph, config.log, config.file, *host_log);
    for (std::size_t k = 0; k < per_tick.size(); ++k) {
      for (int i = 0; i < per_tick[k]; ++i) {
        msg::Imu imu;
        imu.stamp = ++stamp;  // 1, 2, 3 ...: every row says which message it is
        sim.imu.publish(imu);
        sim.state.publish(msg::State{});
      }
      rec.capture(sim.graph, static_cast<Nanos>(k) * 2'500'000);
    }
    const FlightFacts facts{config, 7, 0.015, 1, 2'500'000, no_instances, nullptr, router, nullptr, 0.0, no_failsafes};
    rec.finish(facts, result);
  }
  auto imu_rows = lines(read_file(dir / "topics" / "imu.csv"));
  imu_rows.erase(imu_rows.begin());
  const std::size_t held = FlightRecorder::kBurstDepth;
  REQUIRE(imu_rows.size() == 3 + 1 + 2 + held + 1);  // the 5 of the long burst its writer no longer held are missing
  std::vector<std::int64_t> stamps;
  for (const auto& r : imu_rows) stamps.push_back(std::stoll(cells(r)[1]));
  CHECK(stamps.front() == 1);
  CHECK(stamps[5] == 6);                                                  // the first six, in order
  CHECK(stamps[6] == 6 + 5 + 1);                                          // the long burst's last `held`
  CHECK(stamps.back() == stamp);                                          // and the last message
  CHECK(std::stod(cells(imu_rows[2])[0]) == 0.0);                         // a burst's rows carry the tick's flight time
  CHECK(lines(read_file(dir / "topics" / "state.csv")).size() == 1 + 1);  // thinned to plot_rate: the latest of the first tick
  CHECK(result.log_error.find("topic 'imu': 5 messages not logged") != std::string::npos);
}
