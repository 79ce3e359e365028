// tern import's converters (core/apps/import/) on the two real flights in data/real_flights:
// row counts, hand-checked rows (units and frames written out below), the header a flight log
// writes, and one-line errors for corrupt or truncated inputs.
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <yaml-cpp/yaml.h>

#include "import/archive_input.hpp"
#include "import/import_support.hpp"
#include "import/importers.hpp"
#include "record/flight_log.hpp"
#include "tern/msg/estimator.hpp"
#include "tern/msg/sensors.hpp"

namespace fs = std::filesystem;
using namespace tern;
using namespace tern::core;

namespace {

const fs::path kFlights = fs::path(TERN_REAL_FLIGHTS_DIR);
const fs::path kZurich = kFlights / "px4_fixedwing_zurich2014_InputFilesPX4_search.zip";
const fs::path kAlfa = kFlights / "alfa_carbonZ_2018-07-18-15-53-31_1_engine_failure_csv.tar.gz";

struct TempDir {
  fs::path path;
  TempDir() {
    std::string p = (fs::temp_directory_path() / "tern-test-import-XXXXXX").string();
    REQUIRE(mkdtemp(p.data()) != nullptr);
    path = p;
  }
  ~TempDir() { fs::remove_all(path); }
};

/// A topic table of a sensor log: its header line and its rows' cells.
struct Table {
  std::string header;
  std::vector<std::string> names;
  std::vector<std::vector<std::string>> rows;
  std::size_t col(const std::string& name) const {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return i;
    FAIL("no column " << name);
    return 0;
  }
  /// The row whose stamp [ns] is `stamp`.
  const std::vector<std::string>& at(std::int64_t stamp) const {
    const std::size_t c = col("stamp");
    for (const auto& r : rows)
      if (std::stoll(r[c]) == stamp) return r;
    FAIL("no row with stamp " << stamp);
    return rows.front();
  }
  double num(const std::vector<std::string>& row, const std::string& name) const { return std::stod(row[col(name)]); }
};

Table read_table(const fs::path& csv) {
  Table t;
  std::ifstream in(csv);
  REQUIRE(std::getline(in, t.header));
  std::stringstream h(t.header);
  for (std::string c; std::getline(h, c, ',');) t.names.push_back(c.substr(0, c.find(" [")));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream l(line);
    for (std::string c; std::getline(l, c, ',');) cells.push_back(c);
    t.rows.push_back(std::move(cells));
  }
  return t;
}

/// The header line FlightLog writes for message type T (a tern flight log's topics/<t>.csv).
template <class T>
std::string flight_log_header() {
  TempDir d;
  {
    FlightLog log(d.path);
    log.add_topic("x", reflect::layout<T>(), sizeof(T));
  }
  std::ifstream in(d.path / "topics" / "x.csv");
  std::string line;
  std::getline(in, line);
  return line;
}

using Importer = std::function<ImportReport(const fs::path&, SensorLogWriter&)>;
/// import_alfa without the surfaces' options.
const Importer alfa_default = [](const fs::path& in, SensorLogWriter& out) { return import_alfa(in, out); };

ImportReport import_into(const fs::path& input, const fs::path& out_dir, const Importer& importer) {
  const ArchiveInput in(input);
  SensorLogWriter out(out_dir);
  out.set_origin(input.filename().string());
  return importer(in.dir(), out);
}

/// The ImportError's message of importing `dir`, "" if none.
std::string import_error(const fs::path& dir, const fs::path& out_dir, const Importer& importer) {
  try {
    import_into(dir, out_dir, importer);
  } catch (const ImportError& e) {
    return e.what();
  }
  return "";
}

/// Copies the first `lines` lines of `from` to `to` (all if 0).
void copy_lines(const fs::path& from, const fs::path& to, std::size_t lines = 0) {
  std::ifstream in(from);
  std::ofstream out(to);
  std::string line;
  for (std::size_t n = 0; std::getline(in, line) && (lines == 0 || n < lines); ++n) out << line << "\n";
}

