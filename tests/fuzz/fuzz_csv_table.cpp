// fuzz_csv_table: libFuzzer target for the sensor-log table readers (core/apps/replay/replay_csv.hpp)
// that `tern replay`, `sysid` and `validate` use on a log's topics/*.csv and params.csv, and for
// the time parser of replay's tables (table_limits.hpp). Any bytes: a table, or ConfigError (one
// line); never a crash, an out-of-bounds read or a hang.
#include <cstdint>
#include <string>

#include "config/error.hpp"
#include "fuzz_input.hpp"
#include "replay/replay_csv.hpp"
#include "replay/table_limits.hpp"

using namespace tern::core;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = tern::fuzz::as_file(data, size, ".csv");
  try {
    const CsvTable t = read_csv_table(file);
    for (const auto& [name, column] : t.columns)
      if (column.size() != t.rows) __builtin_trap();  // every column holds one value per row
  } catch (const ConfigError&) {
  }
  try {
    const ParamHistory h = read_params_csv(file);
    for (const auto& [name, values] : h.values) h.number_at(name, 0.0);
  } catch (const ConfigError&) {
  }
  // the first line as a `t [s]` cell: a time within the bound, or none
  const std::string first(reinterpret_cast<const char*>(data), size);
  if (const auto t = parse_log_time(first.substr(0, first.find('\n'))))
    if (*t > static_cast<tern::Nanos>(kMaxLogTime) * tern::kNanosPerSecond ||
        *t < -static_cast<tern::Nanos>(kMaxLogTime) * tern::kNanosPerSecond)
      __builtin_trap();
  return 0;
}
