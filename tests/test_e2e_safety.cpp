// End to end, issue 18: the safety net on the default mission (held seeds): a crash ends the
// flight; the safety monitor hands a misbehaving cruise controller (hard-over within the limits,
// silent, flying out of the envelope) to the fallback; the state-loss recovery flies through an
// IMU drop-out. Each flight is the shipped default mission with one edit.
#include <doctest/doctest.h>

#include <sys/wait.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "e2e_util.hpp"

using namespace tern::core;

namespace {

const std::string kTestController = (fs::path(TERN_TEST_PLUGIN_DIR) / "libtern_test_controller.so").string();

// The default mission with `ctl` (a test_controller with `params`) flying cruise, slc the rest
// and the fallback; `machine`: the phase_machine section, if any.
std::string cruise_flown_by(const std::string& params, const std::string& machine = "") {
  return default_mission_with({{"phases: {takeoff: slc, climb: slc, cruise: slc}",
                                "  - {name: ctl, plugin: " + kTestController + ", rate: 100, params: {" + params +
                                    "}}\nphases: {takeoff: slc, climb: slc, cruise: ctl}\nfallback: slc\n" + machine}});
}

// The lowest true altitude (m above the origin) between t0 and t1 (s), from truth.csv.
double lowest_altitude(const FlightResult& r, double t0, double t1) {
  const auto rows = lines(read_file(r.run_dir / "topics" / "truth.csv"));
  REQUIRE(rows.size() > 1);
  const auto header = cells(rows[0]);
  const auto col = static_cast<std::size_t>(std::find(header.begin(), header.end(), "p_d [m]") - header.begin());
  REQUIRE(col < header.size());
  // the whole window is in the table (a log that ended before t1 gave the rows there were, and
  // none at all 1e9: a check "> 30 m" passed on a flight that never got there)
  REQUIRE_MESSAGE(std::stod(cells(rows.back())[0]) >= t1, "truth.csv ends before t = " << t1 << " s");
  double low = 1e9;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const auto c = cells(rows[k]);
    const double t = std::stod(c[0]);
    if (t >= t0 && t <= t1) low = std::min(low, -std::stod(c[col]));
  }
  return low;
}

double instance_figure(const nlohmann::json& s, const std::string& inst, const std::string& key) {
  return s["instances"][inst][key].get<double>();
}

// The flight went on to its end with the aircraft flying, and the fallback took over for `cause`.
void check_saved(const FlightResult& r, const std::string& cause) {
  CHECK(r.ok);
  const auto s = summary(r);
  CHECK(s["end_reason"] == "duration");
  CHECK(instance_figure(s, "sim", "sim_crashed") == 0.0);
  CHECK(s["fallback_engaged"] == true);
  const auto& h = s["controller_handovers"];
  REQUIRE(h.size() >= 2);
  CHECK(h.back()["from"] == "ctl");
  CHECK(h.back()["to"] == "slc");
  CHECK_MESSAGE(h.back()["reason"].get<std::string>().find(cause) != std::string::npos, h.back()["reason"]);
  CHECK(read_file(r.run_dir / "tern.log").find(cause) != std::string::npos);
}

}  // namespace

