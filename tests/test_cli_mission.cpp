// Issue 22 item 3: `tern check` reads the mission the path planner will fly, with the planner's
// own parser, and checks where its waypoints are; `tern fly` refuses the same errors before it
// flies. Errors: one line each naming file:line and the field, exit status 1; warnings: printed,
// exit status 0. On the shipped default mission, with its waypoints from a file (--set
// planner.mission_file) or inline (mission:).
#include <doctest/doctest.h>

#include "test_process.hpp"
#include "test_util.hpp"

namespace {

const std::string kDefault = std::string(TERN_SOURCE_DIR) + "/configs/missions/default.yaml";

struct Run {
  int rc;
  std::string out;
  bool has(const std::string& s) const { return out.find(s) != std::string::npos; }
};

Run run(const std::vector<std::string>& args) {
  const fs::path out = test_dir() / "tern.out";
  const int rc = run_tern(args, out);
  return {rc, read_file(out)};
}

/// `tern check` on the default mission flying the waypoint file `text`, plus `extra` options.
Run check_file(const std::string& name, const std::string& text, std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {"check", kDefault, "--set", "planner.mission_file=" + write_file(name, text).string()};
  args.insert(args.end(), extra.begin(), extra.end());
  return run(args);
}

/// The default mission with its `mission:` section replaced by `mission` (and `top` added).
fs::path inline_config(const std::string& name, const std::string& mission, const std::string& top = "") {
  std::string cfg = read_file(kDefault);
  for (const std::string dir : {"../aircraft/", "../gains/"})
    for (auto at = cfg.find(dir); at != std::string::npos; at = cfg.find(dir))
      cfg.replace(at, dir.size(), std::string(TERN_SOURCE_DIR) + "/configs/" + dir.substr(3));
  cfg = cfg.substr(0, cfg.find("mission:\n  file:")) + top + mission;
  return write_file(name, cfg);
}

}  // namespace

TEST_CASE("an unknown key in a ROSplane waypoint file: file:line, the field and the closest key; exit 1") {
  const Run r = check_file("use_chii.yaml", "wp:\n  w: [400.0, -250.0, -70.0]\n  chi_d: 1.1518\n  use_chii: False\n  va_d: 17.0\n");
  CHECK(r.rc == 1);
  CHECK(r.has("tern: error: " + (test_dir() / "use_chii.yaml").string() + ":4: wp 1: unknown key 'use_chii' (did you mean 'use_chi'?)\n"));
  CHECK_FALSE(r.has("config OK"));
}

TEST_CASE("types and latitude/longitude ranges") {
  Run r = check_file("type.yaml", "waypoints:\n  - [400, -250, -70]\n  - {ned: [0, 0, -70], Va_d: fast}\n");
  CHECK(r.rc == 1);
  CHECK(r.has(":3: waypoints[1].Va_d: 'fast' is not a number\n"));
  r = check_file("lat.yaml", "waypoints:\n  - {lla: [95.0, -111.65, 1457.0]}\n");
  CHECK(r.rc == 1);
  CHECK(r.has(":2: waypoints[0]: latitude 95 deg is outside [-90, 90]\n"));
  r = check_file("lon.yaml", "waypoints:\n  - {lla: [40.25, -191.65, 1457.0]}\n");
  CHECK(r.rc == 1);
  CHECK(r.has(":2: waypoints[0]: longitude -191.65 deg is outside [-180, 180]\n"));
}

