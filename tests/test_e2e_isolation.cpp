// End to end, issue 19 item 1: isolation on the default mission. Every plugin isolated flies
// byte-identical CSV logs to the in-process flight of the same seed; an isolated cruise
// controller that segfaults is replaced by the fallback in the same tick and the aircraft flies
// on to the end of the flight, with a complete log.
#include <doctest/doctest.h>

#include <cmath>
#include <map>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "e2e_util.hpp"

using namespace tern::core;

namespace {

const std::string kTestController = (fs::path(TERN_TEST_PLUGIN_DIR) / "libtern_test_controller.so").string();

// `yaml` with `isolate: true` on every instance of `plugins:` (entries start "  - name: ").
std::string isolate_all(std::string yaml) {
  std::size_t n = 0;
  for (std::size_t at = yaml.find("  - name: "); at != std::string::npos; at = yaml.find("  - name: ", at + 20)) {
    yaml.insert(at + 4, "isolate: true\n    ");
    ++n;
  }
  REQUIRE(n == 6);
  return yaml;
}

std::map<std::string, std::string> csv_files(const fs::path& run) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(run / "topics")) out[e.path().filename().string()] = read_file(e.path());
  out["params.csv"] = read_file(run / "params.csv");
  return out;
}

}  // namespace

TEST_CASE("issue 19: the default mission with every plugin isolated logs byte-identical CSVs (same seed)") {
  const std::string yaml = default_mission_with({});
  const FlightResult a = fly_yaml(yaml, "iso_e2e_plain", 1, 40.0);
  const FlightResult b = fly_yaml(isolate_all(yaml), "iso_e2e_isolated", 1, 40.0);
  REQUIRE(a.ok);
  REQUIRE(b.ok);
  const auto fa = csv_files(a.run_dir), fb = csv_files(b.run_dir);
  CHECK(fa.size() >= 10);
  REQUIRE(fa.size() == fb.size());
  for (const auto& [name, text] : fa) {
    INFO(name);
    REQUIRE(fb.count(name));
    if (name == "params.csv")  // the configs differ in their name or layout: the sources' file:line with them
      CHECK(config_sources_neutral(text) == config_sources_neutral(fb.at(name)));
    else
      CHECK(text == fb.at(name));
  }
  CHECK(summary(a)["instances"] == summary(b)["instances"]);  // the plugins' summary figures crossed
}

TEST_CASE("issue 19: an isolated cruise controller that segfaults: the fallback takes over in that tick, the flight goes on") {
  // ctl flies cruise (from about 22 s with seed 3, elevator held at slc's cruise trim) and segfaults at 24 s, or at its first step
  // if cruise comes later
  const std::string yaml =
      default_mission_with({{"phases: {takeoff: slc, climb: slc, cruise: slc}",
                             "  - {name: ctl, plugin: " + kTestController +
                                 ", rate: 100, isolate: true, params: {tag: 0.17, h_target: 70, kp: 0.05, fail_mode: segv, fail_at: 24}}\n"
                                 "phases: {takeoff: slc, climb: slc, cruise: ctl}\nfallback: slc\n"}});
  const FlightResult r = fly_yaml(yaml, "iso_e2e_segv", 3, 120.0);
  CHECK(r.ok);
  const auto s = summary(r);
  CHECK(s["end_reason"] == "duration");
  CHECK(s["duration_s"].get<double>() == 120.0);
  CHECK(s["instances"]["sim"]["sim_crashed"].get<double>() == 0.0);
  CHECK(s["fallback_engaged"] == true);
  const auto& h = s["controller_handovers"];
  REQUIRE(h.size() >= 2);
  CHECK(h[h.size() - 2]["to"] == "ctl");
  CHECK(h.back()["from"] == "ctl");
  CHECK(h.back()["to"] == "slc");
  CHECK(h.back()["reason"] == "fallback for the rest of the flight: isolated instance ctl died: SIGSEGV");
  CHECK(h.back()["t_s"].get<double>() >= 24.0);
  // the same tick: a command stamped with the time ctl died (slc's, since ctl died in its step)
  const auto rows = lines(read_file(r.run_dir / "topics" / "actuators.csv"));
  const double t_death = h.back()["t_s"].get<double>();
  const std::string at_death = fmt::format("{:.9f},{},", t_death, std::llround(t_death * 1e9));
  bool slc_at_death = false;
  for (const auto& row : rows) slc_at_death = slc_at_death || row.rfind(at_death, 0) == 0;
  CHECK(slc_at_death);
  CHECK(rows.back().rfind("120.000000000,", 0) == 0);  // the log goes on to the end
  const std::string log = read_file(r.run_dir / "tern.log");
  CHECK(log.find("controller ctl -> slc: fallback for the rest of the flight: isolated instance ctl died: SIGSEGV") != std::string::npos);
}
