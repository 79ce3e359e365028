// Every bad input of the host gets one clear line naming file, field and value.
#include <doctest/doctest.h>

#include <sys/wait.h>

#include <cstdlib>

#include <yaml-cpp/yaml.h>

#include "config/error.hpp"
#include "tern/plugin.hpp"
#include "test_util.hpp"

using doctest::Contains;

TEST_CASE("a valid config builds") { CHECK(build_error(base_config()) == ""); }

TEST_CASE("missing config file") {
  try {
    tern::core::load_config(test_dir() / "nope.yaml");
    FAIL("no error");
  } catch (const tern::core::ConfigError& e) {
    CHECK(std::string(e.what()) == "config file '" + (test_dir() / "nope.yaml").string() + "' not found");
  }
}

TEST_CASE("YAML syntax error names line and column") {
  const std::string e = build_error("name: x\nplugins: [\n  {name: a,\n", "syntax.yaml");
  CHECK(e.find("syntax.yaml:4:1: YAML syntax error:") != std::string::npos);
}

TEST_CASE("unknown keys suggest the closest valid one") {
  CHECK(build_error(base_config("", "sead: 3\n")) ==
        (test_dir() / "cfg.yaml").string() + ":5:1: unknown key 'sead' (did you mean 'seed'?)");
  const std::string e = build_error(base_config("  - {name: x, plugin: test_controller, rat: 100}\n"));
  CHECK(e.find(":9:40: plugins[3]: unknown key 'rat' (did you mean 'rate'?)") != std::string::npos);
}

TEST_CASE("a key given twice in one map is refused: YAML forbids it, and yaml-cpp would read the first silently") {
  CHECK(build_error(base_config("", "seed: 3\n")) ==  // base_config sets seed on line 2
        (test_dir() / "cfg.yaml").string() + ":5:1: key 'seed' given twice (first at line 2): one of the two would be ignored");
  const std::string e = build_error(base_config("  - {name: x, plugin: test_controller, rate: 100, params: {kp: 1, kp: 2}}\n"));
  CHECK(e.find(":9:67: plugins[3].params: key 'kp' given twice (first at line 9): one of the two would be ignored") != std::string::npos);
}

TEST_CASE("log.format, log.chunk_size, log.ros_channels, log.zstd_level: one line naming the key and the value") {
  auto with_log = [](const std::string& log) {
    std::string y = base_config();
    return y.replace(y.find("log: {max_rate: 0}"), 18, "log: {" + log + "}");
  };
  CHECK(build_error(with_log("format: mcap, chunk_size: 65536")) == "");
  CHECK(build_error(with_log("format: parquet")).find(":4:15: log.format: expected csv, mcap or both, got 'parquet'") != std::string::npos);
  CHECK(build_error(with_log("chunk_size: 10")).find("log.chunk_size: must be 1024 to 1073741824 bytes, got 10") != std::string::npos);
  CHECK(build_error(with_log("format: mcap, ros_channels: false")) == "");
  CHECK(build_error(with_log("ros_channels: maybe")).find("log.ros_channels: expected true or false, got 'maybe'") != std::string::npos);
  CHECK(build_error(with_log("ros_channels: [true]")).find("log.ros_channels: expected true or false, got '<list>'") != std::string::npos);
  CHECK(build_error(with_log("format: mcap, zstd_level: -5")) == "");
  CHECK(build_error(with_log("zstd_level: 22")).find("log.zstd_level: must be an integer from -7 to 19, got 22") != std::string::npos);
  CHECK(build_error(with_log("zstd_level: 1.5")).find("log.zstd_level: must be an integer from -7 to 19, got 1.5") != std::string::npos);
  CHECK(build_error(with_log("zstd_level: fast")).find("log.zstd_level") != std::string::npos);
}

TEST_CASE("every boolean setting reads the same words (yaml_bool): true/false, True/FALSE, yes/no, on/off") {
  const std::filesystem::path f = test_dir() / "bools.yaml";
  const YAML::Node words = YAML::Load("[true, True, TRUE, yes, on, false, False, no, Off]");
  const std::vector<bool> expected{true, true, true, true, true, false, false, false, false};
  for (std::size_t i = 0; i < expected.size(); ++i) CHECK(tern::core::yaml_bool(words[i], f, "x") == expected[i]);
  for (const char* bad : {"1", "maybe", "truee", "~"}) {
    INFO(bad);
    CHECK_THROWS_WITH_AS(tern::core::yaml_bool(YAML::Load(bad), f, "a.b"), doctest::Contains("a.b: expected true or false"),
                         tern::core::ConfigError);
  }
}

TEST_CASE("plugin not found prints the search path") {
  const std::string e = build_error(base_config("  - {name: x, plugin: test_sensr, rate: 400}\n"));
  CHECK(e.find("plugins[3].plugin: plugin 'test_sensr' not found: no libtern_test_sensr.so in the plugin search path [") !=
        std::string::npos);
  CHECK(e.find(TERN_TEST_PLUGIN_DIR) != std::string::npos);
  CHECK(e.find("(did you mean 'test_sensor'?)") != std::string::npos);
}

