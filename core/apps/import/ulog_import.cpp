// core/apps/import/ulog_import.cpp: `tern import ulog`: the unit and frame conversions, the choice of
// each output's source topic, sensor_log.yaml's settings and notes (the mapping: ulog_import.hpp; the
// handlers: ulog_conversion.cpp; the reader: ulog_reader.hpp).
#include "import/ulog_import.hpp"

#include <cmath>
#include <ctime>
#include <map>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "import/importers.hpp"
#include "import/ulog_conversion.hpp"
#include "tern/input_file.hpp"
#include "tern/math.hpp"

namespace tern::core {

namespace ulog_import {

msg::FixType px4_fix_type(int px4) {
  if (px4 == 2) return msg::FixType::fix_2d;
  if (px4 >= 3 && px4 <= 6) return msg::FixType::fix_3d;
  if (px4 == 7 || px4 == 8) return msg::FixType::dead_reckoning;
  return msg::FixType::none;
}

Euler euler_from_px4_quaternion(double w, double x, double y, double z) {
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  w /= n, x /= n, y /= n, z /= n;
  const double phi = std::atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y));
  const double theta = std::asin(std::clamp(2.0 * (w * y - z * x), -1.0, 1.0));
  const double psi = std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
  return {phi, theta, psi};
}

LatLon px4_reproject(double ref_lat_deg, double ref_lon_deg, double north_m, double east_m) {
  constexpr double kRadius = 6371000.0;  // PX4's CONSTANTS_RADIUS_OF_EARTH
  const double x = north_m / kRadius, y = east_m / kRadius, c = std::hypot(x, y);
  if (c == 0.0) return {ref_lat_deg, ref_lon_deg};
  const double lat0 = ref_lat_deg * kRadPerDeg, sin_c = std::sin(c), cos_c = std::cos(c);
  const double lat = std::asin(cos_c * std::sin(lat0) + x * sin_c * std::cos(lat0) / c);
  const double lon = ref_lon_deg * kRadPerDeg + std::atan2(y * sin_c, c * std::cos(lat0) * cos_c - x * std::sin(lat0) * sin_c);
  return {lat / kRadPerDeg, lon / kRadPerDeg};
}

std::string iso_date_from_utc_usec(std::uint64_t utc_usec) {
  const std::time_t secs = static_cast<std::time_t>(utc_usec / 1000000);
  std::tm tm{};
  // a date an ISO YYYY-MM-DD holds, or none (a corrupt time_utc_usec reaches years past 9999)
  if (gmtime_r(&secs, &tm) == nullptr || tm.tm_year + 1900 > 9999) return "";
  return fmt::format("{:04d}-{:02d}-{:02d}", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday);
}

}  // namespace ulog_import

