// Issue 79 item 5: QGroundControl's .plan files. QGroundControl's own fixed-wing test plan flies in
// simulation unchanged (`tern fly --plan`) to its landing; a config's mission is written as a plan
// (`tern export plan`) that reads back (`tern check --plan`); a bad plan is one line naming the field;
// a run's plan (`tern export plan RUN`) is the mission as its log says it flew.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include "test_process.hpp"
#include "test_util.hpp"

namespace {

const std::string kDefault = std::string(TERN_SOURCE_DIR) + "/configs/missions/default.yaml";
const std::string kPlans = std::string(TERN_SOURCE_DIR) + "/tests/data/qgc_plans/";

std::pair<int, std::string> run_cli(const std::vector<std::string>& args) {
  const fs::path out = test_dir() / "tern.out";
  const int rc = run_tern(args, out);
  return {rc, read_file(out)};
}

}  // namespace

TEST_CASE("QGroundControl's fixed-wing test plan flies unchanged, from its home to its landing") {
  const fs::path logs = test_dir() / "plan_runs";
  const auto [rc, out] = run_cli({"fly", kDefault, "--plan", kPlans + "PX4SITL-ArduPlane.plan", "--duration", "2500", "--log-level",
                                  "summary", "-q", "--log-dir", logs.string()});
  INFO(out);
  REQUIRE(rc == 0);
  fs::path run;
  for (const auto& e : fs::directory_iterator(logs)) run = e.path();
  const auto summary = nlohmann::json::parse(read_file(run / "summary.json"));
  CHECK(summary["end_reason"] == "landed");
  // takeoff, 2 waypoints, the loiter at the altitude before it, the terrain-frame waypoint, the
  // loiter down to 80 m, 2 waypoints flown with the ground speed: all passed, then the landing
  CHECK(summary["instances"]["manager"]["waypoints_passed"] == 8.0);
  CHECK(summary["instances"]["phase_machine"]["go_arounds"] == 0.0);
  const std::string config = read_file(run / "config.yaml");
  CHECK(config.find("--set sim.origin_lat=47.39") != std::string::npos);  // the plan's home is the world's origin
  CHECK(config.find("--plan " + kPlans + "PX4SITL-ArduPlane.plan") != std::string::npos);
}

TEST_CASE("a config's mission written as a plan reads back; a bad plan is one line naming the field") {
  const fs::path plan = test_dir() / "default.plan";
  fs::remove(plan);
  auto [rc, out] = run_cli({"export", "plan", kDefault, plan.string()});
  INFO(out);
  REQUIRE(rc == 0);
  const auto j = nlohmann::json::parse(read_file(plan));
  const auto& items = j["mission"]["items"];
  REQUIRE(items.size() >= 6);
  CHECK(items[items.size() - 1]["command"] == 21);  // NAV_LAND last
  // loops: 5 as a DO_JUMP before it (repeated 4 times), then the land item's airspeed (15 m/s)
  CHECK(items[items.size() - 3]["command"] == 177);
  CHECK(items[items.size() - 3]["params"][1] == 4.0);
  CHECK(items[items.size() - 2]["command"] == 178);
  CHECK(items[items.size() - 2]["params"][1] == 15.0);
  CHECK(j["mission"]["plannedHomePosition"][0] == doctest::Approx(40.2463).epsilon(1e-3));
  std::tie(rc, out) = run_cli({"check", kDefault, "--plan", plan.string()});
  CHECK(rc == 0);
  std::tie(rc, out) = run_cli({"export", "plan", kDefault, plan.string()});
  CHECK(rc == 1);  // never overwritten
  const fs::path bad = write_file("bad.plan", R"({"fileType": "Plan", "mission": {"plannedHomePosition": [47, 8, 400], "items": [
    {"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, 0, 47.1, 8, "high"]}]}})");
  std::tie(rc, out) = run_cli({"check", kDefault, "--plan", bad.string()});
  CHECK(rc == 1);
  CHECK(out.find("--plan: " + bad.string() + ": mission.items[0].params[6]: expected a number or null, got \"high\"") != std::string::npos);
  const fs::path refused = write_file("refused.plan", R"({"fileType": "Plan", "mission": {"plannedHomePosition": [47, 8, 400], "items": [
    {"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, 0, 47.01, 8, 50]},
    {"type": "SimpleItem", "command": 183, "frame": 2, "params": [1, 1500, 0, 0, 0, 0, 0]}]}})");
  std::tie(rc, out) = run_cli({"check", kDefault, "--plan", refused.string()});
  CHECK(rc == 1);
  CHECK(out.find("mission item 1 (MAV_CMD 183): not a mission item tern flies") != std::string::npos);
}

TEST_CASE("a run's plan is the mission as it flew, read from its MCAP log; without a list, the config's") {
  const fs::path logs = test_dir() / "export_runs";
  fs::remove_all(logs);
  auto [rc, out] = run_cli({"fly", kDefault, "--duration", "20", "--log-format", "mcap", "-q", "--log-dir", logs.string()});
  REQUIRE(rc == 0);
  fs::path run;
  for (const auto& e : fs::directory_iterator(logs)) run = e.path();
  REQUIRE(fs::exists(run / "flight.mcap"));
  REQUIRE_FALSE(fs::exists(run / "topics"));
  const fs::path flown = test_dir() / "flown.plan", configured = test_dir() / "configured.plan";
  fs::remove(flown), fs::remove(configured);
  std::tie(rc, out) = run_cli({"export", "plan", run.string(), flown.string()});
  INFO(out);
  REQUIRE(rc == 0);
  CHECK(out.find("the mission as flown (its last waypoint list, revision 1") != std::string::npos);
  REQUIRE(run_cli({"export", "plan", kDefault, configured.string()}).first == 0);
  CHECK(read_file(flown) == read_file(configured));  // nothing changed it in flight: the config's, loops and all
  fs::remove(run / "flight.mcap");
  fs::remove(flown);
  std::tie(rc, out) = run_cli({"export", "plan", run.string(), flown.string()});
  CHECK(rc == 0);
  CHECK(out.find("the log has no waypoint list: the config's mission") != std::string::npos);
  CHECK(read_file(flown) == read_file(configured));
}