bool has_warning(const ImportReport& r, const std::string& part) {
  for (const auto& w : r.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("a log's temperature in deg C: kelvin within -100..150 deg C; NaN, infinities and sensor codes counted, the default written") {
  std::uint64_t missing = 0;
  CHECK(tern::core::kelvin_from_celsius(25.0, missing) == doctest::Approx(298.15));
  CHECK(tern::core::kelvin_from_celsius(-40.0, missing) == doctest::Approx(233.15));
  CHECK(missing == 0);
  for (const double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL, 150.0, -100.0, 327.67, -273.15})
    CHECK(tern::core::kelvin_from_celsius(bad, missing) == tern::msg::Baro{}.temperature);
  CHECK(missing == 7);
}

TEST_CASE("sensor log tables have a tern flight log's header") {
  TempDir d;
  {
    SensorLogWriter w(d.path / "log");
    msg::Imu imu;
    imu.stamp = 5;
    w.write("imu", imu);
    msg::Reference ref;
    ref.stamp = 5;
    w.write("reference", ref);
    imu.stamp = 4;
    CHECK_THROWS_AS(w.write("imu", imu), ImportError);  // time must not go backwards
    w.finish({"test", "none", "", YAML::Node(), {}});
  }
  CHECK(read_table(d.path / "log" / "topics" / "imu.csv").header == flight_log_header<msg::Imu>());
  CHECK(read_table(d.path / "log" / "topics" / "imu.csv").header ==
        "t [s],stamp [ns],accel_x [m/s^2],accel_y [m/s^2],accel_z [m/s^2],gyro_x [rad/s],gyro_y [rad/s],gyro_z [rad/s],temperature [K]");
  CHECK(read_table(d.path / "log" / "topics" / "reference.csv").header == flight_log_header<msg::Reference>());
  CHECK(read_table(d.path / "log" / "topics" / "imu.csv").rows.at(0).at(0) == "0.000000005");  // t [s] = stamp
  CHECK(YAML::LoadFile((d.path / "log" / "sensor_log.yaml").string())["tern_sensor_log"].as<int>() == 1);
  CHECK(!fs::exists(d.path / "log" / "params.csv"));
  // an existing, non-empty output directory is refused
  CHECK_THROWS_AS(SensorLogWriter(d.path / "log"), ImportError);
}

TEST_CASE("sensor log: a sensor slower than 2.5 Hz gets a time-out of 2.5 mean intervals, a faster one the default") {
  TempDir d;
  {
    SensorLogWriter w(d.path / "log");
    for (std::int64_t k = 0; k < 5; ++k) {  // a 1-Hz pitot and a 5-Hz GNSS over 4 s
      msg::DiffPressure dp;
      dp.stamp = k * 1'000'000'000;
      w.write("diff_pressure", dp);
    }
    for (std::int64_t k = 0; k < 21; ++k) {
      msg::Gnss g;
      g.stamp = k * 200'000'000;
      w.write("gnss", g);
    }
    for (std::int64_t k = 0; k < 11; ++k) {  // a 2-Hz barometer: 1.25 s, longer than any default
      msg::Baro b;
      b.stamp = k * 500'000'000;
      w.write("baro", b);
    }
    msg::Mag m;  // one row: no interval, no setting
    w.write("mag", m);
    YAML::Node est;
    est["mag_timeout"] = 7.0;
    w.finish({"test", "none", "", est, {}});
  }
  const YAML::Node e = YAML::LoadFile((d.path / "log" / "sensor_log.yaml").string())["estimator"];
  CHECK(e["diff_pressure_timeout"].as<double>() == doctest::Approx(2.5));
  CHECK(!e["gnss_timeout"]);  // 0.2-s interval: estimator_ekf's default stays (2.5 of them would shorten it)
  CHECK(e["baro_timeout"].as<double>() == doctest::Approx(1.25));
  CHECK(e["mag_timeout"].as<double>() == 7.0);  // the importer's own setting is kept
}

TEST_CASE("inertialnav: the Zurich PX4 flight, from its zip as shipped") {
  TempDir d;
  const fs::path log = d.path / "zurich";
  const ImportReport r = import_into(kZurich, log, import_inertialnav);
  // one row per line of IMU.txt, MAG.txt, GPS.txt; NTUN.txt gives baro and diff_pressure;
  // ATT.txt and GPOSonboard.txt (7364 rows each) share 7168 of their times: 7560 reference rows
  CHECK(r.rows.at("imu") == 20444);
  CHECK(r.rows.at("mag") == 20444);
  CHECK(r.rows.at("gnss") == 752);
  CHECK(r.rows.at("baro") == 10869);
  CHECK(r.rows.at("diff_pressure") == 10869);
  CHECK(r.rows.at("reference") == 7560);
  // above 3 m/s, GPS.txt's speed and course (radians) and GPSraw.txt's NED velocity agree within 0.5 m/s but twice
  REQUIRE(r.warnings.size() == 2);
  CHECK(has_warning(r, "2 of 642 fixes above 3 m/s"));
  CHECK(has_warning(r,
                    ": no surface commands in this log (InertialNav's files hold sensors and the onboard estimate only): no "
                    "actuators.csv written (tern sysid needs one)"));
  CHECK(!fs::exists(log / "topics" / "actuators.csv"));
  // the warnings stay in sensor_log.yaml's notes (tern sysid names the one of a missing table)
  int kept = 0;
  for (const auto& n : YAML::LoadFile((log / "sensor_log.yaml").string())["notes"])
    kept += n.as<std::string>().rfind("import warning: ", 0) == 0 ? 1 : 0;
  CHECK(kept == 2);

  SUBCASE("imu: IMU.txt line 2, ms -> ns, gyro rad/s and accel m/s^2 already body FRD") {
    // "8.2111359e+00 8.2111359e+00 1.5411900e-01 2.6476000e-02 5.3018000e-02 1.3661700e+00 3.2541300e-01 -9.0435160e+00"
    const Table t = read_table(log / "topics" / "imu.csv");
    const auto& row = t.at(8211136);  // 8.2111359 ms = 8211135.9 ns, rounded
    CHECK(t.num(row, "gyro_x") == 1.54119e-01);
    CHECK(t.num(row, "gyro_z") == 5.3018e-02);
    CHECK(t.num(row, "accel_x") == 1.36617);
    CHECK(t.num(row, "accel_z") == -9.043516);  // on the ground: specific force up, z down: about -g
  }
  SUBCASE("mag: MAG.txt line 5000, (field - offset) mGauss * 1e-7 = T") {
    // "3.6376061e+04 3.6376061e+04 1.0545600e+02 -2.6908400e+02 3.2717700e+02 0 0 0"
    const Table t = read_table(log / "topics" / "mag.csv");
    const auto& row = t.at(36376061000);
    CHECK(t.num(row, "field_x") == doctest::Approx((105.456 - 0.0) * 1e-7).epsilon(1e-12));
    CHECK(t.num(row, "field_y") == doctest::Approx(-269.084e-7).epsilon(1e-12));
    CHECK(t.num(row, "field_z") == doctest::Approx(327.177e-7).epsilon(1e-12));
  }
  SUBCASE("baro and diff_pressure: NTUN.txt line 1291, EAS and baro height") {
    // "1.7790254e+04 ... 1.0100987e+01 (EAS m/s) 4.2616592e+02 (baro height m) 0"
    const Table dp = read_table(log / "topics" / "diff_pressure.csv");
    CHECK(dp.num(dp.at(17790254000), "pressure") == doctest::Approx(0.5 * 1.225 * 10.100987 * 10.100987).epsilon(1e-12));  // 62.49 Pa
    const Table baro = read_table(log / "topics" / "baro.csv");
    const double isa = 101325.0 * std::pow(1.0 - 2.25577e-5 * 426.16592, 5.25588);  // ISA troposphere, 1013.25 hPa datum
    CHECK(baro.num(baro.at(17790254000), "pressure") == doctest::Approx(isa).epsilon(1e-12));
  }
  SUBCASE("gnss: GPS.txt line 101, velocity from GPSraw.txt; course in radians gives the same") {
    // GPS.txt: "1.9939400e+04 3 ... 4.7389038e+01 8.0332980e+00 3.7515802e+02 ... 9.8581388e+00 4.3747280e+00 -2.8700000e+00"
    // GPSraw.txt: "1.9939400e+04 4.7389038e+01 8.0332980e+00 3.7515802e+02 -3.27 -9.30 -2.87"
    const Table t = read_table(log / "topics" / "gnss.csv");
    const auto& row = t.at(19939400000);
    CHECK(t.num(row, "lat") == 47.389038);
    CHECK(t.num(row, "lon") == 8.033298);
    CHECK(t.num(row, "alt") == 375.15802);
    CHECK(t.num(row, "fix_type") == 3);
    CHECK(t.num(row, "vel_n") == -3.27);
    CHECK(t.num(row, "vel_e") == -9.3);
    CHECK(t.num(row, "vel_d") == -2.87);
    // course 4.374728 rad = 250.7 deg (south-west): Vg cos(chi), Vg sin(chi) match GPSraw.txt to the cm
    CHECK(9.8581388 * std::cos(4.374728) == doctest::Approx(-3.27).epsilon(0.005));
    CHECK(9.8581388 * std::sin(4.374728) == doctest::Approx(-9.30).epsilon(0.005));
  }
  SUBCASE("reference: ATT.txt and GPOSonboard.txt line 1000, degrees -> rad") {
    // ATT: "2.0325380e+04 2.0325380e+04 -9.6188155e+00 2.6185432e+01 -1.7991018e+02 0 0"
    // GPOSonboard: "2.0325380e+04 4.7389028e+01 8.0332530e+00 4.3515387e+02 -3.5862010e+00 -9.3718380e+00 -2.7426070e+00"
    const Table t = read_table(log / "topics" / "reference.csv");
    const auto& row = t.at(20325380000);
    CHECK(t.num(row, "phi") == doctest::Approx(-9.6188155 * M_PI / 180).epsilon(1e-12));
    CHECK(t.num(row, "theta") == doctest::Approx(26.185432 * M_PI / 180).epsilon(1e-12));
    CHECK(t.num(row, "psi") == doctest::Approx(-179.91018 * M_PI / 180).epsilon(1e-12));
    CHECK(t.num(row, "lat") == 47.389028);
    CHECK(t.num(row, "v_e") == -9.371838);
    CHECK(std::isnan(t.num(row, "w_n")));
  }
  SUBCASE("sensor_log.yaml: timing.txt's delays and EAS2TAS") {
    const YAML::Node y = YAML::LoadFile((log / "sensor_log.yaml").string());
    CHECK(y["tern_sensor_log"].as<int>() == 1);
    CHECK(y["date"].as<std::string>() == "2014-02-11");
    CHECK(y["origin"].as<std::string>() == kZurich.filename().string());
    CHECK(y["estimator"]["gnss_delay"].as<double>() == doctest::Approx(0.21));  // msecPosDelay 210
    CHECK(y["estimator"]["baro_delay"].as<double>() == doctest::Approx(0.35));
    CHECK(y["estimator"]["mag_delay"].as<double>() == doctest::Approx(0.03));
    CHECK(y["estimator"]["diff_pressure_delay"].as<double>() == doctest::Approx(0.21));
    CHECK(y["estimator"]["rho"].as<double>() == doctest::Approx(1.225));  // EAS2TAS 1.0 in timing.txt
    CHECK(y["notes"].size() >= 5);
  }
}

TEST_CASE("an archive's warnings name the archive, not the directory it was unpacked into") {
  const tern::core::ArchiveInput a(kZurich);
  const std::string zip = kZurich.string();
  CHECK(a.readable(a.dir().string() + ": no surface commands") == zip + ": no surface commands");
  CHECK(a.readable((a.dir() / "GPS.txt").string() + ":12: bad row") == zip + ":GPS.txt:12: bad row");
}

TEST_CASE("inertialnav: without GPSraw.txt the velocity comes from speed and course; bad rows give one line") {
  TempDir d;
  const ArchiveInput zurich(kZurich);
  const fs::path in = d.path / "in";
  fs::create_directories(in);
  for (const char* f : {"IMU.txt", "MAG.txt", "NTUN.txt", "GPS.txt", "timing.txt"}) copy_lines(zurich.dir() / f, in / f, 120);
  const ImportReport r = import_into(in, d.path / "a", import_inertialnav);
  CHECK(r.rows.at("gnss") == 120);
  CHECK(r.rows.count("reference") == 0);
  const Table t = read_table(d.path / "a" / "topics" / "gnss.csv");
  const auto& row = t.at(19939400000);  // line 101: Vg 9.8581388 m/s, course 4.374728 rad
  CHECK(t.num(row, "vel_n") == doctest::Approx(9.8581388 * std::cos(4.374728)).epsilon(1e-12));
  CHECK(t.num(row, "vel_e") == doctest::Approx(9.8581388 * std::sin(4.374728)).epsilon(1e-12));

  // a GPS.txt cut in its 50th line
  {
    std::ofstream gps(in / "GPS.txt", std::ios::app);
    gps << "   2.1e+04   3.0000000e+00   2.1e+04   0.0 0.0\n";
  }
  const std::string truncated = import_error(in, d.path / "b", import_inertialnav);
  CHECK(truncated.find("GPS.txt:121: expected 14 values, got 5") != std::string::npos);
  CHECK(truncated.find('\n') == std::string::npos);
  copy_lines(zurich.dir() / "GPS.txt", in / "GPS.txt", 120);
  // a cell that is no number
  {
    std::ofstream imu(in / "IMU.txt", std::ios::app);
    imu << "9.0e+05 9.0e+05 0.1 0.2 abc 0.0 0.0 -9.8\n";
  }
  const std::string corrupt = import_error(in, d.path / "c", import_inertialnav);
  CHECK(corrupt.find("IMU.txt:121: column 5: 'abc' is not a finite number") != std::string::npos);
}

TEST_CASE("alfa: the Carbon-Z engine-failure flight, from its tar.gz as shipped") {
  TempDir d;
  const fs::path log = d.path / "alfa";
  const ImportReport r = import_into(kAlfa, log, alfa_default);
  // one row per data line (the CSVs' line counts minus their header)
  CHECK(r.rows.at("imu") == 1324);
  CHECK(r.rows.at("mag") == 1324);
  CHECK(r.rows.at("baro") == 1323);
  CHECK(r.rows.at("gnss") == 662);
  CHECK(r.rows.at("diff_pressure") == 2471);
  CHECK(r.rows.at("reference") == 544 + 544);  // odometry rows and global-position rows
  CHECK(has_warning(r, "the IMU is logged at 10.0 Hz"));
  CHECK(has_warning(r, "no vertical velocity"));
  // the shipped flight has no rc/out table: no surface commands, one line
  CHECK(has_warning(r, ": no surface commands in this log (no *-mavros-rc-out.csv): no actuators.csv written (tern sysid needs one)"));
  CHECK(r.rows.count("actuators") == 0);
  {  // what the log implies for the estimator: no down velocity, the field's default GNSS latency
    const YAML::Node y = YAML::LoadFile((log / "sensor_log.yaml").string());
    CHECK(y["estimator"]["use_gnss_vel_d"].as<bool>() == false);
    CHECK(y["estimator"]["gnss_delay"].as<double>() == 0.11);
  }

  // time zero: the earliest first header stamp, nav_info/airspeed's 1531943810860078371 ns
  constexpr std::int64_t t0 = 1531943810860078371;
  SUBCASE("imu: data_raw's first row, body FLU -> FRD (y, z negated)") {
    // stamp 1531943810878600982; angular_velocity (2.018, -0.293, 0.212); linear_acceleration (1.79461695, -0.1372931, 14.0823494)
    const Table t = read_table(log / "topics" / "imu.csv");
    const auto& row = t.at(1531943810878600982 - t0);
    CHECK(t.rows.front() == row);
    CHECK(t.num(row, "gyro_x") == 2.018);
    CHECK(t.num(row, "gyro_y") == 0.293);
    CHECK(t.num(row, "gyro_z") == -0.212);
    CHECK(t.num(row, "accel_x") == 1.79461695);
    CHECK(t.num(row, "accel_y") == 0.1372931);
    CHECK(t.num(row, "accel_z") == -14.0823494);  // FLU +14: pulling 1.4 g up; FRD: -14
  }
  SUBCASE("mag: first row, mavros value / 1000 = mGauss, * 1e-7 = T, FLU -> FRD") {
    // magnetic_field (-194000, 440000, -250000): (-194, 440, -250) mGauss FLU -> (-194, -440, 250) mGauss FRD; |B| = 54 uT
    const Table t = read_table(log / "topics" / "mag.csv");
    const auto& row = t.at(1531943810878600982 - t0);
    CHECK(t.num(row, "field_x") == doctest::Approx(-194.0 * 1e-7).epsilon(1e-12));
    CHECK(t.num(row, "field_y") == doctest::Approx(-440.0 * 1e-7).epsilon(1e-12));
    CHECK(t.num(row, "field_z") == doctest::Approx(250.0 * 1e-7).epsilon(1e-12));
  }
  SUBCASE("baro, diff_pressure: Pa as written; airspeed (EAS) -> 0.5 * 1.225 * EAS^2") {
    const Table b = read_table(log / "topics" / "baro.csv");
    CHECK(b.num(b.at(1531943810882826784 - t0), "pressure") == 97310.4980469);
    const Table dp = read_table(log / "topics" / "diff_pressure.csv");
    CHECK(dp.num(dp.at(0), "pressure") == doctest::Approx(0.5 * 1.225 * 17.666934967 * 17.666934967).epsilon(1e-12));  // 191.2 Pa
  }
  SUBCASE("gnss: raw/fix + raw/gps_vel's first row, ENU -> NED") {
    // fix: 40.5914601, -79.8995372, 349.262177802, covariance0 0.435600034618, covariance8 1.74240013847
    // gps_vel (ENU): (19.0866183839, -1.98924575298, 0.0) -> NED (-1.98924575298, 19.0866183839, 0)
    const Table t = read_table(log / "topics" / "gnss.csv");
    const auto& row = t.at(1531943810933254299 - t0);
    CHECK(t.num(row, "lat") == 40.5914601);
    CHECK(t.num(row, "lon") == -79.8995372);
    CHECK(t.num(row, "alt") == 349.262177802);
    CHECK(t.num(row, "vel_n") == -1.98924575298);
    CHECK(t.num(row, "vel_e") == 19.0866183839);
    CHECK(t.num(row, "vel_d") == 0.0);
    // covariance type 1: mavros' (HDOP * gps_uere)^2 = 0.4356 is a DOP, not an accuracy: none
    // reported; the dilutions are (gps_uere 1: HDOP 0.66, and the VDOP from covariance 8)
    CHECK(t.num(row, "h_acc") == 0.0);
    CHECK(t.num(row, "v_acc") == 0.0);
    CHECK(t.num(row, "hdop") == doctest::Approx(0.66).epsilon(1e-6));
    CHECK(t.num(row, "vdop") > t.num(row, "hdop"));
  }
  SUBCASE("reference: odometry's first row, ENU/FLU quaternion -> NED/FRD Euler angles") {
    // orientation (x, y, z, w) = (0.430355280624, 0.0100020537959, -0.00634773302409, -0.902581850939)
    // ROS roll/pitch/yaw of FLU in ENU; the same body in NED/FRD: phi = roll, theta = -pitch, psi = pi/2 - yaw
    const double x = 0.430355280624, y = 0.0100020537959, z = -0.00634773302409, w = -0.902581850939;
    const double roll = std::atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y));
    const double pitch = std::asin(2 * (w * y - z * x));
    const double yaw = std::atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
    const Table t = read_table(log / "topics" / "reference.csv");
    const auto& row = t.at(1531943810886923691 - t0);
    CHECK(t.num(row, "phi") == doctest::Approx(roll).epsilon(1e-9));
    CHECK(t.num(row, "theta") == doctest::Approx(-pitch).epsilon(1e-9));
    CHECK(std::remainder(t.num(row, "psi") - (M_PI / 2 - yaw), 2 * M_PI) == doctest::Approx(0.0).epsilon(1e-9));
    // its body velocity rotated to NED points where the GNSS says the aircraft goes (east, 19 m/s)
    CHECK(t.num(row, "v_e") == doctest::Approx(19.49).epsilon(0.01));
    CHECK(std::isnan(t.num(row, "lat")));
    const auto& pos = t.at(1531943810884418155 - t0);  // global_position/global's first row
    CHECK(t.num(pos, "lat") == 40.5914577);
    CHECK(std::isnan(t.num(pos, "phi")));
  }
  SUBCASE("sensor_log.yaml: the date from the stamps, the engine failure in the notes") {
    const YAML::Node y = YAML::LoadFile((log / "sensor_log.yaml").string());
    CHECK(y["date"].as<std::string>() == "2018-07-18");
    bool failure_noted = false;
    for (const auto& n : y["notes"]) failure_noted |= n.as<std::string>().find("engine failure flag set from t = ") != std::string::npos;
    CHECK(failure_noted);
  }
}

