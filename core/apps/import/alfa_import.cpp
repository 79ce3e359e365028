// `tern import alfa`: the ALFA dataset's mavros CSVs (CMU AirLab's AirLab Failure and Anomaly
// dataset, castacks/alfa-dataset-tools: `rostopic echo -p` tables, one
// "<bag>-mavros-<topic>.csv" per topic) into a sensor log.
//
// mavros publishes ROS frames (REP-103): body FLU (x forward, y left, z up) and world ENU. The
// sensor log is body FRD and NED:
//   body FLU -> FRD:  (x, y, z) -> (x, -y, -z)
//   ENU -> NED:       (e, n, u) -> (n, e, -u)
//   attitude:         R_ned_frd = P R_enu_flu F, P = [[0,1,0],[1,0,0],[0,0,-1]], F = diag(1,-1,-1)
// Units as mavros writes them (mavros imu plugin, ArduPilot's RAW_IMU): gyro rad/s, accel m/s^2,
// magnetic field the autopilot's mGauss multiplied by 1000 (mavros' constant "MILLIT_TO_TESLA =
// 1000.0"), so T = value * 1e-3 * 1e-7; static pressure Pa. Time: the ROS header stamps (ns
// since 1970), made relative to the earliest first stamp of the tables read.
// Surfaces: rc/out (mavros_msgs/RCOut: the autopilot's SERVO_OUTPUT_RAW, one pulse width in us per
// channel, columns field.channels0..) where the dataset has it: ArduPlane's default channel map
// (RCMAP_ROLL 1, RCMAP_PITCH 2, RCMAP_THROTTLE 3, RCMAP_YAW 4: ArduPilot's
// libraries/AP_RCMapper/AP_RCMapper.cpp; --rc-channels), surfaces about 1500 us +-500 us, throttle
// 1000..2000 us (surface_commands.hpp). ArduPlane's scaled servo outputs are positive for roll
// right, nose up (ArduPlane's stabilize_pitch: the elevator from demanded minus measured pitch)
// and yaw right, and an unreversed channel's pulse grows with them (SRV_Channel's pwm_from_angle).
#include <cmath>
#include <ctime>
#include <limits>
#include <optional>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "import/import_support.hpp"
#include "import/importers.hpp"
#include "import/text_table.hpp"
#include "tern/msg/estimator.hpp"
#include "tern/msg/sensors.hpp"

