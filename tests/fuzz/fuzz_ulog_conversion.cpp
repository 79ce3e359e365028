// fuzz_ulog_conversion: libFuzzer target for `tern import ulog` past the reader (core/apps/import/
// importers.hpp import_ulog: ulog_import.cpp, ulog_conversion.cpp): the survey of the topics, the
// choice of each output's source, the handlers that turn PX4's topics into the sensor log's imu,
// mag, baro, diff_pressure, gnss, reference and actuators rows (units, frames, stamps, the 1-s
// reorder window, the servo effectiveness of PX4 v1.13+), the parameters mapped onto the
// estimator's settings, and the sensor log written (sensor_log_writer.hpp). The surfaces' full
// deflections are given (--max-deflection 0.35 0.35 0.35), so that the actuators rows are written.
// Any bytes: a sensor log, or one ImportError line naming the .ulg; never a crash, a hang, an
// overflow, another exception (what escapes import_ulog escapes `tern import`), or a log that
// tern replay cannot read: sensor_log.yaml reads (replay/sensor_log_meta.hpp), and every table
// the report counts reads (replay/replay_csv.hpp) with as many rows as the report says. The .ulg
// and the sensor log are this process's, under TMPDIR; the sensor log is removed after each input.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "config/error.hpp"
#include "fuzz_input.hpp"
#include "import/importers.hpp"
#include "replay/replay_csv.hpp"
#include "replay/sensor_log_meta.hpp"

using namespace tern::core;
namespace fs = std::filesystem;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fs::path ulg = tern::fuzz::in_dir(data, size, "flight.ulg");
  const fs::path out = ulg.parent_path() / "sensor_log";
  std::error_code ec;
  fs::remove_all(out, ec);
  CommandMapping mapping;
  mapping.max_deflection = std::array<double, 3>{0.35, 0.35, 0.35};
  try {
    ImportReport report;
    {
      SensorLogWriter writer(out);
      report = import_ulog(ulg, writer, mapping);
    }
    if (std::getenv("TERN_FUZZ_VERBOSE"))  // what a seed gives
      for (const auto& [topic, rows] : report.rows)
        std::fprintf(stderr, "%s: %llu rows\n", topic.c_str(), static_cast<unsigned long long>(rows));
    // what tern replay reads of it
    try {
      (void)read_sensor_log_settings(out);
      for (const auto& [topic, rows] : report.rows)
        if (read_csv_table(out / "topics" / (topic + ".csv")).rows != rows) __builtin_trap();
    } catch (const ConfigError& e) {
      tern::fuzz::note(e);
      __builtin_trap();  // import wrote what replay cannot read
    }
  } catch (const ImportError& e) {
    tern::fuzz::note(e);
    const std::string what = e.what();
    if (what.rfind(ulg.string() + ":", 0) != 0 || what.find('\n') != std::string::npos) __builtin_trap();
  }
  fs::remove_all(out, ec);
  return 0;
}
