// Isolation and the watchdog (issue 19, items 1 and 2), on the test plugins: an isolated
// instance flies bit-identically to an in-process one (parameters, log lines and summaries
// cross); when its child crashes, hangs or exits the flight ends cleanly with one line naming it;
// hot-swap replaces the child. In-process: a slow step is reported once, a step stuck past the
// hard budget ends `tern fly` within the budget, and SIGINT ends a `tern fly` stuck in a loop.
#include <doctest/doctest.h>

#include <csignal>
#include <map>

#include <nlohmann/json.hpp>

#include "runners/isolated_plugin.hpp"
#include "test_process.hpp"
#include "test_util.hpp"

using namespace tern::core;

namespace {

// base_config() with `isolate: true` on instance `name` (and `params` added to it).
std::string with_instance(std::string yaml, const std::string& name, const std::string& extra) {
  const std::string key = "{name: " + name + ",";
  const auto at = yaml.find(key);
  REQUIRE(at != std::string::npos);
  const auto end = yaml.rfind('}', yaml.find('\n', at));  // the entry is one line
  yaml.insert(end, ", " + extra);
  return yaml;
}

std::string isolated(const std::string& yaml, const std::string& name) { return with_instance(yaml, name, "isolate: true"); }

// Every file of a run's topics/ and params.csv, by name.
std::map<std::string, std::string> csv_files(const fs::path& run) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(run / "topics")) out[e.path().filename().string()] = read_file(e.path());
  out["params.csv"] = read_file(run / "params.csv");
  return out;
}

nlohmann::json summary_of(const FlightResult& r) { return nlohmann::json::parse(read_file(r.run_dir / "summary.json")); }

std::size_t count_lines_with(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (const auto& l : lines(text)) n += l.find(what) != std::string::npos;
  return n;
}

// Flies `yaml` with a live parameter change (ctl.tag) queued before the first tick.
FlightResult fly_with_change(const std::string& yaml, const std::string& logdir) {
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / logdir;
  Host h(load_config(write_file(logdir + ".yaml", yaml)), o);
  h.build();
  h.request_param("ctl.tag", tern::ParamValue(0.25), "test");
  return h.fly();
}

}  // namespace

TEST_CASE("isolated or not, the same seed gives byte-identical CSV logs (parameters, log lines and summaries cross)") {
  const std::string plain = with_instance(base_config(), "filter", "params: {log_every_s: 0.5}");
  const std::string both = isolated(isolated(plain, "filter"), "ctl");
  const FlightResult a = fly_with_change(plain, "iso_plain");
  const FlightResult b = fly_with_change(both, "iso_both");
  REQUIRE(a.ok);
  REQUIRE(b.ok);
  const auto fa = csv_files(a.run_dir), fb = csv_files(b.run_dir);
  REQUIRE(fa.size() == fb.size());
  CHECK(fa.size() >= 4);
  for (const auto& [name, text] : fa) {
    INFO(name);
    REQUIRE(fb.count(name));
    CHECK(text.size() > 0);
    if (name == "params.csv")  // the configs differ in their name or layout: the sources' file:line with them
      CHECK(config_sources_neutral(text) == config_sources_neutral(fb.at(name)));
    else
      CHECK(text == fb.at(name));
  }
  CHECK(fb.at("actuators.csv").find(",0.25") != std::string::npos);  // the live change reached the child
  // summaries cross (stop), log lines cross (to tern.log, under the instance's name)
  CHECK(summary_of(a)["instances"]["filter"] == summary_of(b)["instances"]["filter"]);
  CHECK(summary_of(b)["instances"]["filter"]["steps"].get<double>() == 801.0);
  CHECK(count_lines_with(read_file(b.run_dir / "tern.log"), "filter: step at t=") == 5);
  CHECK(count_lines_with(read_file(a.run_dir / "tern.log"), "filter: step at t=") == 5);
}

