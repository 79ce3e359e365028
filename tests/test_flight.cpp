// Flights: determinism, the flight log, the phase router, SIGINT.
#include <doctest/doctest.h>

#include <signal.h>
#include <fcntl.h>
#include <sys/wait.h>

#include <chrono>
#include <thread>

#include <nlohmann/json.hpp>

#include "test_util.hpp"

using namespace tern::core;

namespace {

const std::string kRouted = base_config(
    "  - {name: ctl2, plugin: test_controller, rate: 100, params: {tag: 0.2, h_target: 30}}\n",
    "phases: {takeoff: ctl, climb: ctl, cruise: ctl2}\nfallback: ctl\nphase_machine: {alt_toz: 2, alt_hz: 3, preflight: false}\n");
}  // namespace

TEST_CASE("the same seed gives byte-identical logs; another seed does not") {
  const FlightResult a = fly_yaml(kRouted, "det_a", 11);
  const FlightResult b = fly_yaml(kRouted, "det_b", 11);
  const FlightResult c = fly_yaml(kRouted, "det_c", 12);
  REQUIRE(a.ok);
  REQUIRE(b.ok);
  int files = 0;
  for (const auto& e : fs::directory_iterator(a.run_dir / "topics")) {
    const std::string name = e.path().filename().string();
    CHECK_MESSAGE(read_file(e.path()) == read_file(b.run_dir / "topics" / name), name);
    ++files;
  }
  CHECK(files >= 6);  // imu, truth, state, actuators, controller_internals, flight_phase
  CHECK(read_file(a.run_dir / "summary.json") == read_file(b.run_dir / "summary.json"));
  CHECK(read_file(a.run_dir / "params.csv") == read_file(b.run_dir / "params.csv"));
  CHECK(read_file(a.run_dir / "topics" / "imu.csv") != read_file(c.run_dir / "topics" / "imu.csv"));
}

TEST_CASE("the flight log: header with units, one row per message, resolved config, parameters") {
  const FlightResult r = fly_yaml(base_config(), "log");
  REQUIRE(r.ok);
  const auto imu = lines(read_file(r.run_dir / "topics" / "imu.csv"));
  REQUIRE(imu.size() == 802);  // header + 801 samples over 2 s at 400 Hz
  CHECK(imu[0] ==
        "t [s],stamp [ns],accel_x [m/s^2],accel_y [m/s^2],accel_z [m/s^2],gyro_x [rad/s],gyro_y [rad/s],gyro_z [rad/s],temperature [K]");
  CHECK(imu[2].rfind("0.002500000,2500000,", 0) == 0);
  const auto act = lines(read_file(r.run_dir / "topics" / "actuators.csv"));
  CHECK(act.size() == 202);
  const std::string cfg = read_file(r.run_dir / "config.yaml");
  CHECK(cfg.find("climb_gain: 10") != std::string::npos);  // defaults resolved into the config
  const auto params = lines(read_file(r.run_dir / "params.csv"));
  CHECK(params[0] == "t [s],parameter,value,source");
  CHECK(std::find(params.begin(), params.end(), "0.000000000,ctl.kp,0.05,default") != params.end());
  CHECK(fs::exists(r.run_dir / "tern.log"));
  const auto timing = nlohmann::json::parse(read_file(r.run_dir / "timing.json"));
  CHECK(timing["instances"]["sensor"]["steps"] == 801);
}

TEST_CASE("params.csv: a value from the config is logged with its file and line, even at its default; a request's source lasts") {
  std::string yaml = base_config();
  yaml.replace(yaml.find("rate: 100}"), 10, "rate: 100, params: {kp: 0.05}}");  // kp's default, on line 8
  HostOptions o;
  o.quiet = true;
  o.duration = 0.1;
  o.log_dir = test_dir() / "param_sources";
  const fs::path file = write_file("param_sources.yaml", yaml);
  Host h(load_config(file), o);
  h.build();
  const FlightResult first = h.fly();
  REQUIRE(first.ok);
  const auto params = lines(read_file(first.run_dir / "params.csv"));
  CHECK(std::find(params.begin(), params.end(), "0.000000000,ctl.kp,0.05," + file.string() + ":8") != params.end());
  CHECK(std::find(params.begin(), params.end(), "0.000000000,ctl.h_target,30,default") != params.end());
  h.request_param("ctl.kp", 0.2, "console");  // between flights: applied at the next flight's first tick
  REQUIRE(h.fly().ok);
  const FlightResult third = h.fly();
  REQUIRE(third.ok);
  const auto later = lines(read_file(third.run_dir / "params.csv"));
  CHECK(std::find(later.begin(), later.end(), "0.000000000,ctl.kp,0.2,console") != later.end());
}