TEST_CASE("below the ground, and the lla flag forgotten (a warning besides), against the simulator's origin") {
  const std::string file = write_file("lla_forgotten.yaml",
                                      "wp:\n  w: [400.0, -250.0, -70.0]\n  va_d: 17.0\n"
                                      "wp:\n  w: [40.2499718, -111.6503560, 1457.0]\n  lla: False\n  va_d: 17.0\n")
                               .string();
  Run r = run({"check", kDefault, "--set", "planner.mission_file=" + file});
  CHECK(r.rc == 1);
  CHECK(r.has("tern: warning: " + file +
              ":4: wp 2: [40.2499718, -111.650356, 1457] is NED (m) but looks like latitude, longitude, "
              "altitude: lla: true forgotten?\n"));
  CHECK(r.has("tern: error: " + file + ":4: wp 2: down = 1457 m: 1457.0 m below home, below the ground"));
  // an LLA altitude below the simulator's ground (origin_alt 1387 m)
  r = check_file("lla_low.yaml", "waypoints:\n  - [0, 300, -70]\n  - {lla: [40.2499718, -111.6503560, 1300.0]}\n");
  CHECK(r.rc == 1);
  CHECK(r.has(":3: waypoints[1]: altitude 1300 m MSL is 87.0 m below home (1387 m MSL): below the ground\n"));
  // tern fly refuses it before flying: no run directory
  r = run(
      {"fly", kDefault, "--set", "planner.mission_file=" + file, "-q", "--duration", "1", "--log-dir", (test_dir() / "refused").string()});
  CHECK(r.rc == 1);
  CHECK(r.has("tern: error: " + file + ":4: wp 2: down = 1457 m"));
  CHECK_FALSE(fs::exists(test_dir() / "refused"));
}

TEST_CASE("too far from home: 5 km by default, check.max_waypoint_distance in the config") {
  Run r = check_file("far.yaml", "waypoints:\n  - [400, -250, -70]\n  - [-21996, 250, -70]\n");
  CHECK(r.rc == 1);
  CHECK(r.has(":3: waypoints[1]: 21997.5 m from home, further than check.max_waypoint_distance = 5000 m\n"));
  const fs::path cfg = inline_config("near.yaml", "mission:\n  waypoints:\n    - [400, -250, -70]\n    - [-400, -50, -70]\n",
                                     "check: {max_waypoint_distance: 300}\n");
  r = run({"check", cfg.string()});
  CHECK(r.rc == 1);
  // inline waypoints: the config file's own lines
  const auto n = lines(read_file(cfg)).size();
  CHECK(r.has(cfg.string() + ":" + std::to_string(n - 1) +
              ": waypoints[0]: 476.9 m from home, further than check.max_waypoint_distance = 300 m\n"));
  CHECK(r.has(cfg.string() + ":" + std::to_string(n) + ": waypoints[1]: 409.1 m from home"));
}

TEST_CASE("legs shorter than the path manager's R_min, the radius as configured") {
  const std::string mission = "waypoints:\n  - [400, -250, -70]\n  - [-400, -50, -70]\n  - [-400, -80, -70]\n  - [400, -50, -70]\n";
  Run r = check_file("short.yaml", mission);
  CHECK(r.rc == 1);
  CHECK(
      r.has(":4: waypoints[2]: the leg from waypoints[1] is 30.0 m, shorter than the minimum turn radius manager.R_min = 50 m: "
            "no room to turn\n"));
  r = check_file("short.yaml", mission, {"--set", "manager.R_min=25"});
  CHECK(r.rc == 0);
  CHECK(r.has("config OK"));
}

TEST_CASE("legal but suspicious: warnings, exit 0") {
  const Run r = check_file("lla_like.yaml",
                           "waypoints:\n  - [400, -250, -70]\n  - {w: [40.2499718, -111.6503560, -70], lla: false}\n"
                           "  - [-400, -250, -70]\n");
  CHECK(r.rc == 0);
  CHECK(r.has("tern: warning: "));
  CHECK(r.has(":3: waypoints[1]: [40.2499718, -111.650356, -70] is NED (m) but looks like latitude"));
  CHECK(r.has("config OK"));
}

TEST_CASE("the shipped missions with the stock controller back in cruise: TECS idle, no second writer") {
  const Run r =
      run({"check", std::string(TERN_SOURCE_DIR) + "/configs/missions/tecs.yaml", "--phases", "takeoff=slc,climb=slc,cruise=slc"});
  CHECK(r.rc == 0);
  CHECK(r.has("(not routed: idle, never steps, writes nothing)"));
  CHECK(r.has("config OK"));
}