TEST_CASE("an isolated estimator that segfaults ends the flight cleanly: plugin_failed, one line naming it and SIGSEGV") {
  const std::string yaml = with_instance(isolated(base_config(), "filter"), "filter", "params: {fail_mode: segv, fail_at: 1.0}");
  const FlightResult r = fly_yaml(yaml, "iso_segv");
  CHECK_FALSE(r.ok);
  CHECK(r.end_reason == "plugin_failed");
  CHECK(r.end_detail == "isolated instance filter died: SIGSEGV at t=1.000 s");
  CHECK(tern::to_seconds(r.flown) == doctest::Approx(1.0));
  const std::string log = read_file(r.run_dir / "tern.log");
  CHECK(count_lines_with(log, "isolated instance filter died: SIGSEGV") == 1);
  CHECK(summary_of(r)["end_reason"] == "plugin_failed");
  const std::string imu = read_file(r.run_dir / "topics" / "imu.csv");
  CHECK(imu.back() == '\n');
  CHECK(lines(imu).back().rfind("1.000000000,", 0) == 0);  // the tick it failed in is logged
}

TEST_CASE("an isolated estimator that hangs is killed past watchdog.hard_ms: clean end naming it") {
  const std::string yaml =
      with_instance(isolated(base_config("", "watchdog: {hard_ms: 300}\n"), "filter"), "filter", "params: {fail_mode: hang, fail_at: 0.5}");
  const auto t0 = std::chrono::steady_clock::now();
  const FlightResult r = fly_yaml(yaml, "iso_hang");
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK_FALSE(r.ok);
  CHECK(r.end_reason == "plugin_failed");
  CHECK(r.end_detail == "isolated instance filter hung: no reply within 0.300 s, killed with SIGKILL at t=0.500 s");
  CHECK(wall < 10.0);
  CHECK(count_lines_with(read_file(r.run_dir / "tern.log"), "isolated instance filter hung") == 1);
  CHECK(summary_of(r)["end_reason"] == "plugin_failed");
}

TEST_CASE("an isolated instance whose process exits: plugin_failed, the exit status named") {
  const std::string yaml = with_instance(isolated(base_config(), "filter"), "filter", "params: {fail_mode: exit, fail_at: 0.25}");
  const FlightResult r = fly_yaml(yaml, "iso_exit");
  CHECK(r.end_reason == "plugin_failed");
  CHECK(r.end_detail == "isolated instance filter exited with status 3 at t=0.250 s");
}

TEST_CASE("an isolated plugin that throws is an error like in-process, and the child lives on") {
  const std::string yaml = with_instance(isolated(base_config(), "ctl"), "ctl", "params: {fail_mode: throw, fail_at: 0.5}");
  const FlightResult r = fly_yaml(yaml, "iso_throw");
  CHECK(r.end_reason == "error: ctl.step threw at t=0.500 s: deliberate failure");
}

TEST_CASE("hot-swap of an isolated instance: the next flight runs the new library in a new child") {
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / "iso_swap";
  Host h(load_config(write_file("iso_swap.yaml", isolated(base_config(), "ctl"))), o);
  h.build();
  const auto* before = h.instances()[2]->isolated;
  REQUIRE(before != nullptr);
  const pid_t old_child = before->child();
  REQUIRE(h.fly().ok);
  h.swap("ctl", fs::path(TERN_TEST_PLUGIN_DIR) / "v2" / "libtern_test_controller.so");
  const auto* after = h.instances()[2]->isolated;
  REQUIRE(after != nullptr);
  CHECK(after->child() != old_child);
  CHECK(::kill(old_child, 0) != 0);  // the old child is gone (reaped)
  const FlightResult r = h.fly();
  CHECK(r.ok);
  CHECK(summary_of(r)["instances"]["ctl"]["version"].get<double>() == 2.0);
}

TEST_CASE("isolation refuses bad input in one line: isolate not a boolean") {
  CHECK(build_error(with_instance(base_config(), "ctl", "isolate: yes please")).find("plugins[2].isolate: expected true or false") !=
        std::string::npos);
  CHECK(build_error(base_config("", "watchdog: {soft_ms: 10, hard_ms: 5}\n")).find("watchdog: need 0 < soft_ms <= hard_ms") !=
        std::string::npos);
}