namespace tern::core {

namespace fs = std::filesystem;

namespace {

constexpr double kMavrosMagToTesla = 1e-3 * 1e-7;  // value / 1000 = mGauss; 1 mGauss = 1e-7 T
constexpr double kImuLowRateHz = 50.0;             // below this the IMU warning is given

/// Body FLU -> FRD.
Eigen::Vector3d flu_to_frd(const Eigen::Vector3d& v) { return {v.x(), 0.0 - v.y(), 0.0 - v.z()}; }  // 0 - 0 = +0, not -0
/// World ENU -> NED.
Eigen::Vector3d enu_to_ned(const Eigen::Vector3d& v) { return {v.y(), v.x(), 0.0 - v.z()}; }
/// Attitude of body FLU in ENU -> attitude of body FRD in NED.
Eigen::Matrix3d ned_frd_from_enu_flu(const Eigen::Matrix3d& r_enu_flu) {
  Eigen::Matrix3d p;
  p << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  return p * r_enu_flu * Eigen::Vector3d(1, -1, -1).asDiagonal();
}

/// A mavros table: its file, the stamp column, and one row read ahead.
struct RosTable {
  RosTable(const fs::path& file) : t(file, TextTable::Separator::comma), stamp_col(t.column("field.header.stamp")) { more = t.next(); }
  Nanos stamp(Nanos t0) const { return t.integer(stamp_col) - t0; }
  double num(const std::string& field) const { return t.number(t.column(field)); }
  Eigen::Vector3d vec(const std::string& prefix) const { return {num(prefix + ".x"), num(prefix + ".y"), num(prefix + ".z")}; }
  TextTable t;
  std::size_t stamp_col;
  bool more;
};

struct Inputs {
  fs::path imu, mag, baro, fix, gps_vel, airspeed, odom, global, engines, rc_out;
  bool airspeed_is_vfr_hud = false;
};

Inputs find_inputs(const fs::path& dir) {
  Inputs in;
  in.imu = file_ending_with(dir, "-mavros-imu-data_raw.csv");
  if (in.imu.empty()) in.imu = file_ending_with(dir, "-mavros-imu-data.csv");
  if (in.imu.empty()) throw ImportError(fmt::format("{}: no *-mavros-imu-data_raw.csv nor *-mavros-imu-data.csv", dir.string()));
  in.mag = file_ending_with(dir, "-mavros-imu-mag.csv");
  in.baro = file_ending_with(dir, "-mavros-imu-atm_pressure.csv");
  in.fix = file_ending_with(dir, "-mavros-global_position-raw-fix.csv");
  in.gps_vel = file_ending_with(dir, "-mavros-global_position-raw-gps_vel.csv");
  in.airspeed = file_ending_with(dir, "-mavros-nav_info-airspeed.csv");
  if (in.airspeed.empty()) {
    in.airspeed = file_ending_with(dir, "-mavros-vfr_hud.csv");
    in.airspeed_is_vfr_hud = !in.airspeed.empty();
  }
  in.odom = file_ending_with(dir, "-mavros-local_position-odom.csv");
  in.global = file_ending_with(dir, "-mavros-global_position-global.csv");
  in.engines = file_ending_with(dir, "-failure_status-engines.csv");
  in.rc_out = file_ending_with(dir, "-mavros-rc-out.csv");
  return in;
}

/// The earliest first header stamp of the tables (the log's time zero).
Nanos time_zero(const Inputs& in) {
  Nanos t0 = std::numeric_limits<Nanos>::max();
  for (const fs::path* f : {&in.imu, &in.mag, &in.baro, &in.fix, &in.airspeed, &in.odom, &in.global, &in.rc_out}) {
    if (f->empty()) continue;
    RosTable t(*f);
    if (t.more) t0 = std::min(t0, t.stamp(0));
  }
  if (t0 == std::numeric_limits<Nanos>::max()) throw ImportError(fmt::format("{}: no rows", in.imu.string()));
  return t0;
}

/// "2018-07-18" from a stamp in ns since 1970 (UTC); "" if the stamp is no calendar time.
std::string utc_date(Nanos stamp) {
  if (stamp < 1'000'000'000'000'000'000LL) return "";  // before 2001-09-09: not a Unix time stamp
  const std::time_t s = static_cast<std::time_t>(stamp / 1'000'000'000LL);
  std::tm tm{};
  gmtime_r(&s, &tm);
  char buf[16];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", &tm);
  return buf;
}

void import_imu(const fs::path& file, Nanos t0, SensorLogWriter& out, ImportReport& report, std::vector<std::string>& notes) {
  RosTable r(file);
  StampOrder order;
  IntervalStats dt;
  for (; r.more; r.more = r.t.next()) {
    msg::Imu m;
    m.stamp = r.stamp(t0);
    m.gyro = flu_to_frd(r.vec("field.angular_velocity"));
    m.accel = flu_to_frd(r.vec("field.linear_acceleration"));
    if (!order.accept(m.stamp)) continue;
    dt.add(m.stamp);
    out.write("imu", m);
  }
  order.report(file, report);
  notes.push_back(fmt::format("imu: {}: {}", file.filename().string(), dt.describe()));
  if (dt.count() > 1 && 1.0 / dt.mean_s() < kImuLowRateHz)
    report.warnings.push_back(
        fmt::format("{}: the IMU is logged at {:.1f} Hz (intervals up to {:.0f} ms): far below an estimator's rate; each "
                    "sample stands for its whole interval, expect a coarse attitude",
                    file.filename().string(), 1.0 / dt.mean_s(), dt.max_s() * 1e3));
}

void import_mag(const fs::path& file, Nanos t0, SensorLogWriter& out, ImportReport& report) {
  RosTable r(file);
  StampOrder order;
  for (; r.more; r.more = r.t.next()) {
    msg::Mag m;
    m.stamp = r.stamp(t0);
    m.field = flu_to_frd(r.vec("field.magnetic_field")) * kMavrosMagToTesla;
    if (order.accept(m.stamp)) out.write("mag", m);
  }
  order.report(file, report);
}

void import_baro(const fs::path& file, Nanos t0, SensorLogWriter& out, ImportReport& report) {
  RosTable r(file);
  StampOrder order;
  for (; r.more; r.more = r.t.next()) {
    msg::Baro b;
    b.stamp = r.stamp(t0);
    b.pressure = r.num("field.fluid_pressure");  // Pa
    if (order.accept(b.stamp)) out.write("baro", b);
  }
  order.report(file, report);
}

/// raw/fix and raw/gps_vel carry the same header stamps (one GPS_RAW_INT each): read in step.
void import_gnss(const Inputs& in, Nanos t0, SensorLogWriter& out, ImportReport& report) {
  RosTable fix(in.fix), vel(in.gps_vel);
  StampOrder order;
  for (; fix.more; fix.more = fix.t.next(), vel.more = vel.t.next()) {
    if (!vel.more) vel.t.fail(fmt::format("ends before {} (its line {})", in.fix.filename().string(), fix.t.line()));
    msg::Gnss g;
    g.stamp = fix.stamp(t0);
    if (vel.stamp(t0) != g.stamp)
      vel.t.fail(fmt::format("header stamp differs from {} line {}'s", in.fix.filename().string(), fix.t.line()));
    g.fix_type = fix.num("field.status.status") >= 0 ? msg::FixType::fix_3d : msg::FixType::none;
    g.lat = fix.num("field.latitude");
    g.lon = fix.num("field.longitude");
    g.alt = fix.num("field.altitude");
    // Only a covariance the receiver reported is an accuracy in metres: DIAGONAL_KNOWN (2) or
    // KNOWN (3). APPROXIMATED (1) is mavros' (DOP * gps_uere)^2 with gps_uere 1 by default
    // (mavros global_position.cpp, handle_gps_raw_int: MAVLink 1's GPS_RAW_INT has no h_acc,
    // its eph and epv are the HDOP and VDOP): its square roots are the HDOP and VDOP, not metres.
    // Then no accuracy is reported (0), the dilutions are.
    const double covariance_type = fix.num("field.position_covariance_type");
    const double var_h = fix.num("field.position_covariance0"), var_v = fix.num("field.position_covariance8");
    if (covariance_type >= 2) {
      g.h_acc = std::sqrt(var_h);
      g.v_acc = std::sqrt(var_v);
    } else if (covariance_type == 1 && var_h > 0.0 && var_v > 0.0) {
      g.hdop = std::sqrt(var_h);
      g.vdop = std::sqrt(var_v);
    }
    g.vel = enu_to_ned(vel.vec("field.twist.linear"));
    if (order.accept(g.stamp)) out.write("gnss", g);
  }
  order.report(in.fix, report);
  report.warnings.push_back(
      fmt::format("{}: no vertical velocity (GPS_RAW_INT has none; mavros writes z = 0): vel_d is 0 in every fix, and sensor_log.yaml "
                  "sets the estimator's use_gnss_vel_d false",
                  in.gps_vel.filename().string()));
  report.warnings.push_back(
      fmt::format("{}: altitude is mavros' height above the WGS-84 ellipsoid (about 33 m below mean sea level near "
                  "Pittsburgh), not above mean sea level",
                  in.fix.filename().string()));
}

void import_airspeed(const Inputs& in, Nanos t0, SensorLogWriter& out, ImportReport& report) {
  RosTable r(in.airspeed);
  StampOrder order;
  const std::string field = in.airspeed_is_vfr_hud ? "field.airspeed" : "field.measured";
  for (; r.more; r.more = r.t.next()) {
    msg::DiffPressure dp;
    dp.stamp = r.stamp(t0);
    dp.pressure = diff_pressure_from_eas(r.num(field));
    if (order.accept(dp.stamp)) out.write("diff_pressure", dp);
  }
  order.report(in.airspeed, report);
}

/// The autopilot's odometry (attitude and body velocity) and global position, merged by time
/// into the reference topic (each row holds one of them; the other's columns are nan).
void import_reference(const Inputs& in, Nanos t0, SensorLogWriter& out, ImportReport& report) {
  std::optional<RosTable> odom, global;
  if (!in.odom.empty()) odom.emplace(in.odom);
  if (!in.global.empty()) global.emplace(in.global);
  StampOrder order;
  constexpr Nanos kEnd = std::numeric_limits<Nanos>::max();
  for (;;) {
    const Nanos to = odom && odom->more ? odom->stamp(t0) : kEnd, tg = global && global->more ? global->stamp(t0) : kEnd;
    if (to == kEnd && tg == kEnd) break;
    msg::Reference r;
    if (to <= tg) {
      r.stamp = to;
      const Eigen::Quaterniond q(odom->num("field.pose.pose.orientation.w"), odom->num("field.pose.pose.orientation.x"),
                                 odom->num("field.pose.pose.orientation.y"), odom->num("field.pose.pose.orientation.z"));
      const Eigen::Matrix3d r_enu_flu = q.normalized().toRotationMatrix();
      const Eigen::Matrix3d m = ned_frd_from_enu_flu(r_enu_flu);
      r.phi = std::atan2(m(2, 1), m(2, 2));  // 3-2-1 Euler angles
      r.theta = -std::asin(std::clamp(m(2, 0), -1.0, 1.0));
      r.psi = std::atan2(m(1, 0), m(0, 0));
      const Eigen::Vector3d v = enu_to_ned(r_enu_flu * odom->vec("field.twist.twist.linear"));  // twist: body FLU
      r.v_n = v.x(), r.v_e = v.y(), r.v_d = v.z();
      odom->more = odom->t.next();
    } else {
      r.stamp = tg;
      r.lat = global->num("field.latitude");
      r.lon = global->num("field.longitude");
      r.alt = global->num("field.altitude");
      global->more = global->t.next();
    }
    if (order.accept(r.stamp)) out.write("reference", r);
  }
  order.report(in.odom.empty() ? in.global : in.odom, report);
}

/// rc/out's servo pulses as the surfaces' commands (ArduPilot's sense: roll right, pitch up, yaw
/// right for a longer pulse on an unreversed channel), through `mapping`.
void import_actuators(const fs::path& file, Nanos t0, const CommandMapping& mapping, SensorLogWriter& out, ImportReport& report,
                      std::vector<std::string>& notes) {
  RosTable r(file);
  std::array<std::size_t, 4> col{};  // aileron, elevator, throttle, rudder
  for (std::size_t i = 0; i < 4; ++i) {
    const int ch = mapping.rc_channels[i];
    col[i] = r.t.column(fmt::format("field.channels{}", std::abs(ch) - 1));
  }
  StampOrder order;
  IntervalStats dt;
  for (; r.more; r.more = r.t.next()) {
    auto pwm = [&](std::size_t i) { return r.t.number(col[i]); };
    NormalisedCommand u;
    u.roll = normalised_from_pwm(pwm(0), mapping.rc_channels[0] < 0);
    u.pitch = normalised_from_pwm(pwm(1), mapping.rc_channels[1] < 0);
    u.throttle = throttle_from_pwm(pwm(2));
    u.yaw = normalised_from_pwm(pwm(3), mapping.rc_channels[3] < 0);
    const msg::Actuators a = actuators_from_normalised(r.stamp(t0), u, mapping);
    if (!order.accept(a.stamp)) continue;
    dt.add(a.stamp);
    out.write("actuators", a);
  }
  order.report(file, report);
  const auto& ch = mapping.rc_channels;
  notes.push_back(
      fmt::format("actuators: {}: servo pulses of channels aileron {}, elevator {}, throttle {}, rudder {} (a negative "
                  "channel reversed; ArduPlane's default RCMAP 1 2 3 4); surfaces (pwm - 1500) / 500 us, throttle (pwm - "
                  "1000) / 1000 us (SERVOn_MIN/TRIM/MAX defaults; this dataset has no parameters)",
                  file.filename().string(), ch[0], ch[1], ch[2], ch[3]));
  notes.push_back(describe(mapping));
  notes.push_back(fmt::format("actuators: {}: {}", file.filename().string(), dt.describe()));
  if (dt.count() > 1)
    if (auto w = actuator_rate_warning(file.filename().string(), 1.0 / dt.mean_s()); !w.empty()) report.warnings.push_back(w);
}

/// The first time the engine-failure flag is set, s on the log's clock (the table has only the
/// bag's receive time, %time); nan if never.
double engine_failure_s(const fs::path& file, Nanos t0) {
  TextTable t(file, TextTable::Separator::comma);
  const std::size_t time = t.column("%time"), data = t.column("field.data");
  while (t.next())
    if (t.number(data) != 0) return static_cast<double>(t.integer(time) - t0) * 1e-9;
  return std::nan("");
}

}  // namespace

ImportReport import_alfa(const fs::path& in, SensorLogWriter& out, const CommandMapping& commands) {
  const fs::path dir = directory_holding(in, {"-mavros-imu-data_raw.csv", "-mavros-imu-data.csv"});
  const Inputs inputs = find_inputs(dir);
  const Nanos t0 = time_zero(inputs);
  ImportReport report;
  SensorLogMeta meta;
  meta.source = "ALFA dataset mavros CSVs (CMU AirLab, castacks/alfa-dataset-tools)";
  meta.aircraft = "ArduPlane fixed wing (ALFA: Carbon-Z T-28)";
  meta.date = utc_date(t0);
  auto& n = meta.notes;
  n.push_back(fmt::format("stamps: ROS header stamps minus {} ns (the earliest first stamp); date: that stamp's UTC date", t0));
  import_imu(inputs.imu, t0, out, report, n);
  if (!inputs.mag.empty()) import_mag(inputs.mag, t0, out, report);
  if (!inputs.baro.empty()) import_baro(inputs.baro, t0, out, report);
  if (!inputs.fix.empty() && !inputs.gps_vel.empty()) {
    import_gnss(inputs, t0, out, report);
    // fused as 0 the missing down velocity held every climb and descent back (baro NIS 1.9
    // with 33 of 1229 rejected, GNSS positions 77 % accepted; north-east only: 0.38, none, 84 %)
    meta.estimator["use_gnss_vel_d"] = false;
    // The fixes are stamped when ArduPilot had them (GPS_RAW_INT's time_usec through mavros'
    // synchronized_header), after the receiver's own latency, which the log does not give: the
    // field's default for a receiver of unknown latency applies (PX4 EKF2_GPS_DELAY, 110 ms).
    // Swept on this flight: 0 / 0.05 / 0.11 / 0.15 / 0.22 s gave horizontal position vs the fixes
    // 1.58 / 0.83 / 0.51 / 0.51 / 0.60 m RMS, GNSS positions 84 / 88 / 92 / 92 / 92 % accepted.
    meta.estimator["gnss_delay"] = 0.11;
    n.push_back("gnss: the receiver's latency is not in the log: gnss_delay 0.11 s, PX4 EKF2_GPS_DELAY's default");
    n.push_back("gnss: vel_d is not measured (0 written): estimator use_gnss_vel_d false (north and east velocity only)");
  } else if (!inputs.fix.empty() || !inputs.gps_vel.empty())
    report.warnings.push_back(fmt::format("{}: GNSS needs both raw/fix and raw/gps_vel: no gnss topic written", dir.string()));
  if (!inputs.airspeed.empty()) import_airspeed(inputs, t0, out, report);
  import_reference(inputs, t0, out, report);
  if (inputs.rc_out.empty())
    report.warnings.push_back(
        fmt::format("{}: no surface commands in this log (no *-mavros-rc-out.csv): no actuators.csv written (tern "
                    "sysid needs one)",
                    dir.string()));
  else if (!commands.max_deflection)
    report.warnings.push_back(
        fmt::format("{}: holds the servos' pulses: no actuators.csv written without --max-deflection A E R (rad: the "
                    "full aileron, elevator and rudder deflections, the aircraft file's servos.max_delta_a/e/r; the "
                    "log does not hold them)",
                    inputs.rc_out.filename().string()));
  else
    import_actuators(inputs.rc_out, t0, commands, out, report, n);
  n.push_back("frames: mavros body FLU -> FRD (y, z negated), ENU -> NED (x and y swapped, z negated), attitude R_ned_frd = P R_enu_flu F");
  n.push_back("mag: mavros' value / 1000 = the autopilot's mGauss (calibrated), * 1e-7 = T");
  n.push_back(fmt::format("diff_pressure: {} taken as EAS (ArduPilot's airspeed): 0.5 * 1.225 * EAS^2 Pa",
                          inputs.airspeed.empty() ? std::string("(none)") : inputs.airspeed.filename().string()));
  n.push_back(
      "gnss: NavSatFix status >= 0 taken as a 3-D fix; h_acc, v_acc from the position covariance's diagonal only where the receiver "
      "reported it (covariance type >= 2); type 1 is mavros' DOP^2 (gps_uere 1), not metres: no accuracy (0); no satellite count");
  n.push_back(
      "reference: local_position/odom (attitude; twist in body FLU rotated to NED) and global_position/global (ellipsoidal height)");
  n.push_back(
      "no other sensor delays known: the estimator's own delay settings apply; temperature columns not recorded (288.15 K written)");
  n.push_back("EAS2TAS not recorded: the estimator's rho setting applies (ISA density at the field's ~97.3 kPa: about 1.19 kg/m^3)");
  if (!inputs.engines.empty()) {
    const double t_fail = engine_failure_s(inputs.engines, t0);
    if (std::isfinite(t_fail)) n.push_back(fmt::format("engine failure flag set from t = {:.2f} s (failure_status/engines)", t_fail));
  }
  out.finish(meta, report.warnings);
  report.rows = out.rows();
  return report;
}

}  // namespace tern::core
