// Hot-swap between flights, the phase table, and `tern serve` driven from the command line.
#include <doctest/doctest.h>

#include <sys/wait.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <thread>

#include <nlohmann/json.hpp>

#include "graph/loader.hpp"
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

// A `tern serve` process on config `yaml` (its output in NAME.out), and clients of it.
struct Served {
  fs::path sock, out;
  Served(const std::string& yaml, const std::string& name, const std::string& options)
      : sock(test_dir() / (name + ".sock")), out(test_dir() / (name + ".out")) {
    const fs::path cfg = write_file(name + ".yaml", yaml);
    const std::string cmd = std::string(TERN_BIN) + " serve " + cfg.string() + " " + options + " --socket " + sock.string() +
                            " --log-dir " + (test_dir() / (name + "_runs")).string() + " > " + out.string() + " 2>&1 &";
    REQUIRE(std::system(cmd.c_str()) == 0);
    for (int i = 0; i < 500 && !fs::exists(sock); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    REQUIRE(fs::exists(sock));
  }
  /// `tern ARGS --socket SOCK`: its exit status and output.
  std::pair<int, std::string> run(const std::string& args) const {
    const std::string client_out = (test_dir() / "client.out").string();
    const int rc = std::system((std::string(TERN_BIN) + " " + args + " --socket " + sock.string() + " > " + client_out + " 2>&1").c_str());
    return {WEXITSTATUS(rc), read_file(client_out)};
  }
};
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
  CHECK_FALSE(s.contains("flight"));  // summary.json is the flight's alone: the host's count is in timing.json
  CHECK(nlohmann::json::parse(read_file(b.run_dir / "timing.json"))["flight"] == 2);
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

TEST_CASE("swap reports both libraries' SHA-256 and says when they are the same") {
  auto h = host_for(base_config(), "swap_sha");
  const std::string sha1 = file_sha256(kV1), sha2 = file_sha256(kV2);
  CHECK(sha1.size() == 64);
  CHECK(sha1 != sha2);
  // an independent digest: sha256sum's answer for the same bytes
  const fs::path out = test_dir() / "sha256sum.out";
  REQUIRE(std::system(("sha256sum " + kV1.string() + " > " + out.string()).c_str()) == 0);
  CHECK(read_file(out).substr(0, 64) == sha1);
  const SwapReport a = h->swap("ctl", kV2);
  CHECK(a.old_sha256 == sha1);
  CHECK(a.new_sha256 == sha2);
  CHECK_FALSE(a.same());
  // a "rebuild" that left the file as it was (the build failed): same bytes, swapped with a warning
  const fs::path copy = test_dir() / "same" / "libtern_test_controller.so";
  fs::create_directories(copy.parent_path());
  fs::copy_file(kV2, copy, fs::copy_options::overwrite_existing);
  const SwapReport b = h->swap("ctl", copy);
  CHECK(b.same());
  CHECK(b.new_sha256 == sha2);
  // the hash is of the bytes loaded, not of the file now at that path
  fs::copy_file(kV1, copy, fs::copy_options::overwrite_existing);
  CHECK(h->swap("ctl", copy).old_sha256 == sha2);
}

TEST_CASE("abort_flight ends the flight like its duration with a complete log; the host flies again") {
  std::string cfg = base_config();
  cfg.replace(cfg.find("duration: 2"), 11, "duration: 600");
  HostOptions o;
  o.quiet = true;
  o.realtime = true;  // the flight lasts until aborted
  o.log_dir = test_dir() / "abort";
  auto h = std::make_unique<Host>(load_config(write_file("abort.yaml", cfg)), o);
  h->build();
  CHECK_FALSE(h->abort_flight());  // nothing flying
  FlightResult r;
  std::thread flight([&] { r = h->fly(); });
  while (!h->flying()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  CHECK(h->abort_flight());
  flight.join();
  CHECK(r.ok);
  CHECK(r.end_reason == "aborted");
  CHECK(r.flown < tern::from_seconds(600));
  CHECK(r.flown > 0);
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  CHECK(s["end_reason"] == "aborted");
  CHECK(r.summary.find("ended (aborted)") != std::string::npos);
  CHECK(exit_status(r) == 0);
  h->set_duration(0.5);
  const FlightResult next = h->fly();  // an abort asked between flights does not carry over
  CHECK(next.ok);
  CHECK(next.end_reason == "duration");
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
  // Under qemu-user (an arm64 cross build's ctest sets TERN_TEST_UNDER_QEMU) the resident memory
  // is the emulator's, whose translated-code cache grows with every library loaded again (20 MB
  // over these 100 swaps), and under AddressSanitizer freed memory waits in its quarantine (up to
  // 256 MB by default; make sanitize: 21 MB here): only the mapped libraries and descriptors say
  // something there.
#if defined(__SANITIZE_ADDRESS__)
  constexpr bool kQuarantine = true;
#else
  constexpr bool kQuarantine = false;
#endif
  if (std::getenv("TERN_TEST_UNDER_QEMU") == nullptr && !kQuarantine) {
    CHECK(rss_kb() - rss0 < 1024);
  } else {
    MESSAGE("resident memory not checked under qemu-user or AddressSanitizer: " << rss_kb() - rss0 << " kB");
  }
}

TEST_CASE("the phase table changes between flights") {
  auto h = host_for(
      base_config(
          "  - {name: ctl2, plugin: test_controller, rate: 100, params: {tag: 0.2}}\n",
          "phases: {takeoff: ctl, climb: ctl, cruise: ctl}\nfallback: ctl2\nphase_machine: {alt_toz: 2, alt_hz: 3, preflight: false}\n"),
      "phases");
  CHECK_THROWS_WITH_AS(h->set_phases({{tern::msg::Phase::takeoff, "ctl"}, {tern::msg::Phase::climb, "ctl"}}, std::nullopt),
                       "phases: no controller for phase 'cruise'", ConfigError);
  CHECK_THROWS_WITH_AS(
      h->set_phases({{tern::msg::Phase::takeoff, "ctl"}, {tern::msg::Phase::climb, "ctl"}, {tern::msg::Phase::cruise, "ctl3"}},
                    std::nullopt),
      "phases: no plugin instance named 'ctl3' (did you mean 'ctl'?)", ConfigError);
  CHECK_THROWS_WITH_AS(
      h->set_phases({{tern::msg::Phase::takeoff, "ctl"}, {tern::msg::Phase::climb, "ctl"}, {tern::msg::Phase::cruise, "sensor"}},
                    std::nullopt),
      "phases refused, the old table stays: phases.cruise: 'sensor' is not a controller: it runs plugin "
      "'test_sensor' (io); name one of: ctl, ctl2",
      ConfigError);
  CHECK_THROWS_WITH_AS(
      h->set_phases({{tern::msg::Phase::takeoff, "ctl"}, {tern::msg::Phase::climb, "ctl"}, {tern::msg::Phase::cruise, "ctl"}},
                    std::string("filter")),
      "phases refused, the old table stays: fallback: 'filter' is not a controller: it runs plugin "
      "'test_filter' (estimator); name one of: ctl, ctl2",
      ConfigError);
  h->set_phases({{tern::msg::Phase::takeoff, "ctl"}, {tern::msg::Phase::climb, "ctl"}, {tern::msg::Phase::cruise, "ctl2"}}, std::nullopt);
  const FlightResult r = h->fly();
  REQUIRE(r.ok);
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  REQUIRE(s["controller_handovers"].size() == 1);
  CHECK(s["controller_handovers"][0]["to"] == "ctl2");
}

TEST_CASE("tern serve: fly (with its summary), swap (with hashes), fly, abort, status, quit from the command line") {
  // real time: the 600 s flight below lasts until aborted
  const Served server(base_config(), "serve", "--realtime");
  const fs::path& sock = server.sock;
  const std::string bin = TERN_BIN;
  auto run = [&server](const std::string& args) { return server.run(args); };
  auto [rc1, out1] = run("remote fly 0.5");
  CHECK(rc1 == 0);
  CHECK(out1.find("ok: flight 1 ended (duration) at t=0.500 s; log: ") == 0);
  // the summary tables `tern fly` prints, after the first line
  CHECK(out1.find("flight 'hostcheck' ended (duration) at t = 0.50 s") != std::string::npos);
  CHECK(out1.find("instance") != std::string::npos);
  CHECK(out1.find("  ctl ") != std::string::npos);
  auto [rc2, out2] = run("swap ctl " + kV2.string());
  CHECK(rc2 == 0);
  CHECK(out2 == "ok: ctl now runs " + kV2.string() + " (sha256 " + file_sha256(kV1).substr(0, 12) + " -> " +
                    file_sha256(kV2).substr(0, 12) + ")\n");
  auto [rc3, out3] = run("remote fly 0.5");
  CHECK(rc3 == 0);
  const auto log_start = out3.find("log: ") + 5;
  const auto log_dir = out3.substr(log_start, out3.find('\n', log_start) - log_start);
  const auto s = nlohmann::json::parse(read_file(fs::path(log_dir) / "summary.json"));
  CHECK(s["instances"]["ctl"]["version"] == 2.0);
  // the same library again (a failed rebuild): swapped, with a warning
  auto [rc2b, out2b] = run("swap ctl " + kV2.string());
  CHECK(rc2b == 0);
  CHECK(out2b == "ok: ctl now runs " + kV2.string() + "\nwarning: same library (sha256 " + file_sha256(kV2) + "): did the build fail?\n");
  const std::string server_out = read_file(server.out);
  CHECK(server_out.find("sha256 " + file_sha256(kV1) + " -> test_controller (" + kV2.string() + ") sha256 " + file_sha256(kV2)) !=
        std::string::npos);
  CHECK(server_out.find("same library (sha256 " + file_sha256(kV2) + ") as the one running: did the build fail?") != std::string::npos);
  // abort: the long flight ends, its log is complete, the server stays for the next one
  auto [rca0, outa0] = run("remote abort");
  CHECK(rca0 == 1);
  CHECK(outa0 == "error: abort: no flight in progress\n");
  std::pair<int, std::string> long_fly;
  std::thread flying([&] {
    const std::string out = (test_dir() / "long_fly.out").string();
    const int rc = std::system((bin + " remote fly 600 --socket " + sock.string() + " > " + out + " 2>&1").c_str());
    long_fly = {WEXITSTATUS(rc), read_file(out)};
  });
  std::string status;
  for (int i = 0; i < 500 && status.find("flying") == std::string::npos; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    status = run("remote status").second;
  }
  CHECK(status.find("ok: flying (flight 3)") == 0);
  auto [rca, outa] = run("remote abort");
  flying.join();
  CHECK(rca == 0);
  CHECK(outa.find("ok: flight 3 aborting") == 0);
  CHECK(long_fly.first == 0);
  CHECK(long_fly.second.find("ok: flight 3 ended (aborted) at t=") == 0);
  const auto abort_log_start = long_fly.second.find("log: ") + 5;
  const fs::path abort_dir = long_fly.second.substr(abort_log_start, long_fly.second.find('\n', abort_log_start) - abort_log_start);
  CHECK(nlohmann::json::parse(read_file(abort_dir / "summary.json"))["end_reason"] == "aborted");
  CHECK(fs::exists(abort_dir / "timing.json"));
  auto [rc4, out4] = run("phases cruise=ctl");
  CHECK(rc4 == 1);
  CHECK(out4 == "error: phases: this mission has no 'phases:' table (and so no phase machine) to change\n");
  auto [rc5, out5] = run("remote status");
  CHECK(out5 == "ok: idle, 3 flight(s) flown\n");
  auto [rc6, out6] = run("remote quit");
  CHECK(rc6 == 0);
  for (int i = 0; i < 500 && fs::exists(sock); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  CHECK_FALSE(fs::exists(sock));
  auto [rc7, out7] = run("remote status --wait 0.2");  // waits 0.2 s for a server that might be starting
  CHECK(rc7 == 1);
  CHECK(out7.find("no tern serve is listening at") != std::string::npos);
  CHECK(out7.find("after waiting 0.2 s") != std::string::npos);
}

TEST_CASE("tern phases: a partial table changes the phases it names; a misspelt instance gets a suggestion") {
  const Served server(
      base_config("  - {name: ctl2, plugin: test_controller, rate: 100, params: {tag: 0.2}}\n",
                  "phases: {takeoff: ctl, climb: ctl, cruise: ctl}\nphase_machine: {alt_toz: 2, alt_hz: 3, preflight: false}\n"),
      "serve_phases", "");
  auto [rc1, out1] = server.run("phases cruise=ctrl2");
  CHECK(rc1 == 1);
  CHECK(out1.rfind("error: phases: cruise: no plugin instance named 'ctrl2' (did you mean 'ctl2'?)", 0) == 0);
  auto [rc2, out2] = server.run("phases crusie=ctl2");
  CHECK(rc2 == 1);
  CHECK(out2.rfind("error: phases: unknown phase 'crusie' (did you mean 'cruise'?)", 0) == 0);
  // cruise alone: takeoff and climb keep ctl
  auto [rc3, out3] = server.run("phases cruise=ctl2 --fallback ctl");
  CHECK(rc3 == 0);
  CHECK(out3 == "ok: phase table changed\n");
  auto [rc4, out4] = server.run("remote fly");
  REQUIRE(rc4 == 0);
  const auto log_start = out4.find("log: ") + 5;
  const fs::path run_dir = out4.substr(log_start, out4.find('\n', log_start) - log_start);
  const std::string flown = read_file(run_dir / "config.yaml");
  CHECK(flown.find("phases: {takeoff: ctl, climb: ctl, cruise: ctl2}") != std::string::npos);
  CHECK(flown.find("fallback: ctl\n") != std::string::npos);
  const auto s = nlohmann::json::parse(read_file(run_dir / "summary.json"));
  REQUIRE(s["controller_handovers"].size() == 1);
  CHECK(s["controller_handovers"][0]["to"] == "ctl2");
  CHECK(server.run("remote quit").first == 0);
}