TEST_CASE("alfa: a truncated CSV gives one line naming the file and line") {
  TempDir d;
  const ArchiveInput alfa(kAlfa);
  const fs::path in = d.path / "in";
  fs::create_directories(in);
  for (const auto& e : fs::directory_iterator(alfa.dir())) fs::copy_file(e.path(), in / e.path().filename());
  const std::string mag = "carbonZ_2018-07-18-15-53-31_1_engine_failure-mavros-imu-mag.csv";
  copy_lines(alfa.dir() / mag, in / mag, 500);
  {
    std::ofstream f(in / mag, std::ios::app);
    f << "1531943860000000000,2810,1531943860000000000,base_link,-194000.0\n";
  }
  const std::string e = import_error(in, d.path / "out", alfa_default);
  CHECK(e.find(mag + ":501: expected 16 values, got 5") != std::string::npos);
  CHECK(e.find('\n') == std::string::npos);
  CHECK(import_error(kFlights / "no_such.tar.gz", d.path / "out2", alfa_default).find("no_such.tar.gz: no such file") != std::string::npos);
}

TEST_CASE("alfa: rc/out's servo pulses -> actuators: ArduPlane's channel map, the uavbook's signs, a reversed channel") {
  TempDir d;
  const ArchiveInput alfa(kAlfa);
  const fs::path in = d.path / "in";
  fs::create_directories(in);
  for (const auto& e : fs::directory_iterator(alfa.dir())) fs::copy_file(e.path(), in / e.path().filename());
  // mavros_msgs/RCOut as `rostopic echo -p` writes it, at the full dataset's ~3 Hz; time zero stays
  // nav_info/airspeed's first stamp 1531943810860078371 ns
  constexpr std::int64_t t0 = 1531943810860078371, t1 = 1531943811860078371, t2 = 1531943812193411704, t3 = 1531943812526745037;
  {
    std::ofstream f(in / "carbonZ_2018-07-18-15-53-31_1_engine_failure-mavros-rc-out.csv");
    f << "%time,field.header.seq,field.header.stamp,field.header.frame_id,field.channels0,field.channels1,field.channels2,"
         "field.channels3,field.channels4,field.channels5,field.channels6,field.channels7\n";
    // ch1 aileron 1600 us (+0.2: roll right), ch2 elevator 1400 us (-0.2: nose down), ch3 throttle 1750 us (0.75),
    // ch4 rudder 1450 us (-0.1: yaw left)
    f << t1 + 1000 << ",1," << t1 << ",,1600,1400,1750,1450,1500,1500,1000,1000\n";
    f << t2 + 1000 << ",2," << t2 << ",,1500,1500,1000,1500,1500,1500,1000,1000\n";
    f << t3 + 1000 << ",3," << t3 << ",,1000,2000,2000,2000,1500,1500,1000,1000\n";
  }
  CommandMapping m;
  m.max_deflection = std::array<double, 3>{0.35, 0.30, 0.40};
  SUBCASE("the default map 1 2 3 4") {
    SensorLogWriter out(d.path / "log");
    const ImportReport r = import_alfa(in, out, m);
    CHECK(r.rows.at("actuators") == 3);
    CHECK(r.rows.at("imu") == 1324);  // the sensors as without rc/out
    CHECK(has_warning(r,
                      "-mavros-rc-out.csv: the surfaces' commands are logged at 3.0 Hz, below the 50 Hz sysid needs (a held command "
                      "lags half a sample, 167 ms: 15 deg of phase at 0.25 Hz); quasi-steady lift and drag at best"));
    const Table t = read_table(d.path / "log" / "topics" / "actuators.csv");
    const auto& a = t.at(t1 - t0);
    CHECK(t.num(a, "delta_a") == doctest::Approx(0.2 * 0.35).epsilon(1e-12));  // roll right: delta_a > 0
    CHECK(t.num(a, "delta_e") == doctest::Approx(0.2 * 0.30).epsilon(1e-12));  // nose down: delta_e > 0
    CHECK(t.num(a, "delta_r") == doctest::Approx(0.1 * 0.40).epsilon(1e-12));  // yaw left: delta_r > 0
    CHECK(t.num(a, "delta_t") == doctest::Approx(0.75).epsilon(1e-12));
    const auto& centre = t.at(t2 - t0);
    for (const char* c : {"delta_a", "delta_e", "delta_r", "delta_t"}) CHECK(t.num(centre, c) == 0.0);
    const auto& full = t.at(t3 - t0);  // full left stick, full nose up, full throttle, full right rudder
    CHECK(t.num(full, "delta_a") == doctest::Approx(-0.35).epsilon(1e-12));
    CHECK(t.num(full, "delta_e") == doctest::Approx(-0.30).epsilon(1e-12));
    CHECK(t.num(full, "delta_r") == doctest::Approx(-0.40).epsilon(1e-12));
    CHECK(t.num(full, "delta_t") == 1.0);
    const YAML::Node y = YAML::LoadFile((d.path / "log" / "sensor_log.yaml").string());
    bool mapped = false;
    for (const auto& n : y["notes"])
      mapped |= n.as<std::string>().find("channels aileron 1, elevator 2, throttle 3, rudder 4") != std::string::npos;
    CHECK(mapped);
  }
  SUBCASE("elevator on a reversed channel 2, the delay shifting the stamps") {
    m.rc_channels = {1, -2, 3, 4};
    m.command_delay = 0.05;
    SensorLogWriter out(d.path / "log");
    import_alfa(in, out, m);
    const Table t = read_table(d.path / "log" / "topics" / "actuators.csv");
    const auto& a = t.at(t1 - t0 + 50'000'000);
    CHECK(t.num(a, "delta_e") == doctest::Approx(-0.2 * 0.30).epsilon(1e-12));
    CHECK(t.num(a, "delta_a") == doctest::Approx(0.2 * 0.35).epsilon(1e-12));
  }
  SUBCASE("without --max-deflection: no actuators, one line") {
    SensorLogWriter out(d.path / "log");
    const ImportReport r = import_alfa(in, out);
    CHECK(r.rows.count("actuators") == 0);
    CHECK(has_warning(r,
                      "carbonZ_2018-07-18-15-53-31_1_engine_failure-mavros-rc-out.csv: holds the servos' pulses: no actuators.csv "
                      "written without --max-deflection A E R"));
  }
  SUBCASE("a channel the table does not have: one error line naming the file and column") {
    m.rc_channels = {1, 2, 3, 9};
    SensorLogWriter out(d.path / "log");
    std::string e;
    try {
      import_alfa(in, out, m);
    } catch (const ImportError& x) {
      e = x.what();
    }
    CHECK(e.find("-mavros-rc-out.csv:1: no column 'field.channels8'") != std::string::npos);
  }
}