namespace {

namespace fs = std::filesystem;
using namespace ulog_import;
using ulog::DataMessage;
using ulog::Subscription;

/// An output's candidate source topics, best first, with the fields it needs.
struct Candidate {
  const char* topic;
  std::initializer_list<const char*> fields;
  std::uint64_t Survey::*samples = nullptr;  ///< a count of valid samples the survey must have found, if any
};

std::optional<std::string> choose(const Survey& s, const std::map<std::string, ulog::Format>& formats,
                                  std::initializer_list<Candidate> list) {
  for (const auto& c : list) {
    const auto it = s.rows.find(c.topic);
    if (it == s.rows.end() || it->second == 0 || !has_fields(formats, c.topic, c.fields)) continue;
    if (c.samples && s.*c.samples == 0) continue;
    return std::string(c.topic);
  }
  return std::nullopt;
}

/// Chooses each output's source, registers its handler, and notes the choice (or warns of its absence).
void choose_sources(const Survey& s, const ulog::Reader& r, Conversion& c, ImportReport& report, std::vector<std::string>& notes) {
  const auto& F = r.formats();
  const std::string file = r.path().string();
  auto pick = [&](const char* output, std::initializer_list<Candidate> list, const char* missing) -> std::optional<std::string> {
    auto src = choose(s, F, list);
    if (src)
      notes.push_back(fmt::format("{}: from {} ({} messages)", output, *src, s.rows.at(*src)));
    else
      report.warnings.push_back(fmt::format("{}: no {}: {}", file, output, missing));
    return src;
  };
  if (!pick("imu", {{"sensor_combined", {"gyro_rad[0]", "accelerometer_m_s2[0]"}}}, "the sensor log's imu topic is required"))
    throw ImportError(file + ": no sensor_combined data (gyro_rad, accelerometer_m_s2): a sensor log needs an imu topic");
  c.add_imu();
  if (auto src = pick("mag",
                      {{"vehicle_magnetometer", {"magnetometer_ga[0]"}},
                       {"sensor_combined", {"magnetometer_ga[0]", "magnetometer_timestamp_relative"}, &Survey::combined_mag},
                       {"sensor_mag", {"x", "y", "z"}}},
                      "vehicle_magnetometer, sensor_combined.magnetometer_ga or sensor_mag with data")) {
    c.add_mag(*src);
    if (*src == "sensor_mag")
      report.warnings.push_back(
          file + ": mag from raw sensor_mag instance 0: PX4's calibration (CAL_MAG*) is not applied, nor is the board rotation guaranteed");
  }
  if (auto src = pick("baro",
                      {{"vehicle_air_data", {"baro_alt_meter"}},
                       {"sensor_combined", {"baro_alt_meter", "baro_timestamp_relative"}, &Survey::combined_baro},
                       {"sensor_baro", {"pressure"}}},
                      "vehicle_air_data, sensor_combined.baro_alt_meter or sensor_baro with data"))
    c.add_baro(*src);
  if (auto src = pick("diff_pressure", {{"differential_pressure", {}}, {"airspeed", {"indicated_airspeed_m_s"}}},
                      "differential_pressure or airspeed with data")) {
    c.add_diff_pressure(*src);
    if (*src == "airspeed") notes.push_back("diff_pressure: airspeed.indicated_airspeed_m_s taken as EAS, 0.5 * 1.225 * EAS^2");
  }
  if (auto src = pick("gnss", {{"vehicle_gps_position", {"fix_type", "vel_n_m_s"}}, {"sensor_gps", {"fix_type", "vel_n_m_s"}}},
                      "vehicle_gps_position or sensor_gps with data (without GNSS the estimator never initialises)")) {
    c.add_gnss(*src);
    notes.push_back(
        "gnss: lat/lon/alt as logged (int32 1e-7 deg and mm, or doubles); h_acc/v_acc from eph/epv; s_acc from s_variance_m_s "
        "(the receiver's speed accuracy in m/s, 1 sigma, despite its name); fix_type 0-1 none, 2 2-D, 3-6 3-D, 7-8 dead reckoning");
  }
  if (auto src = pick("reference attitude", {{"vehicle_attitude", {"q[0]"}}, {"control_state", {"q[0]"}}},
                      "vehicle_attitude or control_state with data"))
    c.add_attitude(*src);
  if (auto src =
          pick("reference position",
               {{"vehicle_global_position", {"lat", "lon", "alt"}}, {"vehicle_local_position", {"ref_lat", "xy_global", "z_global"}}},
               "vehicle_global_position or vehicle_local_position with data"))
    c.add_position(*src);
  if (auto src = pick("reference velocity",
                      {{"vehicle_local_position", {"vx", "vy", "vz"}}, {"vehicle_global_position", {"vel_n", "vel_e", "vel_d"}}},
                      "vehicle_local_position or vehicle_global_position with data"))
    c.add_velocity(*src);
  if (auto src = pick("reference wind", {{"wind", {"windspeed_north"}}, {"wind_estimate", {"windspeed_north"}}},
                      "wind or wind_estimate with data"))
    c.add_wind(*src);
}

/// MAVLink's MAV_TYPE (common.xml): 1 fixed wing; 19-25 the VTOLs (tailsitters, tiltrotor, fixed
/// rotor, tiltwing), whose fixed-wing controller publishes actuator_controls_1.
bool is_vtol(int mav_type) { return mav_type >= 19 && mav_type <= 25; }

bool holds_data(const Survey& s, const ulog::Reader& r, const std::string& topic) {
  const auto it = s.rows.find(topic);
  return r.formats().count(topic) && it != s.rows.end() && it->second > 0;
}

std::string no_deflection_line(const std::string& file, const std::string& topic) {
  return fmt::format(
      "{}: {} holds the surfaces' commands, normalised: no actuators.csv written without --max-deflection A E R (rad: the "
      "full aileron, elevator and rudder deflections, the aircraft file's servos.max_delta_a/e/r; a ULog does not hold them)",
      file, topic);
}

/// PX4 v1.13+ (control allocation): actuator_servos through the surfaces' torque effectiveness
/// (CA_SV_CS<i>_TRQ_R/P/Y), throttle from actuator_motors' forward motors.
void choose_servo_actuators(const Survey& s, const ulog::Reader& r, Conversion& c, const CommandMapping& mapping, ImportReport& report,
                            std::vector<std::string>& notes) {
  const std::string file = r.path().string();
  const int count = c.integer_param("CA_SV_CS_COUNT").value_or(0);
  std::array<std::vector<double>, 3> e;
  std::string surfaces;
  const ulog::Subscription servos("actuator_servos", 0, 0, r.formats());
  for (int i = 0; i < count; ++i) {
    if (!servos.field(fmt::format("control[{}]", i))) {
      report.warnings.push_back(
          fmt::format("{}: topic actuator_servos has no field control[{}] (CA_SV_CS_COUNT {}): no actuators.csv "
                      "written; the sensors are imported",
                      file, i, count));
      return;
    }
    const char* axis[] = {"R", "P", "Y"};
    for (int a = 0; a < 3; ++a) e[a].push_back(c.param(fmt::format("CA_SV_CS{}_TRQ_{}", i, axis[a])).value_or(0.0));
    surfaces += fmt::format("{}servo {} (CA_SV_CS{}_TYPE {}) roll {} pitch {} yaw {}", surfaces.empty() ? "" : "; ", i, i,
                            c.param(fmt::format("CA_SV_CS{}_TYPE", i)).value_or(0.0), e[0].back(), e[1].back(), e[2].back());
  }
  if (count <= 0 || surfaces.empty()) {
    report.warnings.push_back(
        fmt::format("{}: actuator_servos holds data but the log has no CA_SV_CS_COUNT (the control surfaces' "
                    "configuration): no actuators.csv written",
                    file));
    return;
  }
  if (!mapping.max_deflection) return void(report.warnings.push_back(no_deflection_line(file, "actuator_servos")));
  // throttle: a fixed wing's (CA_AIRFRAME 1) motors all push forward; a VTOL's forward motors are
  // those whose thrust axis CA_ROTOR<i>_AX_X points forward
  std::vector<int> motors;
  const int rotors = c.integer_param("CA_ROTOR_COUNT").value_or(0);
  const bool fixed_wing = c.param("CA_AIRFRAME").value_or(-1.0) == 1.0;
  if (holds_data(s, r, "actuator_motors")) {
    const ulog::Subscription m("actuator_motors", 0, 0, r.formats());
    // the motors actuator_motors has (control[] is one array: past its end no rotor has a field;
    // CA_ROTOR_COUNT 2^31 - 1 would otherwise loop for minutes, fuzz_ulog_conversion)
    for (int i = 0; i < rotors && m.field(fmt::format("control[{}]", i)); ++i)
      if (fixed_wing || c.param(fmt::format("CA_ROTOR{}_AX_X", i)).value_or(0.0) > 0.5) motors.push_back(i);
  }
  c.add_servo_actuators(e, motors, mapping);
  notes.push_back(
      "actuators: from actuator_servos (positions -1..1) through the torque effectiveness CA_SV_CS<i>_TRQ_R/P/Y, per axis "
      "sum E_i s_i / sum |E_i|: " +
      surfaces);
  std::string m;
  for (int i : motors) m += fmt::format("{}{}", m.empty() ? "" : ", ", i);
  notes.push_back(motors.empty() ? std::string("actuators: no forward motor in actuator_motors (CA_AIRFRAME, CA_ROTOR<i>_AX_X): delta_t 0")
                                 : "actuators: delta_t the mean of actuator_motors' forward motors " + m + ", the latest in force");
  notes.push_back(describe(mapping));
}

/// The surfaces' commands: actuator_controls_1 (the fixed-wing group) on a VTOL, else
/// actuator_controls_0 (the attitude controller's group: a fixed wing's surfaces and throttle);
/// PX4 v1.13+ without them: actuator_servos and actuator_motors. One line where the log has none,
/// where the topic is malformed, or where the full deflections were not stated.
void choose_actuators(const Survey& s, const ulog::Reader& r, Conversion& c, const CommandMapping& mapping, ImportReport& report,
                      std::vector<std::string>& notes) {
  const std::string file = r.path().string();
  const int mav_type = c.integer_param("MAV_TYPE").value_or(0);
  const std::string source = is_vtol(mav_type) ? "actuator_controls_1" : "actuator_controls_0";
  if (!holds_data(s, r, source)) {
    if (holds_data(s, r, "actuator_servos")) return choose_servo_actuators(s, r, c, mapping, report, notes);
    report.warnings.push_back(
        fmt::format("{}: no surface commands in this log (neither {} nor actuator_servos holds data): no "
                    "actuators.csv written (tern sysid needs one)",
                    file, source));
    return;
  }
  if (!has_fields(r.formats(), source, {"control[0]", "control[1]", "control[2]", "control[3]"})) {
    report.warnings.push_back(
        fmt::format("{}: topic {} has no fields control[0..3] (roll, pitch, yaw, throttle): no actuators.csv "
                    "written; the sensors are imported",
                    file, source));
    return;
  }
  if (!mapping.max_deflection) return void(report.warnings.push_back(no_deflection_line(file, source)));
  c.add_actuators(source, mapping);
  notes.push_back(fmt::format(
      "actuators: from {} ({} messages): control[0..3] = roll, pitch, yaw (-1..1: roll right, nose up, nose "
      "right positive), throttle (0..1){}",
      source, s.rows.at(source), is_vtol(mav_type) ? "; a VTOL's fixed-wing group (MAV_TYPE " + std::to_string(mav_type) + ")" : ""));
  notes.push_back(describe(mapping));
  if (mav_type != 1 && !is_vtol(mav_type))
    report.warnings.push_back(
        fmt::format("{}: MAV_TYPE {} is no fixed wing: {}'s roll, pitch and yaw are the rotors' torque commands, "
                    "not surfaces; actuators.csv holds them as deflections nonetheless",
                    file, mav_type, source));
}

/// The PX4 parameters that map onto the estimator's settings (docs/sensor-log.md), where the log has them.
void estimator_settings(const Conversion& c, SensorLogMeta& meta) {
  auto delay = [&](const char* px4, const char* tern) {
    if (auto v = c.param(px4)) meta.estimator[tern] = *v * 1e-3;
  };
  delay("EKF2_GPS_DELAY", "gnss_delay");
  delay("EKF2_BARO_DELAY", "baro_delay");
  delay("EKF2_MAG_DELAY", "mag_delay");
  delay("EKF2_ASP_DELAY", "diff_pressure_delay");
  auto position = [&](const char* px4, const char* tern) {
    const auto x = c.param(fmt::format("{}_X", px4)), y = c.param(fmt::format("{}_Y", px4)), z = c.param(fmt::format("{}_Z", px4));
    if (x && y && z) meta.estimator[tern] = std::vector<double>{*x, *y, *z};
  };
  position("EKF2_GPS_POS", "gnss_antenna_position");
  position("EKF2_IMU_POS", "imu_position");
  meta.estimator["imu_mount"] = std::vector<double>{0.0, 0.0, 0.0};  // sensor_combined is already in the body frame
  auto& n = meta.notes;
  n.push_back(
      "estimator: gnss/baro/mag/diff_pressure delays from EKF2_GPS/BARO/MAG/ASP_DELAY (ms -> s), measured from each "
      "sample's timestamp_sample as PX4's EKF2 does; gnss_antenna_position from EKF2_GPS_POS_X/Y/Z, imu_position from EKF2_IMU_POS_X/Y/Z");
  std::string applied;
  for (const char* p :
       {"SENS_BOARD_ROT", "SENS_BOARD_X_OFF", "SENS_BOARD_Y_OFF", "SENS_BOARD_Z_OFF", "CAL_MAG0_XOFF", "CAL_MAG0_YOFF", "CAL_MAG0_ZOFF"})
    if (auto v = c.param(p)) applied += fmt::format(" {}={}", p, *v);
  n.push_back("imu_mount 0: PX4 applied the board rotation and calibration before sensor_combined/vehicle_magnetometer:" + applied);
  for (const char* p : {"EKF2_MAG_DECL", "EKF2_MAG_TYPE", "SENS_BARO_QNH"})
    if (auto v = c.param(p)) n.push_back(fmt::format("PX4 parameter {} = {} (not mapped)", p, *v));
}

std::string info_text(const ulog::Reader& r, const char* key) {
  const auto it = r.info().find(key);
  return it == r.info().end() ? std::string("?") : it->second.text();
}

ImportReport convert(const fs::path& ulg, SensorLogWriter& out, const CommandMapping& mapping) {
  const std::string file = ulg.string();
  const Survey s = survey(ulg);
  ulog::Reader r(ulg);
  ImportReport report;
  SensorLogMeta meta;
  Conversion c(r, out, report);
  choose_sources(s, r, c, report, meta.notes);
  choose_actuators(s, r, c, mapping, report, meta.notes);
  std::uint64_t dropouts = 0, dropout_ms = 0;
  ulog::DataHandler h;
  h.on_subscription = [&](const Subscription& sub) { c.subscribe(sub); };
  h.on_data = [&](const DataMessage& d) { c.data(d); };
  h.on_dropout = [&](std::uint16_t ms, std::uint64_t) { ++dropouts, dropout_ms += ms; };
  const ulog::UlogDataStats stats = r.read_data(h);
  c.finish(file, meta.notes);
  for (auto& w : stats.warnings(file)) report.warnings.push_back(std::move(w));
  if (dropouts)
    report.warnings.push_back(
        fmt::format("{}: {} logging dropout(s), {} ms in all: data lost by PX4's logger", file, dropouts, dropout_ms));
  if (c.imu_intervals.count()) meta.notes.push_back("imu: " + c.imu_intervals.describe());
  if (c.gnss_intervals.count()) meta.notes.push_back("gnss: " + c.gnss_intervals.describe());
  if (c.actuator_intervals.count()) {
    meta.notes.push_back("actuators: " + c.actuator_intervals.describe());
    if (c.actuator_intervals.count() > 1)
      if (auto w = actuator_rate_warning(file, 1.0 / c.actuator_intervals.mean_s()); !w.empty()) report.warnings.push_back(w);
  }
  meta.notes.push_back("times: PX4 timestamps (us since boot) minus the log's start timestamp " + std::to_string(r.start_timestamp()) +
                       " us");
  estimator_settings(c, meta);
  meta.source = fmt::format("PX4 ULog {} ({} {} on {}), by tern import ulog", ulg.filename().string(), info_text(r, "sys_name"),
                            info_text(r, "ver_sw"), info_text(r, "ver_hw"));
  meta.aircraft = fmt::format("PX4 MAV_TYPE {}, SYS_AUTOSTART {}", c.param("MAV_TYPE") ? fmt::format("{}", *c.param("MAV_TYPE")) : "?",
                              c.param("SYS_AUTOSTART") ? fmt::format("{}", *c.param("SYS_AUTOSTART")) : "?");
  meta.date = c.date;
  if (meta.date.empty())
    report.warnings.push_back(file + ": no GNSS fix with a UTC time: the flight's date is unknown (the magnetic model's date is not set)");
  out.finish(meta, report.warnings);
  report.rows = out.rows();
  return report;
}

}  // namespace

ImportReport import_ulog(const fs::path& in, SensorLogWriter& out, const CommandMapping& commands) {
  std::error_code ec;
  fs::path ulg = in;
  if (fs::is_directory(in, ec)) {  // an unpacked archive: the one .ulg in it
    ulg = file_ending_with(in, ".ulg");
    if (ulg.empty()) throw ImportError(in.string() + ": no .ulg file in this directory");
  }
  try {
    return convert(ulg, out, commands);
  } catch (const ulog::UlogError& e) {
    throw ImportError(e.what());
  } catch (const std::out_of_range& e) {  // names from the file (a topic, a field, a type): one line
    throw ImportError(ulg.string() + ": " + printable(e.what(), ulog::kMaxErrorChars));
  }
}

}  // namespace tern::core
