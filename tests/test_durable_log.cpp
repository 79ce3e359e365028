// The flight log survives what ends or starves a flight (issue 19, item 3): SIGKILL loses at
// most 100 ms of wall time of log, SIGHUP ends the flight cleanly, and a write error (file-size
// limit, unwritable directory) is one line while the flight flies on, with exit status 3. The
// same for the MCAP log (issue 44): a killed flight's flight.mcap, recovered and exported, holds
// its rows up to 100 ms before the kill; a file-size limit leaves a file that recovers.
#include <doctest/doctest.h>
#include <sys/resource.h>

#include <cmath>
#include <csignal>
#include <functional>
#include <ctime>
#include <iomanip>

#include <nlohmann/json.hpp>

#include "config/error.hpp"
#include "replay/replay_csv.hpp"
#include "replay/sensor_units.hpp"
#include "replay/table_limits.hpp"
#include "test_process.hpp"
#include "test_util.hpp"
#include "tern/atmosphere.hpp"

namespace {

std::string long_flight() { return base_config().replace(base_config().find("duration: 2"), 11, "duration: 600"); }

/// The one run directory under `logdir` (empty path if there is none yet).
fs::path the_run(const fs::path& logdir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(logdir, ec)) return e.path();
  return {};
}

/// Wall time of tern.log's "flight '...'" line, logged just before the plugins start (and so
/// before the first tick): [YYYY-mm-dd HH:MM:SS.mmm], local time.
std::optional<std::chrono::system_clock::time_point> flight_line_time(const fs::path& run) {
  for (const auto& l : lines(read_file(run / "tern.log"))) {
    if (l.find("] tern: flight '") == std::string::npos) continue;
    std::tm tm{};
    std::istringstream in(l.substr(1, 19));
    in >> std::get_time(&tm, "%Y-%m-%d %H:%M:%S");
    tm.tm_isdst = -1;
    const auto t = std::chrono::system_clock::from_time_t(std::mktime(&tm));
    return t + std::chrono::milliseconds(std::stoi(l.substr(21, 3)));
  }
  return std::nullopt;
}

/// Flight time of the last complete row of a CSV (a partial last line does not count).
double last_row_time(const std::string& csv) {
  const auto end = csv.rfind('\n');
  REQUIRE(end != std::string::npos);
  const auto begin = csv.rfind('\n', end - 1);
  return std::stod(csv.substr(begin + 1, end - begin - 1));
}

/// Starts a long realtime flight logging under test_dir()/<name>_runs; returns its pid once the
/// flight has started (its tern.log has the flight line), and the log directory.
std::pair<pid_t, fs::path> start_realtime_flight(const std::string& name, const std::string& log_format = "csv") {
  const fs::path cfg = write_file(name + ".yaml", long_flight());
  const fs::path logdir = test_dir() / (name + "_runs");
  const pid_t pid = spawn_tern({"fly", cfg.string(), "--realtime", "-q", "--log-dir", logdir.string(), "--log-format", log_format},
                               test_dir() / (name + ".out"));
  REQUIRE(wait_until([&] { return !the_run(logdir).empty() && flight_line_time(the_run(logdir)); }, 20));
  return {pid, logdir};
}

std::size_t count_lines_with(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (const auto& l : lines(text)) n += l.find(what) != std::string::npos;
  return n;
}

}  // namespace

TEST_CASE("SIGKILL of a realtime flight loses at most 100 ms of wall time of log") {
  const auto [pid, logdir] = start_realtime_flight("kill");
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const auto killed_at = std::chrono::system_clock::now();
  kill(pid, SIGKILL);
  wait_for(pid);
  const fs::path run = the_run(logdir);
  // paced to wall time, the flight had flown at most this long when it was killed (the first
  // tick comes after the logged line; its millisecond stamp is truncated: + 1 ms)
  const double flown_max = std::chrono::duration<double>(killed_at - *flight_line_time(run)).count() + 0.001;
  const double logged = last_row_time(read_file(run / "topics" / "imu.csv"));
  INFO("flown at most " << flown_max << " s, logged up to " << logged << " s");
  CHECK(logged > 1.0);
  CHECK(flown_max - logged <= 0.100);
}