TEST_CASE("config.yaml of a host's later flights (a new seed, a changed parameter) is what a fresh host writes") {
  HostOptions o;
  o.quiet = true;
  o.duration = 0.05;
  o.log_dir = test_dir() / "resolved_runs";
  const fs::path file = write_file("resolved.yaml", kRouted);
  const auto fresh = [&](std::uint64_t seed, const std::string& yaml) {
    write_file("resolved.yaml", yaml);
    HostOptions f = o;
    f.seed = seed;
    Host h(load_config(file), f);
    h.build();
    const FlightResult r = h.fly();
    write_file("resolved.yaml", kRouted);
    return read_file(r.run_dir / "config.yaml");
  };
  Host h(load_config(file), o);
  h.build();
  REQUIRE(h.fly().ok);
  REQUIRE(h.reseed(11));
  const std::string second = read_file(h.fly().run_dir / "config.yaml");
  CHECK(second.find("\nseed: 11\n") != std::string::npos);
  CHECK(second == fresh(11, kRouted));
  h.request_param("ctl.kp", 0.2, "console");  // taken at the next flight's first tick
  REQUIRE(h.fly().ok);
  REQUIRE(h.reseed(123456789012));  // a longer seed than the text it replaces
  const std::string fourth = read_file(h.fly().run_dir / "config.yaml");
  std::string with_kp = kRouted;
  with_kp.replace(with_kp.find("rate: 100}"), 10, "rate: 100, params: {kp: 0.2}}");
  CHECK(fourth.find("kp: 0.2") != std::string::npos);
  CHECK(fourth == fresh(123456789012, with_kp));
  REQUIRE(h.reseed(5));
  CHECK(read_file(h.fly().run_dir / "config.yaml") == fresh(5, with_kp));
}

TEST_CASE("phase router: takeoff -> climb -> cruise hands actuators to the cruise controller") {
  const FlightResult r = fly_yaml(kRouted, "router");
  REQUIRE(r.ok);
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  REQUIRE(s["phases"].size() == 3);
  CHECK(s["phases"][1]["phase"] == "climb");
  CHECK(s["phases"][2]["phase"] == "cruise");
  CHECK(s["controller_handovers"].size() == 1);
  CHECK(s["controller_handovers"][0]["to"] == "ctl2");
  CHECK(s["instances"]["ctl2"]["take_overs"] == 1.0);
  CHECK(s["instances"]["ctl2"]["last_take_over_delta_t"].get<double>() > 0.5);  // ctl's last command: climbing
  // before the handover actuators carry ctl's tag (0), after it ctl2's (0.2)
  const auto act = lines(read_file(r.run_dir / "topics" / "actuators.csv"));
  CHECK(act[1].find(",0,") != std::string::npos);
  CHECK(act.back().find(",0.2,") != std::string::npos);
  CHECK(s["fallback_engaged"] == false);
}

TEST_CASE("phase router: a controller that throws or writes NaN is replaced by the fallback in the same tick") {
  for (const std::string mode : {"throw", "nan"}) {
    std::string cfg = kRouted;
    cfg.replace(cfg.find("tag: 0.2"), 8, "tag: 0.2, fail_mode: " + mode + ", fail_at: 1.5");
    const FlightResult r = fly_yaml(cfg, "fallback_" + mode);
    CHECK_MESSAGE(r.ok, mode);
    CHECK(r.end_reason == "duration");
    const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
    CHECK(s["fallback_engaged"] == true);
    const auto& h = s["controller_handovers"];
    REQUIRE(h.size() == 2);
    CHECK(h[1]["to"] == "ctl");
    CHECK(h[1]["t_s"].get<double>() == doctest::Approx(1.5));
    CHECK(h[1]["reason"].get<std::string>().find(mode == "throw" ? "ctl2.step threw: deliberate failure" : "non-finite") !=
          std::string::npos);
    // no NaN ever reached the actuators topic
    const std::string act = read_file(r.run_dir / "topics" / "actuators.csv");
    CHECK(act.find("nan") == std::string::npos);
  }
}