TEST_CASE("a shared object that is not a tern plugin") {
  const std::string e = build_error(base_config("  - {name: x, plugin: not_a_plugin, rate: 400}\n"));
  CHECK(e.find("libtern_not_a_plugin.so' is not a tern plugin: it has no tern_plugin_handshake_v1 symbol") != std::string::npos);
}

TEST_CASE("handshake mismatches are refused before any plugin code runs") {
  // the factories of these plugins abort(): reaching them would kill the test
  std::string e = build_error(base_config("  - {name: x, plugin: " TERN_TEST_PLUGIN_DIR "/libtern_test_bad_api.so, rate: 400}\n"));
  CHECK(e.find("plugin 'test_bad_api'") != std::string::npos);
  CHECK(e.find("SDK API version mismatch: plugin built for API 999, this host speaks API " + std::to_string(tern::kSdkApiVersion)) !=
        std::string::npos);
  e = build_error(base_config("  - {name: x, plugin: " TERN_TEST_PLUGIN_DIR "/libtern_test_bad_abi.so, rate: 400}\n"));
  CHECK(e.find("plugin 'test_bad_abi'") != std::string::npos);
  CHECK(e.find("ABI mismatch: plugin built with 'libstdc++9;cxx11abi=0;eigen=3.3.7;eigen_align=32', host with '") != std::string::npos);
  e = build_error(base_config("  - {name: x, plugin: " TERN_TEST_PLUGIN_DIR "/libtern_test_bad_fingerprint.so, rate: 400}\n"));
  CHECK(e.find("plugin 'test_bad_fingerprint'") != std::string::npos);
  CHECK(e.find("message fingerprint mismatch: tern/Imu is 0123456789abcdef in the plugin") != std::string::npos);
}

TEST_CASE("two writers on one topic") {
  const std::string e = build_error(base_config("  - {name: ctl2, plugin: test_controller, rate: 100}\n"));
  CHECK(e.find("topic 'actuators' has 2 writers: ctl.actuators, ctl2.actuators (only controllers behind the phase router") !=
        std::string::npos);
  // the same two behind the phase router are fine
  CHECK(build_error(base_config("  - {name: ctl2, plugin: test_controller, rate: 100}\n",
                                "phases: {takeoff: ctl, climb: ctl, cruise: ctl2}\n")) == "");
}

TEST_CASE("an input with no producer is named") {
  const std::string e = build_error("name: t\nplugins:\n  - {name: filter, plugin: test_filter, rate: 100}\n");
  CHECK(e.find("input 'filter.imu' (topic 'imu', tern/Imu) has no producer") != std::string::npos);
  const std::string r =
      build_error(base_config("", "").replace(base_config().find("trigger: imu"), 12, "trigger: imu, remap: {imu: imu2}"));
  CHECK(r.find("input 'filter.imu' (topic 'imu2', tern/Imu) has no producer: no instance publishes 'imu2' (did you mean 'imu'?)") !=
        std::string::npos);
}

TEST_CASE("a rate the base rate cannot serve") {
  std::string cfg = base_config();
  cfg.replace(cfg.find("rate: 100"), 9, "rate: 390");
  std::string e = build_error(cfg);
  CHECK(e.find(":8:48: plugins[2].rate: 390 Hz cannot be served by the base rate 400 Hz") != std::string::npos);
  cfg = base_config();
  cfg.replace(cfg.find("rate: 100"), 9, "rate: 800");
  CHECK(build_error(cfg).find("800 Hz cannot be served by the base rate 800 Hz") == std::string::npos);  // 800 becomes the base
  CHECK(build_error(cfg, "r.yaml") == "");
  CHECK(build_error(base_config("", "base_rate: 400\n").replace(base_config("", "base_rate: 400\n").find("rate: 100"), 9, "rate: 160"))
            .find("160 Hz cannot be served by the base rate 400 Hz") != std::string::npos);
}

TEST_CASE("parameters: out of range, wrong type, unknown") {
  std::string e = build_error(base_config(
      "  - {name: c2, plugin: test_controller, rate: 100, remap: {actuators: a2, controller_internals: ci2}, params: {kp: 11}}\n"));
  CHECK(e.find(":9:116: plugins[3].params.kp: parameter 'c2.kp': value 11 is outside the valid range [0, 10] 1/m") != std::string::npos);
  e = build_error(base_config(
      "  - {name: c2, plugin: test_controller, rate: 100, remap: {actuators: a2, controller_internals: ci2}, params: {kp: fast}}\n"));
  CHECK(e.find("plugins[3].params.kp: parameter 'c2.kp': value \"fast\" has the wrong type: expected a number, got a string") !=
        std::string::npos);
  e = build_error(base_config(
      "  - {name: c2, plugin: test_controller, rate: 100, remap: {actuators: a2, controller_internals: ci2}, params: {kq: 1}}\n"));
  CHECK(e.find("plugins[3].params.kq: unknown parameter 'kq' of plugin 'test_controller' (did you mean 'kp'?)") != std::string::npos);
  e =
      build_error(base_config("  - {name: c2, plugin: test_controller, rate: 100, remap: {actuators: a2, controller_internals: ci2}, "
                              "params: {fail_mode: loud}}\n"));
  CHECK(e.find("parameter 'c2.fail_mode': value \"loud\" is not one of none, throw, nan") != std::string::npos);
}