TEST_CASE("SIGKILL of a realtime flight logging MCAP: recovered, it holds the log up to 100 ms before the kill") {
  const auto [pid, logdir] = start_realtime_flight("kill_mcap", "mcap");
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const auto killed_at = std::chrono::system_clock::now();
  kill(pid, SIGKILL);
  wait_for(pid);
  const fs::path run = the_run(logdir);
  const double flown_max = std::chrono::duration<double>(killed_at - *flight_line_time(run)).count() + 0.001;
  CHECK_FALSE(fs::exists(run / "topics"));
  const fs::path out = test_dir() / "kill_mcap_recover.out";
  REQUIRE(run_tern({"export", "recover", run.string()}, out) == 0);
  INFO(read_file(out));
  CHECK(read_file(out).find("stopped: the file ends at byte") != std::string::npos);  // no summary: killed
  REQUIRE(run_tern({"export", "csv", (run / "flight.recovered.mcap").string(), "--out", (run / "exported").string()}, out) == 0);
  const double logged = last_row_time(read_file(run / "exported" / "imu.csv"));
  INFO("flown at most " << flown_max << " s, logged up to " << logged << " s");
  CHECK(logged > 1.0);
  CHECK(flown_max - logged <= 0.100);
}

TEST_CASE("SIGHUP ends the flight like SIGTERM: complete log, exit status 129") {
  const auto [pid, logdir] = start_realtime_flight("hup");
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  kill(pid, SIGHUP);
  const int status = wait_for(pid);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 129);
  const auto s = nlohmann::json::parse(read_file(the_run(logdir) / "summary.json"));
  CHECK(s["end_reason"] == "SIGHUP");
  CHECK(read_file(the_run(logdir) / "tern.log").find("flight ended by SIGHUP") != std::string::npos);
}

TEST_CASE("a file-size limit mid-flight: the flight completes, one error line, whole rows, exit status 3") {
  const fs::path cfg = write_file("fsize.yaml", base_config().replace(base_config().find("duration: 2"), 11, "duration: 30"));
  const fs::path logdir = test_dir() / "fsize_runs";
  const fs::path out = test_dir() / "fsize.out";
  // SIGXFSZ keeps its default action (end the process): tern must ignore it itself
  const int rc = run_tern({"fly", cfg.string(), "-q", "--log-dir", logdir.string()}, out, [] {
    const rlimit lim{64 * 1024, 64 * 1024};
    setrlimit(RLIMIT_FSIZE, &lim);
  });
  const std::string console = read_file(out);
  INFO(console);
  CHECK(rc == 3);
  CHECK(count_lines_with(console, "error") == 1);
  CHECK(count_lines_with(console, "flight log: cannot write '" + logdir.string()) == 1);
  CHECK(console.find("File too large; logging stopped, the flight goes on") != std::string::npos);
  const fs::path run = the_run(logdir);
  const auto s = nlohmann::json::parse(read_file(run / "summary.json"));  // degraded to the summary
  CHECK(s["end_reason"] == "duration");
  CHECK(s["duration_s"].get<double>() == 30.0);
  for (const auto& e : fs::directory_iterator(run / "topics")) {
    const std::string csv = read_file(e.path());
    INFO(e.path().string());
    CHECK((csv.empty() || csv.back() == '\n'));
  }
  CHECK_FALSE(fs::exists(run / "summary.json.tmp"));
}

