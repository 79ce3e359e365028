// fuzz_csv_table: libFuzzer target for the sensor-log table readers (core/apps/replay/replay_csv.hpp)
// that `tern replay`, `sysid` and `validate` use on a log's topics/*.csv and params.csv, for
// the time parser of replay's tables (table_limits.hpp), and for what sysid builds from such a
// table (sysid/flight_data.hpp series_from_tables: a table read taken as the IMU's, and as the
// actuators', beside a still, valid 10-s flight's other tables: any stamps, gaps, duplicates and
// rates, NaN), and the excitation recovered from that series (sysid/excitation_recovery.hpp: its lags and
// low-passes over gaps and NaN); and replay's unit checks (sensor_units.hpp: each column taken as a
// barometer's, a magnetometer's, an IMU's, a GNSS's and a pitot's values, NaN and empty included),
// its stamp-against-t check and hint for a clock since 1970 (table_limits.hpp) and its separator
// check (replay_csv.hpp) on the same bytes. Any bytes: a table and a series of matching columns, or
// ConfigError (one line); never a crash, an out-of-bounds read or a hang.
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "config/error.hpp"
#include "fuzz_input.hpp"
#include "replay/replay_csv.hpp"
#include "replay/sensor_units.hpp"
#include "replay/table_limits.hpp"
#include "sysid/excitation_recovery.hpp"
#include "sysid/flight_data.hpp"

using namespace tern::core;

namespace {

// A table of 0.1-s rows over 10 s with `names` filled by f(name).
template <std::size_t N>
CsvTable still(const std::array<const char*, N>& names, double (*f)(const std::string&)) {
  CsvTable c;
  c.file = "still.csv";
  for (int k = 0; k <= 100; ++k) {
    c.columns["t"].push_back(0.1 * k);
    for (const char* n : names) c.columns[n].push_back(f(n));
  }
  c.rows = 101;
  return c;
}

double zero(const std::string&) { return 0.0; }

// series_from_tables on the table as the IMU's (its columns those) and as the actuators'.
void series_of(const CsvTable& t) {
  sysid::FlightTables f;
  f.imu = still(sysid::kImuColumns, zero);
  f.actuators = still(sysid::kCommandColumns, zero);
  f.state = still(sysid::kStateColumns, [](const std::string& n) { return n == "valid" ? 1.0 : n == "Va" || n == "u" ? 20.0 : 0.0; });
  const auto has = [&](const auto& names) {
    for (const char* n : names)
      if (!t.has(n)) return false;
    return t.has("t");
  };
  for (const bool as_imu : {true, false}) {
    if (!(as_imu ? has(sysid::kImuColumns) : has(sysid::kCommandColumns))) continue;
    sysid::FlightTables g = f;
    (as_imu ? g.imu : g.actuators) = t;
    try {
      sysid::FlightSeries s = sysid::series_from_tables(g, {});
      if (s.delta_a.size() != s.t.size() || s.p.size() != s.t.size()) __builtin_trap();  // one value per sample
      sysid::recover_excitation(s);  // no excitation table: the controller's feedback fitted and taken out
      if (s.size() >= 3 && s.exc_delta_r.size() != s.t.size()) __builtin_trap();
    } catch (const ConfigError&) {
    }
  }
}

// Each of replay's unit checks on `v` (ConfigError or nothing).
void unit_checks(const std::vector<double>& v, const std::vector<double>& t, const std::vector<double>* stamp) {
  const std::vector<void (*)(const std::vector<double>&)> checks = {
      [](const std::vector<double>& x) { require_pressure_unit("baro.csv", x); },
      [](const std::vector<double>& x) { require_field_unit("mag.csv", x); },
      [](const std::vector<double>& x) { require_imu_magnitudes("imu.csv", x, x); },
      [](const std::vector<double>& x) {
        require_gnss_units("gnss.csv", {x, x, x, x});
      },
      [](const std::vector<double>& x) { require_pitot_sign("diff_pressure.csv", x); },
  };
  for (const auto& check : checks) {
    try {
      check(v);
    } catch (const ConfigError&) {
    }
  }
  for (std::size_t k = 0; k < t.size(); ++k) {
    (void)unix_time_hint(t[k]);
    if (!stamp || !std::isfinite(t[k]) || !std::isfinite((*stamp)[k]) || std::fabs(t[k]) > 1e9 || std::fabs((*stamp)[k]) > 9e18) continue;
    try {
      check_stamp_at_t("imu.csv", k + 2, static_cast<tern::Nanos>(t[k] * 1e9), static_cast<tern::Nanos>((*stamp)[k]));
    } catch (const ConfigError&) {
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = tern::fuzz::as_file(data, size, ".csv");
  try {
    const CsvTable t = read_csv_table(file);
    for (const auto& [name, column] : t.columns)
      if (column.size() != t.rows) __builtin_trap();  // every column holds one value per row
    series_of(t);
    const std::vector<double> none;
    for (const auto& [name, column] : t.columns)
      unit_checks(column, t.has("t") ? t.at("t") : none, t.has("stamp") ? &t.at("stamp") : nullptr);
  } catch (const ConfigError&) {
  }
  try {
    require_comma_separated(file, std::string(reinterpret_cast<const char*>(data), size).substr(0, 200));
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
