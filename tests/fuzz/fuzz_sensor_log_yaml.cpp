// fuzz_sensor_log_yaml: libFuzzer target for a sensor log's sensor_log.yaml
// (core/apps/replay/sensor_log_meta.hpp), as `tern replay`, `sysid` and `validate` read it from a
// log directory someone sent: the format version, the date (the magnetic model's decimal year), the
// estimator settings, applied to an estimator_ekf instance of a config, the airborne window, and
// the import's warnings read back for a missing table's error (sysid/import_notes.hpp).
// Any bytes: settings, or ConfigError (one line: file, line, column, field); never a crash, a
// hang, another exception, a window that is not two finite numbers with start before end or an
// import note that is not one line starting "; sensor_log.yaml: import warning: ". The
// file lies in a directory of its own under TMPDIR; nothing is written.
#include <cmath>
#include <cstdint>
#include <string>

#include "config/error.hpp"
#include "fuzz_input.hpp"
#include "replay/sensor_log_meta.hpp"
#include "sysid/import_notes.hpp"

using namespace tern::core;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = tern::fuzz::in_dir(data, size, "sensor_log.yaml");
  try {
    const SensorLogSettings s = read_sensor_log_settings(file.parent_path());
    if (s.file != file) __builtin_trap();
    MissionConfig mc;
    InstanceConfig ekf;
    ekf.name = ekf.plugin = "estimator_ekf";
    mc.plugins.push_back(ekf);
    apply_sensor_log_settings(mc, s);
    if (mc.plugins[0].params.size() != s.estimator.size()) __builtin_trap();
  } catch (const ConfigError& e) {
    tern::fuzz::note(e);
  }
  try {
    if (const auto w = read_airborne_window(file))
      if (!(std::isfinite(w->start_s) && std::isfinite(w->end_s) && w->start_s < w->end_s)) __builtin_trap();
  } catch (const ConfigError& e) {
    tern::fuzz::note(e);
  }
  const std::string said = tern::core::sysid::import_said(file, "actuators.csv");  // never throws
  if (!said.empty() && said.rfind("; sensor_log.yaml: import warning: ", 0) != 0) __builtin_trap();
  for (const char ch : said)
    if (static_cast<unsigned char>(ch) < 0x20) __builtin_trap();
  return 0;
}