TEST_CASE("a file-size limit mid-flight logging MCAP: one error line, exit status 3, a file that recovers") {
  std::string yaml = base_config().replace(base_config().find("duration: 2"), 11, "duration: 30");
  yaml.replace(yaml.find("log: {max_rate: 0}"), 18, "log: {max_rate: 0, chunk_size: 4096}");  // chunks end before the limit
  const fs::path cfg = write_file("fsize_mcap.yaml", yaml);
  const fs::path logdir = test_dir() / "fsize_mcap_runs";
  const fs::path out = test_dir() / "fsize_mcap.out";
  const int rc = run_tern({"fly", cfg.string(), "-q", "--log-dir", logdir.string(), "--log-format", "mcap"}, out, [] {
    const rlimit lim{64 * 1024, 64 * 1024};
    setrlimit(RLIMIT_FSIZE, &lim);
  });
  const std::string console = read_file(out);
  INFO(console);
  CHECK(rc == 3);
  CHECK(count_lines_with(console, "error") == 1);
  CHECK(console.find("File too large; logging stopped, the flight goes on") != std::string::npos);
  const fs::path run = the_run(logdir);
  CHECK(nlohmann::json::parse(read_file(run / "summary.json"))["end_reason"] == "duration");
  CHECK(fs::file_size(run / "flight.mcap") <= 64 * 1024);
  const fs::path rec = test_dir() / "fsize_mcap_recover.out";
  REQUIRE(run_tern({"export", "recover", run.string()}, rec) == 0);
  INFO(read_file(rec));
  CHECK(read_file(rec).find(" messages from ") != std::string::npos);
  CHECK(read_file(rec).find(" 0 messages from ") == std::string::npos);  // the chunks before the limit are kept
}

TEST_CASE("an unwritable log directory: the flight flies, one error line, exit status 3") {
  const fs::path cfg = write_file("rodir.yaml", base_config());
  const fs::path not_a_dir = write_file("plain_file", "x");
  std::vector<std::pair<fs::path, std::string>> cases = {{not_a_dir / "runs", "Not a directory"}};
  const fs::path ro = test_dir() / "read_only";
  fs::create_directories(ro);
  fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
  if (geteuid() != 0) cases.emplace_back(ro, "Permission denied");  // root writes anyway
  for (const auto& [dir, reason] : cases) {
    const fs::path out = test_dir() / "rodir.out";
    const int rc = run_tern({"fly", cfg.string(), "-q", "--log-dir", dir.string()}, out);
    const std::string console = read_file(out);
    INFO(console);
    CHECK(rc == 3);
    CHECK(count_lines_with(console, "error") == 1);
    CHECK(console.find("flight log: cannot create the run directory '" + dir.string()) != std::string::npos);
    CHECK(console.find(reason + "; logging stopped, the flight goes on") != std::string::npos);
  }
  fs::permissions(ro, fs::perms::owner_all);
}

TEST_CASE("tern replay accepts a log whose last line is partial: dropped with one warning") {
  const tern::core::FlightResult flown = fly_yaml(base_config(), "partial_orig");
  REQUIRE(flown.ok);
  const fs::path imu = flown.run_dir / "topics" / "imu.csv";
  const std::size_t rows = lines(read_file(imu)).size();               // header + 801 samples (0 .. 2 s at 400 Hz)
  std::ofstream(imu, std::ios::app) << "2.002500000,2002500000,0.01";  // killed mid-row
  const fs::path out = test_dir() / "partial.out";
  const int rc = run_tern({"replay", flown.run_dir.string(), "-q", "--log-dir", (test_dir() / "partial_replay").string()}, out);
  const std::string console = read_file(out);
  INFO(console);
  CHECK(rc == 0);
  CHECK(count_lines_with(console, "the last line is partial") == 1);
  CHECK(console.find(imu.string() + ":" + std::to_string(rows + 1) + ": the last line is partial (27 characters, no line end") !=
        std::string::npos);
  const fs::path replayed = the_run(test_dir() / "partial_replay");
  CHECK(last_row_time(read_file(replayed / "topics" / "state.csv")) == 2.0);
}