TEST_CASE("phase router: commands beyond the actuator limits hand over to the fallback") {
  std::string cfg = kRouted;
  cfg.replace(cfg.find("tag: 0.2"), 8, "tag: 0.9");  // 0.9 rad elevator > max_deflection 0.7
  const FlightResult r = fly_yaml(cfg, "limits");
  REQUIRE(r.ok);
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  CHECK(s["fallback_engaged"] == true);
  CHECK(s["controller_handovers"].back()["reason"].get<std::string>().find("outside the actuator limits") != std::string::npos);
}

TEST_CASE("issue 18: without `fallback:` the cruise controller is the fallback") {
  // ctl flies takeoff and climb and throws at 0.1 s, in takeoff: ctl2, named for cruise, takes over
  std::string cfg =
      base_config("  - {name: ctl2, plugin: test_controller, rate: 100, params: {tag: 0.2, h_target: 30}}\n",
                  "phases: {takeoff: ctl, climb: ctl, cruise: ctl2}\nphase_machine: {alt_toz: 2, alt_hz: 3, preflight: false}\n");
  cfg.replace(cfg.find("rate: 100}"), 10, "rate: 100, params: {fail_mode: throw, fail_at: 0.1}}");
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / "default_fallback";
  Host h(load_config(write_file("default_fallback.yaml", cfg)), o);
  h.build();
  CHECK(h.graph_text().find("ctl2 (test_controller, controller) 100 Hz  [phase router: cruise, fallback]") != std::string::npos);
  const FlightResult r = h.fly();
  CHECK(r.ok);
  CHECK(r.end_reason == "duration");
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  CHECK(s["fallback_engaged"] == true);
  REQUIRE(s["controller_handovers"].size() == 1);
  CHECK(s["controller_handovers"][0]["from"] == "ctl");
  CHECK(s["controller_handovers"][0]["to"] == "ctl2");
  CHECK(s["controller_handovers"][0]["t_s"].get<double>() == doctest::Approx(0.1));
  CHECK(s["controller_handovers"][0]["reason"] == "fallback for the rest of the flight: ctl.step threw: deliberate failure");
  CHECK(s["phases"].size() >= 2);  // the phases go on; the fallback keeps flying them
}

TEST_CASE("a plugin that throws ends the flight with an error and a complete log") {
  std::string cfg = base_config();
  cfg.replace(cfg.find("rate: 100}"), 10, "rate: 100, params: {fail_mode: throw, fail_at: 1}}");
  const FlightResult r = fly_yaml(cfg, "throw");
  CHECK_FALSE(r.ok);
  CHECK(r.end_reason == "error: ctl.step threw at t=1.000 s: deliberate failure");
  CHECK(fs::exists(r.run_dir / "summary.json"));
  const auto imu = lines(read_file(r.run_dir / "topics" / "imu.csv"));
  CHECK(imu.size() == 402);  // up to and including the failing tick
}

