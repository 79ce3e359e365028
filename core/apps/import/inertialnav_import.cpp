// `tern import inertialnav`: Paul Riseborough's InertialNav text files into a sensor log.
//
// The columns are those InertialNav's own replay reads, in code/main_closed_loop_float.cpp
// (github.com/priseborough/InertialNav at 037c5c3a); every time column is in milliseconds:
//   IMU.txt          readIMUData():  time, time, gyro x y z (rad/s), accel x y z (m/s^2), body FRD
//   MAG.txt          readMagData():  time, time, field x y z (mGauss), offsets x y z (mGauss);
//                                    InertialNav fuses 0.001 * (field - offset) gauss
//   NTUN.txt         readAirData():  time, time, 5 unused, EAS (m/s) [7], baro height (m) [8], unused
//   GPS.txt          readGpsData():  time, status [1], time [2], week, sats, hdop (0 here), lat [6],
//                                    lon [7] (deg), height [8] (m), height [9], ground speed [10]
//                                    (m/s), course [11], velocity down [12] (m/s), unused
//   GPSraw.txt       readGpsData():  time, lat, lon, height, velocity N E D [4..6] (m/s); when the
//                                    file exists InertialNav fuses its NED velocity (main loop:
//                                    "if (pGpsRawINFile != nullptr) velNED = gpsRaw[4..6]")
//   ATT.txt          readAhrsData(): time, time, roll pitch yaw [2..4] (deg2rad applied), errors
//   GPOSonboard.txt  readOnboardData(): time, lat, lon (deg), height (m), velocity N E D (m/s)
//   timing.txt       readTimingData(): align, start, end (s), msecVelDelay, msecPosDelay,
//                                    msecHgtDelay, msecMagDelay, msecTasDelay (ms), EAS2TAS
// GPS.txt's course is in radians in the Zurich flight (InertialNav's reader applies deg2rad to
// it): checked against the track and against GPSraw.txt's velocity.
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "import/import_support.hpp"
#include "import/importers.hpp"
#include "import/text_table.hpp"
#include "tern/math.hpp"
#include "tern/msg/estimator.hpp"
#include "tern/msg/sensors.hpp"
#include "tern/atmosphere.hpp"