namespace {

/// `tern replay` of `log` into test_dir() / name (exit 0): its state.csv.
std::string replayed_state(const fs::path& log, const std::string& name) {
  const fs::path out = test_dir() / (name + ".out");
  const int rc = run_tern({"replay", log.string(), "-q", "--log-dir", (test_dir() / name).string()}, out);
  INFO(read_file(out));
  CHECK(rc == 0);
  return read_file(the_run(test_dir() / name) / "topics" / "state.csv");
}

/// A short flight's log and its copy with every table's text turned by `rewrite` replay to the same
/// state.csv.
void check_same_replay(const std::string& name, const std::function<std::string(const std::string&)>& rewrite) {
  const tern::core::FlightResult flown = fly_yaml(base_config(), name + "_orig");
  REQUIRE(flown.ok);
  const fs::path copy = test_dir() / (name + "_log");
  fs::remove_all(copy);
  fs::copy(flown.run_dir, copy, fs::copy_options::recursive);
  for (const auto& table : fs::directory_iterator(copy / "topics")) {
    const std::string text = rewrite(read_file(table.path()));  // before the file is truncated
    std::ofstream(table.path(), std::ios::binary | std::ios::trunc) << text;
  }
  const std::string state = replayed_state(flown.run_dir, name + "_replay");
  CHECK(state.size() > 1000);
  CHECK(replayed_state(copy, name + "_copy_replay") == state);
}

}  // namespace

TEST_CASE("tern replay reads a log whose tables end their lines in CRLF as the same log with LF") {
  check_same_replay("crlf", [](const std::string& text) {  // as a spreadsheet on Windows saves them
    std::string out;
    for (const char c : text) out += c == '\n' ? std::string("\r\n") : std::string(1, c);
    return out;
  });
}

TEST_CASE("tern replay reads a log whose tables begin with a UTF-8 byte order mark as the same log without") {
  check_same_replay("bom", [](const std::string& text) { return "\xEF\xBB\xBF" + text; });  // Excel's "CSV UTF-8", pandas' utf-8-sig
}

