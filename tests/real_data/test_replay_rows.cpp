// tests/real_data/test_replay_rows.cpp: `tern replay` plays every row of a sensor log, in order,
// each one reaching the estimator (issue 61): a synthetic log whose clock starts at 100 s, with
// bursts (several rows of one topic inside one 2.5-ms step), duplicates (one time twice), a row
// inserted by hand and a last IMU row between two ticks; the replay report's row account
// (replay_report.json "rows") against the rows written, and no time-out before a sensor's first row.
#include <doctest/doctest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "tern/math.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double kT0 = 100.0;  // s: the log's clock starts here (any origin is allowed)

/// A table being written: its header, then one row per call, "t [s]" and "stamp [ns]" first.
struct Table {
  std::ofstream out;
  std::size_t rows = 0;
  Table(const fs::path& file, const std::string& columns) : out(file) { out << "t [s],stamp [ns]," << columns << "\n"; }
  void row(double t, const std::string& values) {
    char stamp[64];
    std::snprintf(stamp, sizeof stamp, "%.9f,%lld,", t, static_cast<long long>(std::llround(t * 1e9)));
    out << stamp << values << "\n";
    ++rows;
  }
};

/// The rows written per topic, and the log's directory.
struct SyntheticLog {
  fs::path dir;
  std::size_t imu = 0, gnss = 0, baro = 0, mag = 0;
  std::size_t imu_duplicates = 0;
  std::size_t baro_after_end = 0;  ///< rows after the last IMU row's tick: not played
};

SyntheticLog write_log(const fs::path& dir) {
  SyntheticLog log{dir};
  fs::create_directories(dir / "topics");
  Table imu(dir / "topics" / "imu.csv", "accel_x,accel_y,accel_z,gyro_x,gyro_y,gyro_z");
  const std::string still = "0,0," + std::to_string(-tern::kStandardGravity) + ",0,0,0";  // level at rest
  for (int k = 0; k <= 5000; ++k) {                                                       // 1 kHz: 2 or 3 rows in each 2.5-ms step
    imu.row(kT0 + k * 1e-3, still);
    if (k == 1000 || k == 3000) imu.row(kT0 + k * 1e-3, still), ++log.imu_duplicates;  // the same time twice
    if (k == 2000) imu.row(kT0 + 2.0005, still);                                       // inserted by hand
  }
  imu.row(kT0 + 5.0013, still);  // the last row, between two ticks
  log.imu = imu.rows;
  Table gnss(dir / "topics" / "gnss.csv", "time_of_validity,fix_type,num_sats,lat,lon,alt,vel_n,vel_e,vel_d,h_acc,v_acc,s_acc");
  const std::string fix = "0,3,12,47.397,8.545,488,0,0,0,0.5,0.8,0.2";
  for (int k = 0; k <= 50; ++k) {
    gnss.row(kT0 + k * 0.1, fix);
    if (k == 20) gnss.row(kT0 + 2.0005, fix);  // a burst: two fixes in one step
    if (k == 30) gnss.row(kT0 + 3.0, fix);     // a duplicate
  }
  log.gnss = gnss.rows;
  Table baro(dir / "topics" / "baro.csv", "pressure");
  for (int k = 0; k <= 250; ++k) {
    baro.row(kT0 + k * 0.02, "95460");
    if (k == 100) baro.row(kT0 + 2.0, "95460");  // a duplicate
  }
  baro.row(kT0 + 5.01, "95460"), ++log.baro_after_end;  // after the replay's last tick (105.0025 s)
  log.baro = baro.rows;
  Table mag(dir / "topics" / "mag.csv", "field_x,field_y,field_z");
  for (int k = 0; k <= 250; ++k) {
    mag.row(kT0 + k * 0.02, "2.1e-05,1e-06,4.3e-05");
    if (k % 50 == 0) mag.row(kT0 + k * 0.02 + 0.001, "2.1e-05,1e-06,4.3e-05");  // bursts
  }
  log.mag = mag.rows;
  return log;
}

std::string run(const std::string& args) {
  const std::string cmd = std::string(TERN_BIN) + " " + args + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> p(popen(cmd.c_str(), "r"), pclose);
  REQUIRE(p);
  std::string out;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), p.get())) out += buf.data();
  const int rc = pclose(p.release());
  INFO(out);
  REQUIRE(WIFEXITED(rc));
  REQUIRE(WEXITSTATUS(rc) == 0);
  return out;
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  REQUIRE(in);
  return nlohmann::json::parse(in);
}

}  // namespace

TEST_CASE("tern replay: every row of a log with bursts, duplicates and a last row between ticks reaches the estimator") {
  const fs::path base = fs::temp_directory_path() / ("tern_replay_rows_" + std::to_string(::getpid()));
  fs::remove_all(base);
  const SyntheticLog log = write_log(base / "log");
  const std::string out = run("replay " + log.dir.string() + " --log-dir " + (base / "runs").string());
  const fs::path dir = fs::directory_iterator(base / "runs")->path();
  const nlohmann::json rows = read_json(dir / "replay_report.json")["rows"];
  INFO(out);
  INFO(rows.dump(2));
  REQUIRE(rows.contains("topics"));
  const auto& t = rows["topics"];
  CHECK(t["imu"]["rows"] == log.imu);
  CHECK(t["imu"]["played"] == log.imu);  // the last row too
  CHECK(t["imu"]["received"] == log.imu);
  CHECK(t["imu"]["invalid"] == log.imu_duplicates);  // a second sample at one time: rejected, counted
  CHECK(t["gnss"]["rows"] == log.gnss);
  CHECK(t["gnss"]["received"] == log.gnss);
  CHECK(t["baro"]["played"] == log.baro - log.baro_after_end);
  CHECK(t["baro"]["received"] == log.baro - log.baro_after_end);
  CHECK(t["mag"]["received"] == log.mag);
  for (const char* topic : {"imu", "gnss", "baro", "mag"}) {
    CHECK(t[topic]["lost"] == 0);
    CHECK(t[topic]["missed"] == 0);
  }
  CHECK(rows["lost"] == 0);
  CHECK(rows["not_played"] == log.baro_after_end);
  CHECK(out.find("rows: 0 lost") != std::string::npos);

  // The replay's own flight log holds every sample the estimator received (several in one tick
  // too), so that a replay of the replay plays the same rows (a replay logs CSV tables).
  std::ifstream imu_csv(dir / "topics" / "imu.csv");
  REQUIRE(imu_csv);
  std::size_t logged = 0;
  for (std::string line; std::getline(imu_csv, line);) ++logged;
  CHECK(logged - 1 == log.imu);  // the header, then every row the log had (duplicates too)

  // The log's clock starts at 100 s: no sensor was silent before its first row.
  const nlohmann::json ekf = read_json(dir / "summary.json")["instances"]["ekf"];
  for (const char* sensor : {"imu", "gnss", "baro", "mag"}) {
    INFO(sensor);
    CHECK(ekf[std::string(sensor) + "_timeouts"] == 0);
  }
  fs::remove_all(base);
}
