// tests/fuzz/fuzz_host.hpp: the host the fuzz targets of tern's request handlers feed (the flight
// console, the ground station's mission protocol, the DDS bridge): built once per fuzzing process
// from the test plugins (tests/plugins: test_sensor at 400 Hz; test_filter on each IMU sample,
// publishing a valid state with an origin; test_controller at 100 Hz), from a config written into
// the process's own directory (fuzz_input.hpp in_dir). Its flights, if the target flies any, log
// under that directory's runs/. A target that includes this defines TERN_FUZZ_TEST_PLUGIN_DIR
// (tests/fuzz/CMakeLists.txt).
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "config/config.hpp"
#include "flight/host.hpp"
#include "fuzz_input.hpp"

namespace tern::fuzz {

struct TestPluginHost {
  std::unique_ptr<tern::core::Host> host;  // built, not flown
  std::filesystem::path config;            // the config file
  std::filesystem::path dir;               // its directory (the process's own)
  std::filesystem::path runs;              // dir/runs: where its flights log
};

/// The test plugins' host named `name` (its mission's name: one folder name), flights 0.2 s long;
/// `extra_yaml` is appended to the config at its top level (e.g. a `failsafes:` block).
/// Throws what load_config and Host::build throw (a test plugin missing from the plugin path).
inline TestPluginHost test_plugin_host(const std::string& name, const std::string& extra_yaml = "") {
  const std::string config = "name: " + name + "\nduration: 0.2\nplugin_path: [" + TERN_FUZZ_TEST_PLUGIN_DIR +
                             "]\nplugins:\n"
                             "  - {name: sensor, plugin: test_sensor, rate: 400}\n"
                             "  - {name: filter, plugin: test_filter, trigger: imu, params: {valid: true, origin: true}}\n"
                             "  - {name: ctl, plugin: test_controller, rate: 100}\n" +
                             extra_yaml;
  const auto file = in_dir(reinterpret_cast<const std::uint8_t*>(config.data()), config.size(), (name + ".yaml").c_str());
  TestPluginHost made;
  made.config = file;
  made.dir = file.parent_path();
  made.runs = made.dir / "runs";
  tern::core::HostOptions o;
  o.quiet = true;
  o.log_dir = made.runs;
  made.host = std::make_unique<tern::core::Host>(tern::core::load_config(file), o);
  made.host->build();
  return made;
}

}  // namespace tern::fuzz
