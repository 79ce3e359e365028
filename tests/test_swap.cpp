// Hot-swap between flights, the phase table, and `tern serve` driven from the command line.
#include <doctest/doctest.h>

#include <sys/wait.h>

#include <chrono>
#include <csignal>
#include <thread>

#include <nlohmann/json.hpp>

#include "loader.hpp"
#include "test_util.hpp"

using namespace tern::core;

namespace {
const fs::path kV1 = fs::path(TERN_TEST_PLUGIN_DIR) / "libtern_test_controller.so";
const fs::path kV2 = fs::path(TERN_TEST_PLUGIN_DIR) / "v2" / "libtern_test_controller.so";

std::unique_ptr<Host> host_for(const std::string& yaml, const std::string& name) {
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / name;
  auto h = std::make_unique<Host>(load_config(write_file(name + ".yaml", yaml)), o);
  h->build();
  return h;
}

double version_flown(const FlightResult& r, const std::string& inst) {
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  return s["instances"][inst]["version"].get<double>();
}

std::size_t count_lines_with(const fs::path& file, const std::string& needle) {
  std::size_t n = 0;
  std::stringstream ss(read_file(file));
  for (std::string l; std::getline(ss, l);) n += l.find(needle) != std::string::npos;
  return n;
}

std::size_t open_fds() {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator("/proc/self/fd")) ++n;
  return n;
}

long rss_kb() {
  std::stringstream ss(read_file("/proc/self/status"));
  for (std::string l; std::getline(ss, l);)
    if (l.rfind("VmRSS:", 0) == 0) return std::stol(l.substr(6));
  return 0;
}
}  // namespace

TEST_CASE("swap v1 -> v2 between flights: the next flight runs the new code, the old library is gone") {
  REQUIRE(fs::exists(kV2));
  auto h = host_for(base_config(), "swap");
  const FlightResult a = h->fly();
  REQUIRE(a.ok);
  CHECK(version_flown(a, "ctl") == 1.0);
  h->swap("ctl", kV2);
  CHECK_FALSE(is_loaded(kV1));
  const FlightResult b = h->fly();
  REQUIRE(b.ok);
  CHECK(version_flown(b, "ctl") == 2.0);
  const auto s = nlohmann::json::parse(read_file(b.run_dir / "summary.json"));
  CHECK(s["flight"] == 2);
  CHECK(s["instances"]["ctl"]["library"] == kV2.string());
  // a rebuild at the same path: copy v1 over a file, swap it in, overwrite with v2, swap again
  const fs::path same = test_dir() / "rebuild" / "libtern_test_controller.so";
  fs::create_directories(same.parent_path());
  fs::copy_file(kV1, same, fs::copy_options::overwrite_existing);
  h->swap("ctl", same);
  CHECK(version_flown(h->fly(), "ctl") == 1.0);
  fs::copy_file(kV2, same, fs::copy_options::overwrite_existing);
  h->swap("ctl", same);
  CHECK(version_flown(h->fly(), "ctl") == 2.0);
  // the first flight and the later ones start from the same initial state
  const auto first = read_file(a.run_dir / "topics" / "truth.csv");
  CHECK(first.substr(0, 400) == read_file(b.run_dir / "topics" / "truth.csv").substr(0, 400));
}