TEST_CASE("issue 18: a dive into the ground ends the flight: end_reason crash, where and how fast, tern fly exits 1") {
  // an air start at 40 m, the elevator held at 0.69 rad (the test controller on the true state)
  const std::string yaml =
      "name: dive\nseed: 3\nduration: 60\naircraft: " + (kMissions / "../aircraft/anaconda.yaml").lexically_normal().string() +
      "\nplugins:\n  - {name: sim, plugin: sim_aero, rate: 400, params: {init_mode: air, init_altitude: 40, init_airspeed: 17}}\n"
      "  - {name: ctl, plugin: " +
      kTestController + ", rate: 100, remap: {state: truth}, params: {tag: 0.69, kp: 0}}\n";
  const FlightResult r = fly_yaml(yaml, "crash_dive", 3, 60.0);
  CHECK_FALSE(r.ok);
  CHECK(r.end_reason == "crash");
  CHECK(tern::to_seconds(r.flown) < 30.0);
  const auto s = summary(r);
  CHECK(s["end_reason"] == "crash");
  CHECK(s["end_detail"].get<std::string>().rfind("sim at t=", 0) == 0);
  CHECK(s["end_detail"].get<std::string>().find("hit the ground") != std::string::npos);
  CHECK(instance_figure(s, "sim", "sim_crashed") == 1.0);
  CHECK(instance_figure(s, "sim", "impact_t_s") == doctest::Approx(s["duration_s"].get<double>()).epsilon(0.01));
  CHECK(instance_figure(s, "sim", "impact_sink_rate_mps") > 0.0);
  CHECK(instance_figure(s, "sim", "impact_airspeed_mps") > 5.0);
  // the command line: exit status 1, and the last line says why
  const fs::path cfg = write_file("dive_cli.yaml", yaml);
  const fs::path out = test_dir() / "dive_cli.out";
  const int rc = std::system((std::string(TERN_BIN) + " fly " + cfg.string() + " --log-dir " + (test_dir() / "dive_cli").string() + " > " +
                              out.string() + " 2>/dev/null")
                                 .c_str());
  CHECK(WEXITSTATUS(rc) == 1);
  const auto text = lines(read_file(out));
  REQUIRE(!text.empty());
  CHECK_MESSAGE(text.back().rfind("FLIGHT ENDED EARLY (crash): sim at t=", 0) == 0, text.back());
}

TEST_CASE("issue 18: a hard-over within the limits in cruise (delta_e 0.69 of 0.7 rad, throttle 0) is caught within 2 s") {
  // throttle 0: h_target far below (kp pulls it to 0). Without the monitor the aircraft dives to
  // -84 deg of pitch and 19 m/s of sink before the phase machine's switch to climb.
  const FlightResult r = fly_yaml(cruise_flown_by("tag: 0.69, h_target: -100, kp: 10"), "hardover", 3, 150.0);
  check_saved(r, "safety monitor:");
  const auto s = summary(r);
  const auto& h = s["controller_handovers"];
  REQUIRE(h.size() >= 2);
  const auto& cruise = h[h.size() - 2];
  REQUIRE(cruise["to"] == "ctl");
  CHECK(h.back()["t_s"].get<double>() - cruise["t_s"].get<double>() < 2.0);
  CHECK(lowest_altitude(r, cruise["t_s"].get<double>(), 150.0) > 30.0);
}

TEST_CASE("issue 18: a cruise controller that stops publishing is replaced after safety_silent_periods") {
  const FlightResult r = fly_yaml(cruise_flown_by("fail_mode: silent, fail_at: 0"), "silent", 3, 150.0);
  check_saved(r, "silent: stepped 5 times in a row without publishing actuators");
}

TEST_CASE("issue 18: a cruise controller that rolls the aircraft out of the envelope is replaced") {
  const FlightResult r = fly_yaml(cruise_flown_by("tag: 0.168, h_target: 70, kp: 0.05, aileron: 0.15"), "envelope", 3, 150.0);
  check_saved(r, "envelope: roll");
}

TEST_CASE("issue 18: an IMU drop-out of 5 s in cruise: the state-loss recovery flies until the estimate is back") {
  const std::string yaml = default_mission_with({{"      pitot_cover: 8.5", "      pitot_cover: 8.5\n      imu_dropout: [200, 205]"}});
  const FlightResult r = fly_yaml(yaml, "imu_dropout", 3, 260.0);
  CHECK(r.ok);
  const auto s = summary(r);
  CHECK(instance_figure(s, "sim", "sim_crashed") == 0.0);
  const auto& h = s["controller_handovers"];
  bool in = false, out = false;
  for (const auto& x : h) {
    in = in || (x["to"] == "state_loss_recovery" && x["t_s"].get<double>() >= 200.0);
    out = out || (x["from"] == "state_loss_recovery" && x["to"] == "slc");
  }
  CHECK(in);
  CHECK(out);
  // without the recovery (phase_machine: {recovery: false}) the aircraft falls from 70 m to 13 m;
  // with it seed 3 loses 21 m (48.7 m at 206 s, as the re-initialised estimate hands back to slc;
  // 69 m when the same seed flies 1.3 s earlier, without the GNSS start-up checks' hold: another
  // gust at the drop-out). At least 40 m: the recovery keeps well over half the height.
  CHECK(lowest_altitude(r, 199.0, 230.0) > 40.0);
  CHECK(read_file(r.run_dir / "tern.log").find("state_loss_recovery: the estimate is invalid") != std::string::npos);
}