TEST_CASE("parameter files: flat and ROS 2 style") {
  write_file("gains_flat.yaml", "kp: 0.2\ntag: 0.1\n");
  write_file("gains_ros.yaml", "/**:\n  ros__parameters:\n    kp: 0.3\n    unrelated_gain: 4.0\nctl:\n  ros__parameters:\n    tag: 0.2\n");
  std::string cfg = base_config();
  cfg.replace(cfg.find("rate: 100}"), 10, "rate: 100, param_file: gains_flat.yaml}");
  CHECK(build_error(cfg) == "");
  cfg = base_config();
  cfg.replace(cfg.find("rate: 100}"), 10, "rate: 100, param_file: gains_ros.yaml}");
  const fs::path p = write_file("ros.yaml", cfg);
  tern::core::HostOptions o;
  o.describing = true;
  o.quiet = true;
  tern::core::Host h(tern::core::load_config(p), o);
  h.build();
  for (const auto& [name, prm] : h.parameters()) {
    if (name == "ctl.kp") CHECK(std::get<double>(prm->value()) == 0.3);
    if (name == "ctl.tag") CHECK(std::get<double>(prm->value()) == 0.2);
  }
  cfg = base_config();
  cfg.replace(cfg.find("rate: 100}"), 10, "rate: 100, param_file: missing.yaml}");
  CHECK(build_error(cfg).find("plugins[2].param_file: '" + (test_dir() / "missing.yaml").string() + "' not found") != std::string::npos);
}

TEST_CASE("other structural errors") {
  CHECK(build_error("name: t\n").find("plugins: missing") != std::string::npos);
  CHECK(build_error("name: t\nplugins:\n  - {name: s, plugin: test_sensor}\n").find("plugins[0] (s): missing 'rate' (Hz) or 'trigger'") !=
        std::string::npos);
  CHECK(build_error(base_config("", "phases: {takeoff: ctl, climb: ctl}\n")).find("phases: no controller for phase 'cruise'") !=
        std::string::npos);
  CHECK(build_error(base_config("", "phases: {takeoff: ctl, climb: ctl, cruise: clt}\n"))
            .find("phases.cruise: no plugin instance named 'clt' (did you mean 'ctl'?)") != std::string::npos);
  std::string neg = base_config();
  neg.replace(neg.find("duration: 2"), 11, "duration: -1");
  CHECK(build_error(neg).find(":3:11: duration: must be > 0 s, got -1") != std::string::npos);
  std::string cfg = base_config();
  cfg.replace(cfg.find("trigger: imu"), 12, "trigger: imu_data");
  CHECK(build_error(cfg).find("plugins[1].trigger: plugin 'test_filter' has no input port 'imu_data' (did you mean 'imu'?)") !=
        std::string::npos);
}

TEST_CASE("issue 18: the fallback and every phase must name a controller instance") {
  const std::string file = (test_dir() / "cfg.yaml").string();
  // the sensor is an I/O plugin: before, this flew an empty flight with exit status 0
  CHECK(build_error(base_config("", "phases: {takeoff: ctl, climb: ctl, cruise: ctl}\nfallback: sensor\n")) ==
        file + ":6:11: fallback: 'sensor' is not a controller: it runs plugin 'test_sensor' (io); name one of: ctl");
  CHECK(build_error(base_config("", "phases: {takeoff: ctl, climb: filter, cruise: ctl}\n")) ==
        file + ":5:31: phases.climb: 'filter' is not a controller: it runs plugin 'test_filter' (estimator); name one of: ctl");
  CHECK(
      build_error(base_config("  - {name: idle, plugin: test_null, rate: 100}\n", "phases: {takeoff: ctl, climb: ctl, cruise: idle}\n")) ==
      file + ":5:44: phases.cruise: 'idle' is not a controller: it runs plugin 'test_null' (generic); name one of: ctl");
}

TEST_CASE("issue 18: tern check refuses a fallback that is not a controller, in one line naming file, field and value") {
  const fs::path cfg =
      write_file("check_fallback.yaml", base_config("", "phases: {takeoff: ctl, climb: ctl, cruise: ctl}\nfallback: sensor\n"));
  const fs::path out = test_dir() / "check_fallback.out";
  const int rc = std::system((std::string(TERN_BIN) + " check " + cfg.string() + " > " + out.string() + " 2>&1").c_str());
  CHECK(WEXITSTATUS(rc) == 1);
  CHECK(read_file(out) == "tern: error: " + cfg.string() +
                              ":6:11: fallback: 'sensor' is not a controller: it runs plugin 'test_sensor' (io); "
                              "name one of: ctl\n");
}