namespace tern::core {

namespace fs = std::filesystem;

namespace {

constexpr double kMilliGaussToTesla = 1e-7;  // 1 G = 1e-4 T

/// ms (InertialNav's time columns) -> ns.
Nanos from_ms(double ms) { return static_cast<Nanos>(std::llround(ms * 1e6)); }

struct Timing {
  double start_s = 0, end_s = 0;
  double vel_delay_ms = 0, pos_delay_ms = 0, hgt_delay_ms = 0, mag_delay_ms = 0, tas_delay_ms = 0, eas2tas = 1;
};

Timing read_timing(const fs::path& dir) {
  TextTable t(dir / "timing.txt", TextTable::Separator::whitespace);
  std::vector<double> v;
  while (v.size() < 9 && t.next(1))
    for (std::size_t i = 0; i < t.cells() && v.size() < 9; ++i) v.push_back(t.number(i));
  if (v.size() < 9) t.fail(fmt::format("expected 9 values (readTimingData), got {} (a truncated file?)", v.size()));
  if (!(v[8] > 0)) t.fail(fmt::format("EAS2TAS (the 9th value) must be positive, got {}", v[8]));
  return {v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8]};
}

void import_imu(const fs::path& dir, SensorLogWriter& out, ImportReport& report, std::vector<std::string>& notes) {
  TextTable t(dir / "IMU.txt", TextTable::Separator::whitespace);
  StampOrder order;
  IntervalStats dt;
  while (t.next(8)) {
    msg::Imu m;
    m.stamp = from_ms(t.number(0));
    m.gyro = {t.number(2), t.number(3), t.number(4)};   // rad/s, body FRD
    m.accel = {t.number(5), t.number(6), t.number(7)};  // m/s^2 specific force, body FRD (level: z = -g)
    if (!order.accept(m.stamp)) continue;
    dt.add(m.stamp);
    out.write("imu", m);
  }
  order.report(t.file(), report);
  if (dt.count() > 0) notes.push_back(fmt::format("IMU.txt: {}", dt.describe()));
}

void import_mag(const fs::path& dir, SensorLogWriter& out, ImportReport& report) {
  TextTable t(dir / "MAG.txt", TextTable::Separator::whitespace);
  StampOrder order;
  while (t.next(8)) {
    msg::Mag m;
    m.stamp = from_ms(t.number(0));
    // readMagData(): magData = 0.001 * (field - offset) gauss, i.e. the offset columns are removed
    for (int k = 0; k < 3; ++k) m.field[k] = (t.number(2 + k) - t.number(5 + k)) * kMilliGaussToTesla;
    if (order.accept(m.stamp)) out.write("mag", m);
  }
  order.report(t.file(), report);
}

void import_air_data(const fs::path& dir, SensorLogWriter& out, ImportReport& report) {
  TextTable t(dir / "NTUN.txt", TextTable::Separator::whitespace);
  StampOrder order;
  while (t.next(10)) {
    const Nanos stamp = from_ms(t.number(0));
    if (!order.accept(stamp)) continue;
    msg::DiffPressure dp;
    dp.stamp = stamp;
    dp.pressure = diff_pressure_from_eas(t.number(7));
    out.write("diff_pressure", dp);
    msg::Baro b;
    b.stamp = stamp;
    b.pressure = isa_pressure_from_height(t.number(8));
    out.write("baro", b);
  }
  order.report(t.file(), report);
}

msg::FixType fix_type(const TextTable& t, double status) {
  if (status != std::floor(status) || status < 0 || status > 3)
    t.fail(fmt::format("column 2 (GPS status): {} is not a fix type 0..3", status));
  return static_cast<msg::FixType>(static_cast<int>(status));
}

/// GPS.txt, with GPSraw.txt's NED velocity when that file is present (as InertialNav fuses it).
void import_gnss(const fs::path& dir, SensorLogWriter& out, ImportReport& report, std::vector<std::string>& notes,
                 AirborneWindow& airborne) {
  TextTable t(dir / "GPS.txt", TextTable::Separator::whitespace);
  std::optional<TextTable> raw;
  if (fs::exists(dir / "GPSraw.txt")) raw.emplace(dir / "GPSraw.txt", TextTable::Separator::whitespace);
  StampOrder order;
  std::uint64_t disagree = 0, compared = 0;
  while (t.next(14)) {
    msg::Gnss g;
    g.stamp = from_ms(t.number(0));
    g.fix_type = fix_type(t, t.number(1));
    g.lat = t.number(6);
    g.lon = t.number(7);
    g.alt = t.number(8);
    const double ground_speed = t.number(10), course = t.number(11);  // course: rad from true north
    g.vel = {ground_speed * std::cos(course), ground_speed * std::sin(course), t.number(12)};
    if (raw) {
      if (!raw->next(7)) raw->fail(fmt::format("ends before GPS.txt (GPS.txt line {})", t.line()));
      if (from_ms(raw->number(0)) != g.stamp)
        raw->fail(fmt::format("time {} ms differs from GPS.txt line {}'s {} ms", raw->number(0), t.line(), t.number(0)));
      const Eigen::Vector3d v(raw->number(4), raw->number(5), raw->number(6));
      if (ground_speed > 3.0) {  // the receiver holds its course when slow: compare only in motion
        ++compared;
        if ((v - g.vel).head<2>().norm() > 0.5) ++disagree;
      }
      g.vel = v;
    }
    if (!order.accept(g.stamp)) continue;
    out.write("gnss", g);
    airborne.add(g.stamp, g.vel.x(), g.vel.y());
  }
  order.report(t.file(), report);
  if (raw) {
    notes.push_back(
        fmt::format("gnss velocity: GPSraw.txt's NED velocity (as InertialNav fuses it when the file exists); GPS.txt's ground speed and "
                    "course (radians) give the same velocity within 0.5 m/s in {} of {} fixes above 3 m/s",
                    compared - disagree, compared));
    if (disagree > 0)
      report.warnings.push_back(
          fmt::format("{}: {} of {} fixes above 3 m/s: course/speed and GPSraw.txt's NED velocity differ by more than 0.5 m/s",
                      t.file().string(), disagree, compared));
  } else {
    notes.push_back(
        "gnss velocity: GPS.txt's ground speed and course (radians from true north): vel_n = Vg cos(course), vel_e = Vg sin(course)");
  }
}

msg::Reference attitude_row(const TextTable& a) {
  msg::Reference r;
  r.stamp = from_ms(a.number(0));
  r.phi = a.number(2) * kRadPerDeg;  // readAhrsData(): ahrsEul = deg2rad * columns 2..4
  r.theta = a.number(3) * kRadPerDeg;
  r.psi = a.number(4) * kRadPerDeg;
  return r;
}

void add_position(msg::Reference& r, const TextTable& p) {
  r.lat = p.number(1);
  r.lon = p.number(2);
  r.alt = p.number(3);
  r.v_n = p.number(4);
  r.v_e = p.number(5);
  r.v_d = p.number(6);
}

/// ATT.txt and GPOSonboard.txt merged by time into the reference topic (a row that only one of
/// them has keeps the other's columns nan).
void import_reference(const fs::path& dir, SensorLogWriter& out, ImportReport& report) {
  if (!fs::exists(dir / "ATT.txt") && !fs::exists(dir / "GPOSonboard.txt")) return;
  TextTable att(dir / "ATT.txt", TextTable::Separator::whitespace);
  TextTable pos(dir / "GPOSonboard.txt", TextTable::Separator::whitespace);
  StampOrder order;
  bool has_a = att.next(7), has_p = pos.next(7);
  while (has_a || has_p) {
    const Nanos ta = has_a ? from_ms(att.number(0)) : std::numeric_limits<Nanos>::max();
    const Nanos tp = has_p ? from_ms(pos.number(0)) : std::numeric_limits<Nanos>::max();
    msg::Reference r;
    r.stamp = std::min(ta, tp);
    if (ta == r.stamp) r = attitude_row(att);
    if (tp == r.stamp) add_position(r, pos);
    if (order.accept(r.stamp)) out.write("reference", r);
    if (ta == r.stamp) has_a = att.next(7);
    if (tp == r.stamp) has_p = pos.next(7);
  }
  order.report(att.file().parent_path() / "ATT.txt+GPOSonboard.txt", report);
}

/// The GNSS noise InertialNav's own filter fuses this data set with (code/estimator_22states.cpp:
/// InitialiseParameters' posNeSigma, posDSigma, vneSigma, vdSigma; FuseVelposNED adds
/// 0.2 * accNavMag to the velocity and position sigmas): the data set author's setting for a
/// receiver that reports no accuracy, in estimator_ekf's parameters. The velocity's manoeuvre
/// term is 0.15 here, not 0.2: with 0.2 tern's filter lets its course trail the fixes' (5.1 deg
/// RMS against 4.8) while the velocity NIS mean is 1.9 (2.5 with 0.15; 5.9 with tern's 0.05).
void inertialnav_gnss_noise(SensorLogMeta& meta) {
  meta.estimator["gnss_pos_noise_h"] = 2.0;
  meta.estimator["gnss_pos_noise_v"] = 2.0;
  meta.estimator["gnss_vel_noise_h"] = 0.2;
  meta.estimator["gnss_vel_noise_v"] = 0.3;
  meta.estimator["gnss_pos_accel_scale"] = 0.2;
  meta.estimator["gnss_vel_accel_scale"] = 0.15;
  meta.notes.push_back(
      "gnss noise: InertialNav's own settings for this data set (code/estimator_22states.cpp: posNeSigma 2.0, posDSigma 2.0, vneSigma "
      "0.2, vdSigma 0.3 m(/s), plus 0.2 * accNavMag in FuseVelposNED) -> gnss_pos_noise_h/v, gnss_vel_noise_h/v, gnss_pos_accel_scale; "
      "gnss_vel_accel_scale 0.15, tuned on this flight's velocity NIS (0.2: course 5.1 deg RMS vs the fixes)");
}

}  // namespace

