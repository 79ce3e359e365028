// End to end: the default mission's preflight with the realistic profile: the simulated FCU
// calibrates its gyro and pitot at power-up (7.7 s), the estimator aligns, the arming checks
// hold, then the aircraft takes off; each arming check, violated, refuses with its own line.
#include <doctest/doctest.h>

#include <string>

#include "e2e_util.hpp"

using namespace tern::core;

namespace {
const std::string kPhases = "phases: {takeoff: slc, climb: slc, cruise: slc}";
}  // namespace

TEST_CASE("preflight, realistic profile: 5 seeds wait for the FCU's calibration and the alignment, then fly") {
  const std::string text = default_mission_with({});
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const FlightResult r = fly_yaml(text, "e2e_preflight_" + std::to_string(seed), seed, 150.0);
    INFO("seed " << seed);
    REQUIRE(r.ok);
    const auto s = summary(r);
    CHECK(s["end_reason"] == "duration");
    REQUIRE(s["phases"].size() >= 4);
    CHECK(s["phases"][0]["phase"] == "preflight");
    CHECK(s["phases"][1]["phase"] == "takeoff");
    const double preflight = s["preflight_s"].get<double>();
    MESSAGE("seed " << seed << ": preflight (FCU calibration, alignment, 2 s of passing checks) " << preflight << " s");
    CHECK(preflight >= 7.7 + 2.0);  // the FCU arms after its calibration; the checks then hold 2 s
    CHECK(preflight < 15.0);
    CHECK(s["instances"]["sim"]["sim_crashed"].get<double>() == 0.0);
    CHECK(s["instances"]["ekf"]["filter_resets"].get<double>() == 0.0);
    CHECK(s["instances"]["ekf"]["mag_resets"].get<double>() == 0.0);
    CHECK(s["instances"]["manager"]["waypoints_passed"].get<double>() >= 4);
  }
}

TEST_CASE("preflight, realistic profile: each arming check refuses with its line, then preflight_failed") {
  struct Case {
    std::pair<std::string, std::string> edit;
    std::string line;
  };
  const std::string sim = "sensor_profile: realistic";
  const Case cases[] = {
      {{sim, sim + "\n      gnss_h_acc: 4.2"}, "GNSS h_acc 4.2 m > 2.5 m"},
      {{sim, sim + "\n      baro_enabled: false"}, "estimator not ready (status degraded: no usable baro"},
      {{sim, sim + "\n      imu_nan: [0, 1000]"}, "estimator not ready (status invalid: no usable imu"},
      {{kPhases, kPhases + "\nphase_machine: {preflight_max_gyro_bias_sigma: 1.0e-5}"}, "estimator gyro bias not converged"},
      {{kPhases, kPhases + "\nphase_machine: {preflight_require_rc: true}"}, ""},  // the simulated receiver is heard
  };
  int k = 0;
  for (const Case& c : cases) {
    std::vector<std::pair<std::string, std::string>> edits{c.edit};
    if (c.edit.first == sim)
      edits.emplace_back(kPhases, kPhases + "\nphase_machine: {preflight_timeout: 10}");
    else
      edits.emplace_back("phase_machine: {", "phase_machine: {preflight_timeout: 10, ");
    const FlightResult r = fly_yaml(default_mission_with(edits), "e2e_preflight_check_" + std::to_string(k++), 1, 40.0);
    INFO(c.edit.second);
    if (c.line.empty()) {
      CHECK(r.ok);
      CHECK(summary(r)["phases"][1]["phase"] == "takeoff");
      continue;
    }
    CHECK_FALSE(r.ok);
    CHECK(r.end_reason.rfind("preflight_failed: ", 0) == 0);
    CHECK_MESSAGE(r.end_reason.find(c.line) != std::string::npos, r.end_reason);
    // the time-out counts from the FCU's arming (after its 7.7-s calibration; a dead IMU never lets it finish)
    if (c.line.find("imu") == std::string::npos) CHECK(tern::to_seconds(r.flown) == doctest::Approx(17.7).epsilon(0.01));
    CHECK(summary(r)["end_reason"] == r.end_reason);
  }
}