TEST_CASE("swap is refused while flying, and a mismatched .so is refused with the current plugin kept") {
  std::string cfg = base_config();
  cfg.replace(cfg.find("duration: 2"), 11, "duration: 30");
  auto h = host_for(cfg, "swap_refused");
  HostOptions o;
  std::thread flight([&] {
    request_stop(0);  // (cleared by fly)
    (void)h->fly();
  });
  while (!h->flying()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  CHECK_THROWS_WITH_AS(h->swap("ctl", kV2), "swap refused: a flight is in progress; swap between flights", ConfigError);
  request_stop(SIGINT);
  flight.join();
  CHECK_THROWS_WITH_AS(h->swap("ctl", fs::path(TERN_TEST_PLUGIN_DIR) / "libtern_test_bad_abi.so"),
                       doctest::Contains("refused, 'test_controller' keeps flying: plugin 'test_bad_abi'"), ConfigError);
  CHECK_THROWS_WITH_AS(h->swap("ctl", fs::path(TERN_TEST_PLUGIN_DIR) / "libtern_test_bad_fingerprint.so"),
                       doctest::Contains("message fingerprint mismatch"), ConfigError);
  CHECK_THROWS_WITH_AS(h->swap("clt", kV2), "swap: no plugin instance named 'clt' (did you mean 'ctl'?)", ConfigError);
  // a plugin whose ports do not fit: the sensor's place taken by a second controller
  CHECK_THROWS_WITH_AS(h->swap("sensor", kV2), doctest::Contains("its ports do not fit the graph"), ConfigError);
  std::string cfg2 = base_config();
  cfg2.replace(cfg2.find("duration: 2"), 11, "duration: 0.5");
  h->set_duration(0.5);
  const FlightResult r = h->fly();
  CHECK(r.ok);
  CHECK(version_flown(r, "ctl") == 1.0);
}

TEST_CASE("100 swaps: no growth of mapped libraries, file descriptors or resident memory") {
  auto h = host_for(base_config(), "swap100");
  h->swap("ctl", kV2);  // warm-up: first copies, loggers, allocations
  h->swap("ctl", kV1);
  const auto maps0 = count_lines_with("/proc/self/maps", "libtern_test_controller");
  const auto fds0 = open_fds();
  const long rss0 = rss_kb();
  for (int i = 0; i < 100; ++i) h->swap("ctl", i % 2 ? kV1 : kV2);
  CHECK(count_lines_with("/proc/self/maps", "libtern_test_controller") == maps0);
  CHECK(open_fds() == fds0);
  CHECK(rss_kb() - rss0 < 1024);
}

TEST_CASE("the phase table changes between flights") {
  auto h = host_for(base_config("  - {name: ctl2, plugin: test_controller, rate: 100, params: {tag: 0.2}}\n",
                                "phases: {takeoff: ctl, climb: ctl, cruise: ctl}\nfallback: ctl2\nphase_machine: {alt_toz: 2, alt_hz: 3, preflight: false}\n"),
                    "phases");
  CHECK_THROWS_WITH_AS(h->set_phases({{tern::msg::Phase::takeoff, "ctl"}, {tern::msg::Phase::climb, "ctl"}}, std::nullopt),
                       "phases: no controller for phase 'cruise'", ConfigError);
  CHECK_THROWS_WITH_AS(h->set_phases({{tern::msg::Phase::takeoff, "ctl"}, {tern::msg::Phase::climb, "ctl"}, {tern::msg::Phase::cruise, "ctl3"}},
                                     std::nullopt),
                       "phases: no plugin instance named 'ctl3' (did you mean 'ctl'?)", ConfigError);
  CHECK_THROWS_WITH_AS(h->set_phases({{tern::msg::Phase::takeoff, "ctl"}, {tern::msg::Phase::climb, "ctl"}, {tern::msg::Phase::cruise, "sensor"}},
                                     std::nullopt),
                       "phases refused, the old table stays: phases.cruise: 'sensor' is not a controller: it runs plugin "
                       "'test_sensor' (io); name one of: ctl, ctl2", ConfigError);
  CHECK_THROWS_WITH_AS(h->set_phases({{tern::msg::Phase::takeoff, "ctl"}, {tern::msg::Phase::climb, "ctl"}, {tern::msg::Phase::cruise, "ctl"}},
                                     std::string("filter")),
                       "phases refused, the old table stays: fallback: 'filter' is not a controller: it runs plugin "
                       "'test_filter' (estimator); name one of: ctl, ctl2", ConfigError);
  h->set_phases({{tern::msg::Phase::takeoff, "ctl"}, {tern::msg::Phase::climb, "ctl"}, {tern::msg::Phase::cruise, "ctl2"}}, std::nullopt);
  const FlightResult r = h->fly();
  REQUIRE(r.ok);
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  REQUIRE(s["controller_handovers"].size() == 1);
  CHECK(s["controller_handovers"][0]["to"] == "ctl2");
}

TEST_CASE("tern serve: fly, swap, fly, status, quit from the command line") {
  const fs::path cfg = write_file("serve.yaml", base_config());
  const fs::path sock = test_dir() / "serve.sock";
  const fs::path logs = test_dir() / "serve_runs";
  const std::string bin = TERN_BIN;
  const std::string serve_cmd = bin + " serve " + cfg.string() + " --socket " + sock.string() + " --log-dir " + logs.string() +
                                " > " + (test_dir() / "serve.out").string() + " 2>&1 &";
  REQUIRE(std::system(serve_cmd.c_str()) == 0);
  for (int i = 0; i < 500 && !fs::exists(sock); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  REQUIRE(fs::exists(sock));
  auto run = [&](const std::string& args) {
    const std::string out = (test_dir() / "client.out").string();
    const int rc = std::system((bin + " " + args + " --socket " + sock.string() + " > " + out + " 2>&1").c_str());
    return std::make_pair(WEXITSTATUS(rc), read_file(out));
  };
  auto [rc1, out1] = run("remote fly 0.5");
  CHECK(rc1 == 0);
  CHECK(out1.find("ok: flight 1 ended (duration) at t=0.500 s; log: ") != std::string::npos);
  auto [rc2, out2] = run("swap ctl " + kV2.string());
  CHECK(rc2 == 0);
  CHECK(out2 == "ok: ctl now runs " + kV2.string() + "\n");
  auto [rc3, out3] = run("remote fly 0.5");
  CHECK(rc3 == 0);
  const auto log_dir = out3.substr(out3.find("log: ") + 5, out3.size() - out3.find("log: ") - 6);
  const auto s = nlohmann::json::parse(read_file(fs::path(log_dir) / "summary.json"));
  CHECK(s["instances"]["ctl"]["version"] == 2.0);
  auto [rc4, out4] = run("phases takeoff=ctl climb=ctl cruise=nope");
  CHECK(rc4 == 1);
  CHECK(out4 == "error: phases: this mission has no 'phases:' table (and so no phase machine) to change\n");
  auto [rc5, out5] = run("remote status");
  CHECK(out5 == "ok: idle, 2 flight(s) flown\n");
  auto [rc6, out6] = run("remote quit");
  CHECK(rc6 == 0);
  for (int i = 0; i < 500 && fs::exists(sock); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  CHECK_FALSE(fs::exists(sock));
  auto [rc7, out7] = run("remote status");
  CHECK(rc7 == 1);
  CHECK(out7.find("no tern serve answers at") != std::string::npos);
}
