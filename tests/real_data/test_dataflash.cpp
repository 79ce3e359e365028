// `tern import dataflash` on ArduPilot DataFlash logs written here from the format's spec
// (libraries/AP_Logger/LogStructure.h: FMT, the format characters and their scales; the messages'
// labels as ArduPlane 4.5 writes them): a synthetic flight of known values (IMU 400 Hz, GPS/GPA 5 Hz,
// BARO/ARSP/MAG/ATT/POS 10 Hz, RCOU 50 Hz, a SIDD manoeuvre, the PARMs mapping the servo outputs),
// checked for values, units, frames, stamps and the surface mapping; then hostile files.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "../test_process.hpp"
#include "import/dataflash_import.hpp"
#include "import/dataflash_reader.hpp"
#include "import/importers.hpp"
#include "tern/atmosphere.hpp"
#include "tern/math.hpp"

namespace fs = std::filesystem;

namespace {

/// A DataFlash log written byte by byte: FMT messages from a format string and labels, then
/// messages of those types packed by their format characters (c C e E stored * 100, L * 1e7).
class DataflashBytes {
 public:
  using Value = std::variant<double, std::string>;
  DataflashBytes() { fmt(128, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns"); }
  /// A FMT message; `length` overrides the length the format makes (a lying FMT).
  void fmt(std::uint8_t type, const std::string& name, const std::string& format, const std::string& labels, int length = -1) {
    std::size_t n = 3;
    for (char c : format) n += tern::core::dataflash::field_size(c);
    formats_[type] = format;
    std::string body;
    body += static_cast<char>(type);
    body += static_cast<char>(length >= 0 ? length : static_cast<int>(n));
    body += fixed(name, 4) + fixed(format, 16) + fixed(labels, 64);
    raw_message(128, body);
  }
  void msg(std::uint8_t type, const std::vector<Value>& values) {
    const std::string& format = formats_.at(type);
    REQUIRE(values.size() == format.size());
    std::string body;
    for (std::size_t i = 0; i < format.size(); ++i) body += pack(format[i], values[i]);
    raw_message(type, body);
  }
  void raw_message(std::uint8_t type, const std::string& body) {
    bytes_ += "\xA3\x95";
    bytes_ += static_cast<char>(type);
    bytes_ += body;
  }
  void garbage(const std::string& g) { bytes_ += g; }
  const std::string& bytes() const { return bytes_; }

 private:
  static std::string fixed(const std::string& s, std::size_t n) {
    REQUIRE(s.size() <= n);
    return s + std::string(n - s.size(), '\0');
  }
  template <class T>
  static std::string raw(T v) {
    std::string s(sizeof v, '\0');
    std::memcpy(s.data(), &v, sizeof v);
    return s;
  }
  static std::string pack(char c, const Value& v) {
    if (c == 'n' || c == 'N' || c == 'Z') return fixed(std::get<std::string>(v), tern::core::dataflash::field_size(c));
    const double x = std::get<double>(v);
    switch (c) {
      case 'b': return raw(static_cast<std::int8_t>(x));
      case 'B':
      case 'M': return raw(static_cast<std::uint8_t>(x));
      case 'h': return raw(static_cast<std::int16_t>(std::lround(x)));
      case 'H': return raw(static_cast<std::uint16_t>(std::lround(x)));
      case 'c': return raw(static_cast<std::int16_t>(std::lround(x * 100)));
      case 'C': return raw(static_cast<std::uint16_t>(std::lround(x * 100)));
      case 'i': return raw(static_cast<std::int32_t>(std::llround(x)));
      case 'I': return raw(static_cast<std::uint32_t>(std::llround(x)));
      case 'e': return raw(static_cast<std::int32_t>(std::llround(x * 100)));
      case 'E': return raw(static_cast<std::uint32_t>(std::llround(x * 100)));
      case 'L': return raw(static_cast<std::int32_t>(std::llround(x * 1e7)));
      case 'q': return raw(static_cast<std::int64_t>(x));
      case 'Q': return raw(static_cast<std::uint64_t>(x));
      case 'f': return raw(static_cast<float>(x));
      case 'd': return raw(x);
      default: FAIL("format character " << c); return {};
    }
  }
  std::map<std::uint8_t, std::string> formats_;
  std::string bytes_;
};

// ArduPlane 4.5's types (ids as its logs number them; any id works, the FMTs say)
enum : std::uint8_t {
  PARM = 64,
  MSG = 91,
  IMU = 130,
  GPS = 131,
  GPA = 132,
  BARO = 133,
  ARSP = 134,
  MAG = 135,
  RCOU = 136,
  ATT = 137,
  POS = 138,
  SIDS = 139,
  SIDD = 140
};

constexpr double kT0 = 5.0;  // s: the log starts 5 s after boot
constexpr double kLat = 47.3977419, kLon = 8.5455938, kAlt = 488.5;

struct Options {
  bool garbage = false;  ///< bytes between messages
  bool unknown = false;  ///< a header of a type no FMT defines
  bool elevons = false;  ///< SERVO1/2 elevons instead of aileron/elevator
  bool vtail = false;    ///< SERVO1/2 a V-tail instead of aileron/elevator, no rudder on C5
  bool sid = true;       ///< a SIDD manoeuvre on the pitch mixer
  int sid_axis = 11;
};

double us(double t_s) { return std::round(t_s * 1e6); }

/// A 4-s synthetic flight: the values below, at the rates of an ArduPlane log.
std::string synthetic_log(const Options& o = {}) {
  DataflashBytes d;
  d.fmt(PARM, "PARM", "QNff", "TimeUS,Name,Value,Default");
  d.fmt(MSG, "MSG", "QZ", "TimeUS,Message");
  d.fmt(IMU, "IMU", "QBffffffIIfBBHH", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,EG,EA,T,GH,AH,GHz,AHz");
  d.fmt(GPS, "GPS", "QBBIHBcLLeffffB", "TimeUS,I,Status,GMS,GWk,NSats,HDop,Lat,Lng,Alt,Spd,GCrs,VZ,Yaw,U");
  d.fmt(GPA, "GPA", "QBCCCCfBIHH", "TimeUS,I,VDop,HAcc,VAcc,SAcc,YAcc,VV,SMS,Delta,Und");
  d.fmt(BARO, "BARO", "QBfffcfIffB", "TimeUS,I,Alt,AltAMSL,Press,Temp,CRt,SMS,Offset,GndTemp,H");
  d.fmt(ARSP, "ARSP", "QBffcffBBffB", "TimeUS,I,Airspeed,DiffPress,Temp,RawPress,Offset,U,H,Hp,TR,Pri");
  d.fmt(MAG, "MAG", "QBhhhhhhhhhBI", "TimeUS,I,MagX,MagY,MagZ,OfsX,OfsY,OfsZ,MOX,MOY,MOZ,Health,S");
  d.fmt(RCOU, "RCOU", "QHHHHHHHHHHHHHH", "TimeUS,C1,C2,C3,C4,C5,C6,C7,C8,C9,C10,C11,C12,C13,C14");
  d.fmt(ATT, "ATT", "QccccCCCCB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF");
  d.fmt(POS, "POS", "QLLfff", "TimeUS,Lat,Lng,Alt,RelHomeAlt,RelOriginAlt");
  d.fmt(SIDS, "SIDS", "QBfffffff", "TimeUS,Ax,Mag,FSt,FSp,TFin,TC,TR,TFout");
  d.fmt(SIDD, "SIDD", "Qfffffffff", "TimeUS,Time,Targ,F,Gx,Gy,Gz,Ax,Ay,Az");
  d.msg(MSG, {us(kT0), std::string("ArduPlane V4.5.7 (test)")});
  auto parm = [&](const std::string& n, double v) { d.msg(PARM, {us(kT0), n, v, 0.0}); };
  if (o.vtail) {
    parm("SERVO1_FUNCTION", 79), parm("SERVO2_FUNCTION", 80), parm("MIXING_GAIN", 0.5);
  } else if (o.elevons) {
    parm("SERVO1_FUNCTION", 77), parm("SERVO2_FUNCTION", 78), parm("MIXING_GAIN", 0.5);
  } else {
    parm("SERVO1_FUNCTION", 4), parm("SERVO2_FUNCTION", 19);
    parm("SERVO2_MIN", 1000), parm("SERVO2_TRIM", 1400), parm("SERVO2_MAX", 2000);
  }
  parm("SERVO3_FUNCTION", 70), parm("SERVO4_FUNCTION", 0);
  parm("SERVO5_FUNCTION", o.vtail ? 0 : 21), parm("SERVO5_REVERSED", 1);  // the rudder on channel 5, reversed
  parm("ARSPD_RATIO", 2.0), parm("GPS_DELAY_MS", 150), parm("EK3_HGT_DELAY", 60);
  for (int k = 0; k < 1600; ++k) {  // IMU 400 Hz, instance 0 and 1
    const double t = kT0 + 0.0025 * k;
    d.msg(IMU, {us(t), 0.0, 0.1 * std::sin(t), 0.05, -0.02, 0.5, 0.1, -tern::kGravity, 0.0, 0.0, 41.25, 1.0, 1.0, 400.0, 400.0});
    d.msg(IMU, {us(t), 1.0, 9.0, 9.0, 9.0, 9.0, 9.0, 9.0, 0.0, 0.0, 40.0, 1.0, 1.0, 400.0, 400.0});
    if (o.garbage && k % 97 == 5) d.garbage(std::string("\x01\x02\xA3\x03garbage", 11));
    if (o.unknown && k == 10) d.raw_message(200, std::string(20, '\x55'));
    if (k % 8 == 0) {  // RCOU 50 Hz
      if (o.vtail) {   // rudder 0.2, elevator 0.1: left (0.1 + 0.2) * 0.5, right (0.1 - 0.2) * 0.5
        d.msg(RCOU, {us(t), 1500 + 0.15 * 400, 1500 - 0.05 * 400, 1580.0, 1234.0, 1400.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0});
      } else if (o.elevons) {  // aileron 0.2, elevator 0.1: left (0.1 - 0.2) * 0.5, right (0.1 + 0.2) * 0.5
        d.msg(RCOU, {us(t), 1500 - 0.05 * 400, 1500 + 0.15 * 400, 1580.0, 1234.0, 1400.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0});
      } else {  // aileron 0.3, elevator -0.5 (below TRIM 1400: (1400 - 1000) * 0.5), throttle 0.6, rudder 0.25 reversed
        d.msg(RCOU, {us(t), 1620.0, 1200.0, 1580.0, 1234.0, 1400.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0});
      }
    }
    if (k % 40 == 0) {  // 10 Hz
      d.msg(BARO, {us(t), 0.0, 12.0, 500.0, 95000.0 + k, 25.5, 0.0, 0.0, 0.0, 0.0, 1.0});
      d.msg(ARSP, {us(t), 0.0, 21.9, 240.0, 20.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 0.0});
      d.msg(MAG, {us(t), 0.0, 200.0, -50.0, 400.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0});
      d.msg(ATT, {us(t), 0.0, 10.5, 0.0, -3.25, 0.0, 350.0, 0.0, 0.0, 0.0});
      d.msg(POS, {us(t), kLat, kLon, kAlt, 12.0, 12.0});
    }
    if (k % 80 == 0) {  // GPS 5 Hz and its accuracies
      d.msg(GPS, {us(t), 0.0, 3.0, 300000000.0 + 1000 * (t - kT0), 2300.0, 12.0, 0.8, kLat, kLon, kAlt, 20.0, 30.0, -1.5, 0.0, 1.0});
      d.msg(GPA, {us(t), 0.0, 1.2, 1.5, 2.5, 0.3, 0.0, 1.0, t * 1000, 0.0, 0.0});
    }
    if (o.sid && k == 400) d.msg(SIDS, {us(t), static_cast<double>(o.sid_axis), 0.1, 0.5, 4.0, 0.0, 4.0, 1.0, 0.0});
    if (o.sid && k >= 400 && k < 800 && k % 8 == 0) {  // SIDD 50 Hz from 1 s to 2 s
      const double tau = (k - 400) * 0.0025;
      d.msg(SIDD, {us(t), tau, 0.1 * std::sin(2 * M_PI * 2 * tau), 2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0});
    }
  }
  return d.bytes();
}

fs::path scratch(const std::string& name, const std::string& bytes) {
  const fs::path p = fs::temp_directory_path() / ("tern_test_dataflash_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}

struct Imported {
  tern::core::ImportReport report;
  fs::path dir;
  /// The table's rows, split at commas (the header first).
  std::vector<std::vector<std::string>> rows(const std::string& topic) const {
    std::ifstream in(dir / "topics" / (topic + ".csv"));
    std::vector<std::vector<std::string>> out;
    for (std::string line; std::getline(in, line);) {
      std::vector<std::string> cells;
      std::stringstream ss(line);
      for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
      out.push_back(cells);
    }
    return out;
  }
  /// Column `name` ("delta_a [rad]", or "fix_type" for "fix_type [enum]") of the table's row `i` (1: the first after the header).
  double at(const std::string& topic, std::size_t i, const std::string& name) const {
    const auto r = rows(topic);
    const auto col =
        std::find_if(r.at(0).begin(), r.at(0).end(), [&](const std::string& c) { return c == name || c.rfind(name + " [", 0) == 0; });
    REQUIRE(col != r.at(0).end());
    return std::stod(r.at(i).at(static_cast<std::size_t>(col - r.at(0).begin())));
  }
  /// The column's first value that is not NaN (rows of one stamp from two messages come in either order).
  double first(const std::string& topic, const std::string& name) const {
    const std::size_t n = rows(topic).size();
    for (std::size_t i = 1; i < n; ++i)
      if (const double v = at(topic, i, name); !std::isnan(v)) return v;
    FAIL("no value in " << topic << "'s " << name);
    return 0.0;
  }
  ~Imported() { fs::remove_all(dir); }
};

Imported import_bytes(const std::string& name, const std::string& bytes, const tern::core::CommandMapping& m = {}) {
  const fs::path bin = scratch(name + ".bin", bytes);
  Imported i;
  i.dir = fs::temp_directory_path() / ("tern_test_dataflash_out_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(i.dir);
  try {
    tern::core::SensorLogWriter out(i.dir);
    i.report = tern::core::import_dataflash(bin, out, m);
  } catch (...) {
    fs::remove(bin);
    throw;
  }
  fs::remove(bin);
  return i;
}

/// The one ImportError line of importing `bytes`, without the file's name (checked to lead it).
std::string import_error(const std::string& name, const std::string& bytes) {
  const fs::path bin = fs::temp_directory_path() / ("tern_test_dataflash_" + std::to_string(::getpid()) + "_" + name + ".bin");
  std::string e;
  try {
    (void)import_bytes(name, bytes);
  } catch (const tern::core::ImportError& x) {
    e = x.what();
  }
  fs::remove_all(fs::temp_directory_path() / ("tern_test_dataflash_out_" + std::to_string(::getpid()) + "_" + name));
  CHECK(e.rfind(bin.string() + ": ", 0) == 0);
  CHECK(e.find('\n') == std::string::npos);
  return e.substr(std::min(e.size(), bin.string().size() + 2));
}

tern::core::CommandMapping deflections() {
  tern::core::CommandMapping m;
  m.max_deflection = std::array<double, 3>{0.35, 0.30, 0.40};
  return m;
}

bool has_warning(const tern::core::ImportReport& r, const std::string& part) {
  return std::count_if(r.warnings.begin(), r.warnings.end(), [&](const std::string& w) { return w.find(part) != std::string::npos; }) == 1;
}

}  // namespace

TEST_CASE("tern import dataflash: a synthetic ArduPlane log's sensors, in the sensor log's units, frames and stamps") {
  const Imported i = import_bytes("flight", synthetic_log(), deflections());
  CHECK(i.report.rows.at("imu") == 1600);  // instance 0 only
  CHECK(i.report.rows.at("gnss") == 20);
  CHECK(i.report.rows.at("baro") == 40);
  CHECK(i.report.rows.at("diff_pressure") == 40);
  CHECK(i.report.rows.at("mag") == 40);
  CHECK(i.report.rows.at("reference") == 80);  // ATT and POS, one row each
  CHECK(i.report.rows.at("actuators") == 200);
  // stamps: TimeUS minus the first (5 s after boot)
  const auto imu = i.rows("imu");
  CHECK(imu.at(0).at(0) == "t [s]");
  CHECK(imu.at(1).at(1) == "0");
  CHECK(imu.at(2).at(1) == "2500000");
  CHECK(i.at("imu", 2, "gyro_x [rad/s]") == doctest::Approx(0.1 * std::sin(kT0 + 0.0025)).epsilon(1e-6));
  CHECK(i.at("imu", 1, "gyro_y [rad/s]") == doctest::Approx(0.05).epsilon(1e-6));
  CHECK(i.at("imu", 1, "accel_z [m/s^2]") == doctest::Approx(-tern::kGravity).epsilon(1e-6));  // FRD: level at rest -g
  CHECK(i.at("imu", 1, "temperature [K]") == doctest::Approx(41.25 + tern::kZeroCelsius));
  // GPS: L (1e-7 deg), e (cm), speed and course as NED, VZ down; GPA's accuracies (C: cm, / 100)
  CHECK(i.at("gnss", 1, "lat [deg]") == doctest::Approx(kLat).epsilon(1e-12));
  CHECK(i.at("gnss", 1, "lon [deg]") == doctest::Approx(kLon).epsilon(1e-12));
  CHECK(i.at("gnss", 1, "alt [m]") == doctest::Approx(kAlt));
  CHECK(i.at("gnss", 1, "vel_n [m/s]") == doctest::Approx(20.0 * std::cos(M_PI / 6)).epsilon(1e-6));
  CHECK(i.at("gnss", 1, "vel_e [m/s]") == doctest::Approx(10.0).epsilon(1e-6));
  CHECK(i.at("gnss", 1, "vel_d [m/s]") == doctest::Approx(-1.5));
  CHECK(i.at("gnss", 1, "fix_type") == 3);
  CHECK(i.at("gnss", 1, "num_sats") == 12);
  CHECK(i.at("gnss", 1, "hdop") == doctest::Approx(0.8));
  CHECK(i.at("gnss", 1, "vdop") == doctest::Approx(1.2));
  CHECK(i.at("gnss", 1, "h_acc [m]") == doctest::Approx(1.5));
  CHECK(i.at("gnss", 1, "v_acc [m]") == doctest::Approx(2.5));
  CHECK(i.at("gnss", 1, "s_acc [m/s]") == doctest::Approx(0.3));
  CHECK(i.at("gnss", 2, "stamp [ns]") == 200000000);
  // BARO Pa, degC * 100; ARSP DiffPress * ARSPD_RATIO 2 * rho0 / 2; MAG mGauss
  CHECK(i.at("baro", 2, "pressure [Pa]") == doctest::Approx(95040.0));
  CHECK(i.at("baro", 1, "temperature [K]") == doctest::Approx(25.5 + tern::kZeroCelsius));
  CHECK(i.at("diff_pressure", 1, "pressure [Pa]") == doctest::Approx(240.0 * 2.0 * tern::kIsaSeaLevelDensity / 2.0));
  CHECK(i.at("diff_pressure", 1, "temperature [K]") == doctest::Approx(293.15));
  CHECK(i.at("mag", 1, "field_x [T]") == doctest::Approx(200e-7));
  CHECK(i.at("mag", 1, "field_y [T]") == doctest::Approx(-50e-7));
  CHECK(i.at("mag", 1, "field_z [T]") == doctest::Approx(400e-7));
  // ATT centidegrees, yaw 350 deg as -10 deg; POS
  CHECK(i.first("reference", "phi [rad]") == doctest::Approx(10.5 * M_PI / 180));
  CHECK(i.first("reference", "theta [rad]") == doctest::Approx(-3.25 * M_PI / 180));
  CHECK(i.first("reference", "psi [rad]") == doctest::Approx(-10.0 * M_PI / 180));
  CHECK(i.first("reference", "lat [deg]") == doctest::Approx(kLat).epsilon(1e-12));
  CHECK(i.first("reference", "alt [m]") == doctest::Approx(kAlt));

  const YAML::Node y = YAML::LoadFile((i.dir / "sensor_log.yaml").string());
  CHECK(y["date"].as<std::string>() == "2024-02-07");  // GPS week 2300, 300000 s, minus 18 leap seconds
  CHECK(y["estimator"]["gnss_delay"].as<double>() == doctest::Approx(0.15));
  CHECK(y["estimator"]["baro_delay"].as<double>() == doctest::Approx(0.06));
  CHECK(!y["estimator"]["use_gnss_vel_d"]);  // GPA's VV 1: the receiver gives a vertical velocity
  CHECK(y["source"].as<std::string>().find("ArduPlane V4.5.7 (test)") != std::string::npos);
  CHECK(i.report.warnings.empty());
}

TEST_CASE("tern import dataflash: RCOU through SERVOn_FUNCTION/MIN/TRIM/MAX/REVERSED; elevons unmixed; SIDD as the excitation") {
  SUBCASE("aileron C1, elevator C2 (TRIM 1400 in 1000..2000), throttle C3, rudder on C5 reversed") {
    const Imported i = import_bytes("surfaces", synthetic_log(), deflections());
    CHECK(i.at("actuators", 1, "delta_a [rad]") == doctest::Approx(0.3 * 0.35));    // roll right: delta_a > 0
    CHECK(i.at("actuators", 1, "delta_e [rad]") == doctest::Approx(0.5 * 0.30));    // nose down (-0.5): delta_e > 0
    CHECK(i.at("actuators", 1, "delta_r [rad]") == doctest::Approx(-0.25 * 0.40));  // 1400 us reversed: yaw right 0.25
    CHECK(i.at("actuators", 1, "delta_t") == doctest::Approx(0.6));                 // (1580 - 1100) / (1900 - 1100)
    CHECK(i.at("actuators", 2, "stamp [ns]") == 20000000);
    const YAML::Node y = YAML::LoadFile((i.dir / "sensor_log.yaml").string());
    std::string notes;
    for (const auto& n : y["notes"]) notes += n.as<std::string>() + "\n";
    CHECK(notes.find("C5 rudder (SERVO5_FUNCTION 21, MIN 1100 TRIM 1500 MAX 1900, REVERSED)") != std::string::npos);
    // SIDD on Mixer Pitch (SIDS Ax 11): Targ a fraction of the elevator's full command, nose up positive
    const auto x = i.rows("excitation");
    REQUIRE(x.size() == 1 + 1 + 50 + 1);  // a 0 at the start, 50 samples, a 0 after the last
    CHECK(i.at("excitation", 1, "delta_e [rad]") == 0.0);
    CHECK(x.at(2).at(1) == "1000000000");
    CHECK(i.at("excitation", 2 + 6, "delta_e [rad]") == doctest::Approx(-0.30 * 0.1 * std::sin(2 * M_PI * 2 * 6 * 0.02)).epsilon(1e-6));
    CHECK(i.at("excitation", 2 + 6, "delta_a [rad]") == 0.0);
    CHECK(x.back().at(1) == "2000000000");
    CHECK(i.at("excitation", x.size() - 1, "delta_e [rad]") == 0.0);
  }
  SUBCASE("elevons (SERVO1/2_FUNCTION 77/78, MIXING_GAIN 0.5)") {
    Options o;
    o.elevons = true;
    const Imported i = import_bytes("elevons", synthetic_log(o), deflections());
    CHECK(i.at("actuators", 1, "delta_a [rad]") == doctest::Approx(0.2 * 0.35));
    CHECK(i.at("actuators", 1, "delta_e [rad]") == doctest::Approx(-0.1 * 0.30));
  }
  SUBCASE("a V-tail (SERVO1/2_FUNCTION 79/80, MIXING_GAIN 0.5), no aileron") {
    Options o;
    o.vtail = true;
    const Imported i = import_bytes("vtail", synthetic_log(o), deflections());
    CHECK(i.at("actuators", 1, "delta_a [rad]") == 0.0);
    CHECK(i.at("actuators", 1, "delta_e [rad]") == doctest::Approx(-0.1 * 0.30));
    CHECK(i.at("actuators", 1, "delta_r [rad]") == doctest::Approx(-0.2 * 0.40));  // yaw right
  }
  SUBCASE("a rate-axis manoeuvre (SIDS Ax 8) is no surface command: no excitation, one line") {
    Options o;
    o.sid_axis = 8;
    const Imported i = import_bytes("rate_axis", synthetic_log(o), deflections());
    CHECK(!fs::exists(i.dir / "topics" / "excitation.csv"));
    CHECK(has_warning(i.report, "SIDD holds a system-identification manoeuvre on SIDS axis 8"));
  }
  SUBCASE("without --max-deflection: the sensors only, one line saying why") {
    const Imported i = import_bytes("no_deflection", synthetic_log());
    CHECK(i.report.rows.count("actuators") == 0);
    CHECK(i.report.rows.count("excitation") == 0);
    CHECK(has_warning(i.report, "no actuators.csv written without --max-deflection A E R"));
  }
}

TEST_CASE("tern import dataflash: the conversions, on hand-checked values") {
  using namespace tern::core::dataflash_import;
  CHECK(ardupilot_fix_type(1) == tern::msg::FixType::none);
  CHECK(ardupilot_fix_type(2) == tern::msg::FixType::fix_2d);
  CHECK(ardupilot_fix_type(6) == tern::msg::FixType::fix_3d);
  CHECK(ardupilot_fix_type(7) == tern::msg::FixType::none);
  CHECK(iso_date_from_gps_week(0, 0) == "");
  CHECK(iso_date_from_gps_week(2300, 19000) == "2024-02-04");  // GPS week 2300 began 2024-02-04 00:00:00 GPS time
  CHECK(iso_date_from_gps_week(2300, 17000) == "2024-02-03");  // 18 leap seconds earlier in UTC: still Saturday
  const ServoRange s{1000, 1400, 2000, false};
  CHECK(angle_from_pwm(2000, s) == 1.0);
  CHECK(angle_from_pwm(1000, s) == -1.0);
  CHECK(angle_from_pwm(1700, s) == doctest::Approx(0.5));
  CHECK(angle_from_pwm(1700, {1000, 1400, 2000, true}) == doctest::Approx(-0.5));
  CHECK(range_from_pwm(1500, {1000, 1500, 2000, false}) == doctest::Approx(0.5));
  CHECK(range_from_pwm(1250, {1000, 1500, 2000, true}) == doctest::Approx(0.75));
  CHECK(range_from_pwm(900, {1000, 1500, 2000, false}) == 0.0);
  const Unmixed u = unmix((0.1 - 0.2) * 0.5, (0.1 + 0.2) * 0.5, 0.5);  // ArduPlane's mixer forward, then back
  CHECK(u.in1 == doctest::Approx(0.2));
  CHECK(u.in2 == doctest::Approx(0.1));
}

TEST_CASE("tern import dataflash: hostile files: one line naming the file, the message and the field, or a counted warning") {
  const std::string good = synthetic_log();
  SUBCASE("garbage between messages: skipped to the next 0xA3 0x95, every message kept") {
    Options o;
    o.garbage = true;
    const Imported i = import_bytes("garbage", synthetic_log(o));
    CHECK(i.report.rows.at("imu") == 1600);
    CHECK(i.report.rows.at("gnss") == 20);
    CHECK(has_warning(i.report, "byte(s) in 17 place(s) that are no message"));
  }
  SUBCASE("a header of a type no FMT defines: skipped, counted") {
    Options o;
    o.unknown = true;
    const Imported i = import_bytes("unknown", synthetic_log(o));
    CHECK(i.report.rows.at("imu") == 1600);
    CHECK(has_warning(i.report, "1 message header(s) of a type no FMT defines"));
  }
  SUBCASE("cut short inside a message: the rest imported, one warning") {
    const Imported i = import_bytes("cut", good.substr(0, good.size() / 2 + 7));
    CHECK(i.report.rows.at("imu") > 700);
    CHECK(has_warning(i.report, "the last message is cut short"));
  }
  SUBCASE("a FMT whose length is not its format's") {
    DataflashBytes d;
    d.fmt(IMU, "IMU", "QBffffff", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ", 50);
    CHECK(import_error("fmt_length", d.bytes()) ==
          "byte 89: FMT of type 130 'IMU': field 'length': 50 bytes, but format 'QBffffff' makes 36 (3 + 33)");
  }
  SUBCASE("a FMT with an unknown format character, or labels not one per field") {
    DataflashBytes d;
    d.fmt(IMU, "IMU", "QBx", "TimeUS,I,X", 12);
    CHECK(import_error("fmt_char", d.bytes()) == "byte 89: FMT of type 130 'IMU': field 'format': unknown format character 'x' in 'QBx'");
    DataflashBytes e;
    e.fmt(IMU, "IMU", "QB", "TimeUS");
    CHECK(import_error("fmt_labels", e.bytes()) ==
          "byte 89: FMT of type 130 'IMU': field 'labels': 1 labels for the 2 fields of format 'QB'");
  }
  SUBCASE("an IMU without GyrX, and a TimeUS beyond any clock") {
    DataflashBytes d;
    d.fmt(IMU, "IMU", "QBf", "TimeUS,I,GyrY");
    d.msg(IMU, {1e6, 0.0, 0.0});
    CHECK(import_error("no_gyr", d.bytes()) == "message 'IMU' (type 130) has no field 'GyrX'");
    DataflashBytes e;
    e.fmt(IMU, "IMU", "QBffffff", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ");
    e.msg(IMU, {1e6, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -9.8});
    e.msg(IMU, {1.8e19, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -9.8});
    CHECK(import_error("far_future", e.bytes()) ==
          "byte 214: message 'IMU': field 'TimeUS': 18000000000000000000 us is beyond any clock's range after the log's first TimeUS "
          "(1000000 us): a corrupt file?");
  }
  SUBCASE("an empty file, one without a message, one without IMU") {
    CHECK(import_error("empty", "") ==
          "byte 0: no DataFlash message (a 0xA3 0x95 header and a FMT) in its 0 bytes: not an ArduPilot .bin log");
    CHECK(import_error("text", std::string(1000, 'x')) ==
          "byte 0: no DataFlash message (a 0xA3 0x95 header and a FMT) in its 1000 bytes: not an ArduPilot .bin log");
    DataflashBytes d;
    CHECK(import_error("no_imu", d.bytes()) == "no IMU messages (GyrX, AccX, ... of instance 0): a sensor log needs an imu topic");
  }
}

TEST_CASE("tern import dataflash: 60 copies of the synthetic log with 1-40 random bytes changed: each imports or gives one line") {
  const std::string good = synthetic_log();
  const char* more = std::getenv("TERN_DATAFLASH_MUTANTS");  // more copies by hand: TERN_DATAFLASH_MUTANTS=3000
  const int copies = more ? std::max(1, std::atoi(more)) : 60;
  std::uint64_t state = 0x9E3779B97F4A7C15ull;  // a fixed xorshift sequence: the same copies every run
  auto next = [&] {
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return state;
  };
  int imported = 0, refused = 0;
  for (int copy = 0; copy < copies; ++copy) {
    std::string bad = good;
    const int changes = 1 + static_cast<int>(next() % 40);
    for (int k = 0; k < changes; ++k) bad[next() % bad.size()] = static_cast<char>(next() & 0xff);
    const std::string name = "mutant" + std::to_string(copy);
    try {
      (void)import_bytes(name, bad, deflections());
      ++imported;
    } catch (const tern::core::ImportError& e) {
      CHECK(std::string(e.what()).find('\n') == std::string::npos);
      ++refused;
    }
    fs::remove_all(fs::temp_directory_path() / ("tern_test_dataflash_out_" + std::to_string(::getpid()) + "_" + name));
  }
  CHECK(imported + refused == copies);
  MESSAGE(imported << " imported, " << refused << " refused");
}

TEST_CASE("tern import dataflash FILE DIR on the command line: rows printed; /dev/zero and a bad FMT one line, exit 1, nothing left") {
  const fs::path tmp = fs::temp_directory_path() / ("tern_test_dataflash_cli_" + std::to_string(::getpid()));
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  std::ofstream(tmp / "LOG.bin", std::ios::binary) << synthetic_log();
  REQUIRE(run_tern({"import", "dataflash", (tmp / "LOG.bin").string(), (tmp / "log").string(), "--max-deflection", "0.35", "0.3", "0.4"},
                   tmp / "import.txt") == 0);
  std::ifstream printed(tmp / "import.txt");
  const std::string text((std::istreambuf_iterator<char>(printed)), std::istreambuf_iterator<char>());
  CHECK(text.find("excitation") != std::string::npos);
  CHECK(text.find("      200 rows") != std::string::npos);  // actuators
  CHECK(fs::exists(tmp / "log" / "sensor_log.yaml"));

  CHECK(run_tern({"import", "dataflash", "/dev/zero", (tmp / "zero").string()}, tmp / "zero.txt") == 1);
  std::ifstream z(tmp / "zero.txt");
  std::string line, rest;
  std::getline(z, line);
  CHECK(line.rfind("tern: error: import: /dev/zero", 0) == 0);
  CHECK(!std::getline(z, rest));
  CHECK(!fs::exists(tmp / "zero"));

  DataflashBytes d;
  d.fmt(IMU, "IMU", "QBffffff", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ", 50);
  std::ofstream(tmp / "BAD.bin", std::ios::binary) << d.bytes();
  CHECK(run_tern({"import", "dataflash", (tmp / "BAD.bin").string(), (tmp / "bad").string()}, tmp / "bad.txt") == 1);
  std::ifstream b(tmp / "bad.txt");
  std::getline(b, line);
  CHECK(line == "tern: error: import: " + (tmp / "BAD.bin").string() +
                    ": byte 89: FMT of type 130 'IMU': field 'length': 50 bytes, but format 'QBffffff' makes 36 (3 + 33)");
  CHECK(!std::getline(b, rest));
  CHECK(!fs::exists(tmp / "bad"));
  fs::remove_all(tmp);
}

TEST_CASE("tern import dataflash FILE DIR, then tern replay DIR: every imported sensor row reaches the estimator") {
  const fs::path tmp = fs::temp_directory_path() / ("tern_test_dataflash_replay_" + std::to_string(::getpid()));
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  std::ofstream(tmp / "LOG.bin", std::ios::binary) << synthetic_log();
  REQUIRE(run_tern({"import", "dataflash", (tmp / "LOG.bin").string(), (tmp / "log").string()}, tmp / "import.txt") == 0);
  REQUIRE(run_tern({"replay", (tmp / "log").string(), "--log-dir", (tmp / "runs").string(), "-q"}, tmp / "replay.txt") == 0);
  std::vector<fs::path> runs;
  for (const auto& e : fs::directory_iterator(tmp / "runs")) runs.push_back(e.path());
  REQUIRE(runs.size() == 1);
  std::ifstream in(runs[0] / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  const auto& ekf = summary.at("instances").at("ekf");
  CHECK(ekf.at("gnss_received").get<double>() == 20);
  CHECK(ekf.at("baro_received").get<double>() == 40);
  CHECK(ekf.at("mag_received").get<double>() == 40);
  CHECK(ekf.at("diff_pressure_received").get<double>() == 40);
  CHECK(ekf.at("imu_received").get<double>() >= 1599);  // the last IMU row may end the replay
  CHECK(ekf.at("gnss_invalid").get<double>() == 0);
  CHECK(ekf.at("baro_invalid").get<double>() == 0);
  CHECK(ekf.at("mag_invalid").get<double>() == 0);
  fs::remove_all(tmp);
}