TEST_CASE("a step over the watchdog's soft budget is reported once per instance and counted in timing.json") {
  const FlightResult r = fly_yaml(base_config("", "watchdog: {soft_ms: 0.000001}\n"), "soft");
  REQUIRE(r.ok);
  const auto timing = nlohmann::json::parse(read_file(r.run_dir / "timing.json"));
  CHECK(timing["instances"]["filter"]["watchdog_slow_steps"].get<double>() > 700.0);
  CHECK_FALSE(summary_of(r)["instances"]["filter"].contains("watchdog_slow_steps"));  // wall time stays out of summary.json
  const std::string log = read_file(r.run_dir / "tern.log");
  CHECK(count_lines_with(log, "filter: a step took") == 1);
  CHECK(count_lines_with(log, "over the watchdog's soft budget") >= 3);  // once each: sensor, filter, ctl (and metrics)
}

TEST_CASE("an in-process step stuck in an endless loop ends `tern fly` within the hard budget; the log is complete") {
  const fs::path cfg = write_file(
      "loop.yaml", with_instance(base_config("", "watchdog: {hard_ms: 400}\n"), "filter", "params: {fail_mode: hang, fail_at: 0.5}"));
  const fs::path logdir = test_dir() / "loop_runs";
  const auto t0 = std::chrono::steady_clock::now();
  const int rc = run_tern({"fly", cfg.string(), "-q", "--log-dir", logdir.string()}, test_dir() / "loop.out");
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string console = read_file(test_dir() / "loop.out");
  INFO(console);
  CHECK(rc == 1);
  CHECK(wall < 5.0);
  const fs::path run = fs::directory_iterator(logdir)->path();
  const auto s = nlohmann::json::parse(read_file(run / "summary.json"));
  CHECK(s["end_reason"] == "watchdog");
  CHECK(s["end_detail"].get<std::string>().rfind("filter at t=0.500 s: a step still running after", 0) == 0);
  CHECK(s["instances"]["filter"]["summary"] == "not read: its step was still running when the flight ended");
  CHECK(s["instances"]["ctl"].contains("steps"));  // the others' figures are read as ever
  CHECK(count_lines_with(read_file(run / "tern.log"), "past the watchdog's hard budget of 400 ms") == 1);
  CHECK(count_lines_with(console, "error") == 1);
  for (const auto& e : fs::directory_iterator(run / "topics")) {
    const std::string csv = read_file(e.path());
    CHECK((!csv.empty() && csv.back() == '\n'));
  }
  // the last tick that ended (the stuck one never captured its messages)
  CHECK(lines(read_file(run / "topics" / "imu.csv")).back().rfind("0.497500000,", 0) == 0);
}

TEST_CASE("SIGINT ends a `tern fly` stuck in a plugin's endless loop: exit 130, summary.json written") {
  const fs::path cfg = write_file(
      "stuck.yaml", with_instance(base_config("", "watchdog: {hard_ms: 600000}\n"), "ctl", "params: {fail_mode: hang, fail_at: 0.2}"));
  const fs::path logdir = test_dir() / "stuck_runs";
  const pid_t pid = spawn_tern({"fly", cfg.string(), "-q", "--log-dir", logdir.string()}, test_dir() / "stuck.out");
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const auto t0 = std::chrono::steady_clock::now();
  ::kill(pid, SIGINT);
  const int status = wait_for(pid);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  INFO(read_file(test_dir() / "stuck.out"));
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
  CHECK(wall < 3.0);
  const fs::path run = fs::directory_iterator(logdir)->path();
  const auto s = nlohmann::json::parse(read_file(run / "summary.json"));
  CHECK(s["end_reason"] == "SIGINT");
  CHECK(s["end_detail"].get<std::string>().find("ctl at t=0.200 s: stuck in a step") == 0);
}