TEST_CASE("SIGINT ends the flight cleanly with a complete log") {
  const fs::path cfg = write_file("sigint.yaml", base_config().replace(base_config().find("duration: 2"), 11, "duration: 600"));
  const fs::path logdir = test_dir() / "sigint_runs";
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    const int devnull = ::open("/dev/null", O_WRONLY);
    dup2(devnull, 1);
    dup2(devnull, 2);
    execl(TERN_BIN, TERN_BIN, "fly", cfg.c_str(), "--realtime", "--log-dir", logdir.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
  std::vector<fs::path> runs;
  for (const auto& e : fs::directory_iterator(logdir)) runs.push_back(e.path());
  REQUIRE(runs.size() == 1);
  const auto s = nlohmann::json::parse(read_file(runs[0] / "summary.json"));
  CHECK(s["end_reason"] == "SIGINT");
  const double flown = s["duration_s"].get<double>();
  CHECK(flown > 0.5);
  CHECK(flown < 600);
  // every row is complete, and the last row is the last tick flown
  const std::string imu = read_file(runs[0] / "topics" / "imu.csv");
  REQUIRE(!imu.empty());
  CHECK(imu.back() == '\n');
  const auto rows = lines(imu);
  const auto commas = std::count(rows[0].begin(), rows[0].end(), ',');
  for (const auto& row : rows) CHECK(std::count(row.begin(), row.end(), ',') == commas);
  CHECK(rows.size() == static_cast<std::size_t>(std::llround(flown * 400)) + 2);
}

TEST_CASE("parameter changes while flying are validated, applied at the next tick and logged") {
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / "paramchange";
  Host h(load_config(write_file("pc.yaml", base_config())), o);
  h.build();
  CHECK_THROWS_WITH_AS(h.request_param("ctl.kq", 0.1, "cli"), "unknown parameter 'ctl.kq' (did you mean 'ctl.kp'?)", ConfigError);
  CHECK_THROWS_AS(h.request_param("ctl.kp", 99.0, "cli"), tern::ParamError);
  h.request_param("ctl.tag", 0.3, "cli");
  const FlightResult r = h.fly();
  REQUIRE(r.ok);
  const auto params = lines(read_file(r.run_dir / "params.csv"));
  CHECK(std::find(params.begin(), params.end(), "0.000000000,ctl.tag,0.3,cli") != params.end());
  const auto act = lines(read_file(r.run_dir / "topics" / "actuators.csv"));
  CHECK(act[1].find(",0.3,") != std::string::npos);
}

TEST_CASE("log.max_rate thins fast topics by flight time; log.rates overrides it per topic") {
  std::string cfg = base_config();
  cfg.replace(cfg.find("log: {max_rate: 0}"), 18, "log: {max_rate: 100, rates: {imu: 0, truth: 10}}");
  const FlightResult r = fly_yaml(cfg, "decimate");
  REQUIRE(r.ok);
  CHECK(lines(read_file(r.run_dir / "topics" / "imu.csv")).size() == 802);    // every sample
  CHECK(lines(read_file(r.run_dir / "topics" / "state.csv")).size() == 202);  // 400 Hz -> 100 Hz
  const auto truth = lines(read_file(r.run_dir / "topics" / "truth.csv"));
  REQUIRE(truth.size() == 22);  // 400 Hz -> 10 Hz
  CHECK(truth[2].rfind("0.100000000,", 0) == 0);
}

TEST_CASE("mission edits from the host API reach the reader of mission_edit, one per tick, in order") {
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / "edits";
  Host h(load_config(write_file("edits.yaml", base_config())), o);
  h.build();
  CHECK(h.graph_text().find("mission_edit [tern/MissionEdit]: host: mission edits from the command line and DDS -> filter.mission_edit") !=
        std::string::npos);
  tern::msg::MissionEdit e;
  e.op = tern::msg::MissionEdit::add;
  e.id = 1;
  h.edit_mission(e);
  e.op = tern::msg::MissionEdit::clear;
  e.id = 2;
  h.edit_mission(e);
  const FlightResult r = h.fly();
  REQUIRE(r.ok);
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  CHECK(s["instances"]["filter"]["mission_edits"] == 2.0);
  CHECK(s["instances"]["filter"]["last_edit_id"] == 2.0);
  const auto rows = lines(read_file(r.run_dir / "topics" / "mission_edit.csv"));
  REQUIRE(rows.size() == 3);
  CHECK(rows[1].rfind("0.000000000,0,1,0,", 0) == 0);
  CHECK(rows[2].rfind("0.002500000,2500000,2,1,", 0) == 0);
}

TEST_CASE("edit_mission without a mission_edit reader is an error") {
  HostOptions o;
  o.quiet = true;
  Host h(load_config(write_file("noedits.yaml", "name: t\nplugins:\n  - {name: sensor, plugin: test_sensor, rate: 400}\n")), o);
  h.build();
  CHECK_THROWS_WITH_AS(h.edit_mission(tern::msg::MissionEdit{}), doctest::Contains("no plugin instance reads topic 'mission_edit'"),
                       ConfigError);
}

TEST_CASE("several tick observers: each sees every tick; one that throws is removed, the others go on") {
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / "observers";
  Host h(load_config(write_file("obs.yaml", base_config())), o);
  h.build();
  int a = 0, b = 0, thrown = 0, removed = 0;
  h.add_tick_observer([&](tern::Nanos) { ++a; });
  const int second = h.add_tick_observer([&](tern::Nanos) { ++b; });
  h.add_tick_observer([&](tern::Nanos now) {
    if (now >= 1'000'000'000) {
      ++thrown;
      throw std::runtime_error("observer failed");
    }
  });
  const int gone = h.add_tick_observer([&](tern::Nanos) { ++removed; });
  h.remove_tick_observer(gone);
  const FlightResult r = h.fly();
  REQUIRE(r.ok);
  CHECK(a > 100);
  CHECK(b == a);
  CHECK(thrown == 1);  // removed after it threw
  CHECK(removed == 0);
  h.remove_tick_observer(second);
  const int before = b;
  REQUIRE(h.fly().ok);
  CHECK(b == before);
  CHECK(a == 2 * before);
}