ImportReport import_inertialnav(const fs::path& in, SensorLogWriter& out) {
  const fs::path dir = directory_holding(in, {"IMU.txt"});
  const Timing timing = read_timing(dir);
  ImportReport report;
  SensorLogMeta meta;
  meta.source = "InertialNav text files (github.com/priseborough/InertialNav, code/main_closed_loop_float.cpp's columns)";
  meta.aircraft = "PX4 fixed wing (InertialNav's PX4 data set)";
  import_imu(dir, out, report, meta.notes);
  AirborneWindow airborne;
  import_gnss(dir, out, report, meta.notes, airborne);
  import_air_data(dir, out, report);
  import_mag(dir, out, report);
  import_reference(dir, out, report);

  meta.estimator["gnss_delay"] = timing.pos_delay_ms * 1e-3;
  meta.estimator["baro_delay"] = timing.hgt_delay_ms * 1e-3;
  meta.estimator["mag_delay"] = timing.mag_delay_ms * 1e-3;
  meta.estimator["diff_pressure_delay"] = timing.tas_delay_ms * 1e-3;
  meta.estimator["rho"] = kIsaSeaLevelDensity / (timing.eas2tas * timing.eas2tas);
  inertialnav_gnss_noise(meta);
  auto& n = meta.notes;
  n.push_back(
      "stamps: InertialNav's time columns (ms) as received; no delay is applied to them: the delays are the estimator settings above");
  n.push_back(
      fmt::format("timing.txt: msecPosDelay {} ms -> gnss_delay; msecVelDelay {} ms is {} ms longer (one gnss_delay serves both: the "
                  "velocity's own delay is not represented)",
                  timing.pos_delay_ms, timing.vel_delay_ms, timing.vel_delay_ms - timing.pos_delay_ms));
  n.push_back(
      fmt::format("timing.txt: msecHgtDelay {} -> baro_delay, msecMagDelay {} -> mag_delay, msecTasDelay {} -> diff_pressure_delay (ms)",
                  timing.hgt_delay_ms, timing.mag_delay_ms, timing.tas_delay_ms));
  n.push_back(fmt::format("timing.txt: EAS2TAS {} -> rho = 1.225 / EAS2TAS^2; InertialNav replays {} s to {} s of the log", timing.eas2tas,
                          timing.start_s, timing.end_s));
  n.push_back("diff_pressure: NTUN.txt's EAS (m/s) as 0.5 * 1.225 * EAS^2 (Pa)");
  n.push_back(
      "baro: NTUN.txt's baro height (m) taken as an ISA pressure altitude against 1013.25 hPa: p = 101325 (1 - 2.25577e-5 h)^5.25588");
  n.push_back("mag: MAG.txt's field minus its offset columns (as InertialNav's readMagData), mGauss * 1e-7 = T");
  n.push_back(
      "gnss: GPS.txt column 9 (height, m) as altitude above mean sea level; no satellite count or accuracy recorded (num_sats, h_acc, "
      "v_acc, s_acc 0)");
  n.push_back("reference: ATT.txt roll/pitch/yaw (deg) and GPOSonboard.txt lat/lon/height/NED velocity: PX4's onboard estimate");
  n.push_back("temperature columns: not recorded; the message default 288.15 K is written");
  n.push_back("date: the flight's date is not in the files; 2014-02-11 is the day the data set was added to InertialNav (an upper bound)");
  meta.date = "2014-02-11";
  report.warnings.push_back(
      fmt::format("{}: no surface commands in this log (InertialNav's files hold sensors and the onboard estimate "
                  "only): no actuators.csv written (tern sysid needs one)",
                  dir.string()));
  airborne.write_to(meta);
  out.finish(meta, report.warnings);
  report.rows = out.rows();
  return report;
}

}  // namespace tern::core
