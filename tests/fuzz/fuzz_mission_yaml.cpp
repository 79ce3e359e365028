// fuzz_mission_yaml: libFuzzer target for the mission config loader (core/host/config/config.hpp
// load_config), as `tern fly`, `check` and `replay --config` read a mission file: the bounded YAML
// load (tern/input_file.hpp: a regular file of at most 16 MiB, at most 100 000 nodes with aliases
// expanded), then every section's checks (run, log, watchdog, check, plugins and their params,
// param_file, remap, phases, fallback, phase_machine, metrics, failsafes), and the planner's reader
// of its `mission:` section (tern/path/mission.hpp parse_mission_section). Any bytes: a config, or
// ConfigError / MissionError (one line); never a crash, a hang, another exception or unbounded memory.
// The same bytes are also read as a waypoint file (parse_mission_text: tern's format or ROSplane's).
// The file lies in a directory of its own under TMPDIR (a relative param_file: or mission file:
// resolves there); nothing is written.
#include <cstdint>
#include <set>
#include <string>

#include "config/config.hpp"
#include "config/error.hpp"
#include "fuzz_input.hpp"
#include "tern/path/mission.hpp"

using namespace tern::core;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = tern::fuzz::in_dir(data, size, "mission.yaml");
  try {
    const MissionConfig mc = load_config(file);
    // what the loader promises: instances, uniquely named, each with a rate or a trigger
    if (mc.plugins.empty()) __builtin_trap();
    std::set<std::string> names;
    for (const auto& ic : mc.plugins)
      if (!names.insert(ic.name).second || (ic.rate.has_value() == ic.trigger.has_value())) __builtin_trap();
    if (!(mc.duration > 0) || !(mc.watchdog.soft_ms > 0 && mc.watchdog.soft_ms <= mc.watchdog.hard_ms)) __builtin_trap();
    if (mc.mission) {
      try {
        const tern::path::Mission m = tern::path::parse_mission_section(mc.mission, mc.dir, mc.file.string());
        if (m.has_lla()) (void)tern::path::resolve_to_ned(m.waypoints, tern::GeoPoint{47.389, 8.034, 470.0});
      } catch (const tern::path::MissionError& e) {
        tern::fuzz::note(e);
      }
    }
  } catch (const ConfigError& e) {
    tern::fuzz::note(e);
  }
  // the same bytes as a waypoint file (`mission: {file:}`, `tern mission load`): tern's or ROSplane's
  try {
    const std::string text(reinterpret_cast<const char*>(data), size);
    (void)tern::path::parse_mission_text(text, "fuzz.yaml");
  } catch (const tern::path::MissionError& e) {
    tern::fuzz::note(e);
  }
  return 0;
}