TEST_CASE("a table separated by semicolons or tabs is refused at its header, naming the separator") {
  const auto refusal = [](const std::string& header) {
    try {
      tern::core::require_comma_separated("imu.csv", header);
    } catch (const tern::core::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(refusal("t [s];stamp [ns];accel_x [m/s^2]").find("imu.csv:1: the header's cells are separated by ';'") != std::string::npos);
  CHECK(refusal("t [s]\tstamp [ns]").find("separated by tabs") != std::string::npos);
  CHECK(refusal("t [s],stamp [ns],note;free text").empty());  // commas: a semicolon inside a cell is the cell's
  CHECK(refusal("t [s]").empty());                            // one column: the columns' own check names what is missing
}

TEST_CASE("a clock in seconds since 1970 is refused with how to bring it to the log's start") {
  using tern::core::unix_time_hint;
  CHECK(unix_time_hint(1732871234.5).find("seconds since 1970 (2024-11-29 09:07:14 UTC)?") != std::string::npos);
  CHECK(unix_time_hint(1732871234.5).find("subtract the first row's t") != std::string::npos);
  for (const double t : {86400.5, 9.0e8, 5.0e9, -1732871234.5}) CHECK_MESSAGE(unix_time_hint(t).empty(), t);  // not a date of a flight log
}

TEST_CASE("a barometer or a magnetometer logged in another unit is refused in one line naming the unit") {
  using tern::core::require_field_unit;
  using tern::core::require_pressure_unit;
  const auto refusal = [](const auto& check, std::vector<double> v) {
    try {
      check(std::move(v));
    } catch (const tern::core::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const auto pressure = [](std::vector<double> v) { require_pressure_unit("baro.csv", std::move(v)); };
  const auto field = [](std::vector<double> v) { require_field_unit("mag.csv", std::move(v)); };
  // a flight at 1400 m (its NaN rows ignored), at sea level, at 5000 m; a field of 48 uT, of 300 uT beside a motor
  for (const std::vector<double>& ok : {std::vector<double>{tern::isa_pressure(1400.0), std::nan(""), tern::isa_pressure(1401.0)},
                                        {tern::kIsaSeaLevelPressure},
                                        {tern::isa_pressure(5000.0)}})
    CHECK(refusal(pressure, ok).empty());
  for (const std::vector<double>& ok : {std::vector<double>{48e-6, 49e-6}, {300e-6}, {}}) CHECK(refusal(field, ok).empty());
  CHECK(refusal(pressure, {850.0, 849.0, 851.0}).find("the pressure's median is 850 Pa") != std::string::npos);
  CHECK(refusal(pressure, {850.0}).find("hPa (mbar) logged as Pa?") != std::string::npos);
  CHECK(refusal(pressure, {85.0}).find("kPa logged as Pa?") != std::string::npos);
  CHECK(refusal(pressure, {12.3}).find("psi logged as Pa?") != std::string::npos);
  CHECK(refusal(field, {0.48}).find("gauss logged as T?") != std::string::npos);
  CHECK(refusal(field, {480.0}).find("milligauss logged as T?") != std::string::npos);
  CHECK(refusal(field, {48.0}).find("microtesla logged as T?") != std::string::npos);
  CHECK(refusal(field, {48000.0}).find("nanotesla logged as T?") != std::string::npos);
  // the GNSS's fixes in the estimator's ranges, and PX4's integer lat (deg * 1e7), alt in mm, speed in cm/s
  const auto gnss = [](tern::core::GnssFixes f) { return [f](std::vector<double>) { tern::core::require_gnss_units("gnss.csv", f); }; };
  CHECK(refusal(gnss({{47.4, -47.4}, {8.5, -122.0}, {488.0, -20.0}, {18.0, 0.0}}), {}).empty());
  CHECK(refusal(gnss({{473977418.0}, {8.5}, {488.0}, {18.0}}), {})
            .find("degrees * 1e7 (PX4's and ArduPilot's integer latitude) logged as deg?") != std::string::npos);
  CHECK(refusal(gnss({{47.4}, {8.5}, {488000.0}, {18.0}}), {}).find("mm or cm logged as m?") != std::string::npos);
  CHECK(refusal(gnss({{47.4}, {8.5}, {488.0}, {1800.0}}), {}).find("mm/s or cm/s logged as m/s?") != std::string::npos);
  // a pitot the right way round (on the ground, then flying at 20 m/s) passes; swapped tubes do not
  const auto pitot = [](std::vector<double> v) { tern::core::require_pitot_sign("diff_pressure.csv", std::move(v)); };
  std::vector<double> flight(100, 245.0);
  for (std::size_t k = 0; k < 30; ++k) flight[k] = k % 2 ? -3.0 : 2.0;  // the ground's noise about 0
  CHECK(refusal(pitot, flight).empty());
  for (double& p : flight) p = -p;
  CHECK(refusal(pitot, flight).find("its tubes are swapped") != std::string::npos);
}

TEST_CASE("a log's `t [s]`: up to 9 decimals exactly, more rounded to the nanosecond, exponents read, anything else refused") {
  using tern::core::parse_log_time;
  CHECK(parse_log_time("12.345000000") == 12'345'000'000);
  CHECK(parse_log_time("-0.5") == -500'000'000);
  CHECK(parse_log_time("564.0074999999999") == 564'007'500'000);         // Python's repr of 564.0075
  CHECK(parse_log_time("564.00749999949") == 564'007'499'999);           // the 10th decimal 4: down
  CHECK(parse_log_time("0.9999999995") == 1'000'000'000);                // rounded up into the next second
  CHECK(parse_log_time("5.640075000000000000e+02") == 564'007'500'000);  // numpy.savetxt's default
  CHECK(parse_log_time("2.5E-3") == 2'500'000);
  CHECK(parse_log_time("86400") == 86'400'000'000'000);
  for (const char* bad : {"", "--5", "+5", ".5", "5.0x", "1e", "1e+", "1e21", "1e999999999", "86400.000000001", "8.64001e4", "nan", " 5"})
    CHECK_MESSAGE(!parse_log_time(bad), bad);
}

TEST_CASE("tern replay reads `t` written with more than 9 decimals (a float's shortest form) as the same log") {
  check_same_replay("decimals", [](const std::string& text) {  // "2.002500000" -> "2.0025000004999": the same ns
    std::string out;
    bool first_cell = false;
    for (const char c : text) {
      if (first_cell && c == ',') out += "4999", first_cell = false;
      if (c == '\n') first_cell = true;
      out += c;
    }
    return out;
  });
}
