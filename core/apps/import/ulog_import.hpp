// core/apps/import/ulog_import.hpp: `tern import ulog`: a PX4 ULog (.ulg) into a sensor log
// (docs/sensor-log.md). import_ulog itself is declared in importers.hpp; this header holds the
// conversions it is made of, so that tests can check them one by one.
//
// Topics (uORB names; fields are looked up by name in the file's own formats, which change between
// PX4 versions; only multi-instance 0 of a topic is used; the first source with data wins):
//   imu            sensor_combined: gyro_rad[3] (rad/s), accelerometer_m_s2[3] (m/s^2), both body FRD
//                  (PX4's sensors module has applied SENS_BOARD_ROT and SENS_BOARD_{X,Y,Z}_OFF);
//                  stamp: timestamp (the gyro's; accelerometer_timestamp_relative is reported)
//   mag            vehicle_magnetometer.magnetometer_ga, else sensor_combined.magnetometer_ga (old logs;
//                  stamp timestamp + magnetometer_timestamp_relative, each sample once), else raw
//                  sensor_mag x,y,z (uncalibrated: a warning); gauss * 1e-4 = T
//   baro           vehicle_air_data.baro_pressure_pa (or its baro_alt_meter through the ISA), else
//                  sensor_combined.baro_alt_meter (old logs, ISA), else sensor_baro.pressure
//   diff_pressure  differential_pressure (differential_pressure_pa, _filtered_pa or _raw_pa; temperature
//                  deg C), else airspeed.indicated_airspeed_m_s taken as EAS (0.5 * 1.225 * EAS^2)
//   gnss           vehicle_gps_position, else sensor_gps: lat/lon (int32 1e-7 deg, or latitude_deg/
//                  longitude_deg doubles), alt (int32 mm MSL, or altitude_msl_m), vel_{n,e,d}_m_s,
//                  eph/epv (m), s_variance_m_s (m/s: the receiver's speed accuracy, 1 sigma, despite
//                  its name), satellites_used, fix_type (px4_fix_type)
//   reference      vehicle_attitude.q (else control_state.q) as roll/pitch/yaw; vehicle_global_position
//                  lat/lon/alt (else vehicle_local_position's x/y/z on its ref_lat/ref_lon/ref_alt, when
//                  xy_global/z_global); vehicle_local_position vx/vy/vz (else vehicle_global_position
//                  vel_n/e/d); wind (else wind_estimate) windspeed_north/east. One row per source
//                  message; the columns that message does not give are NaN.
//   actuators      actuator_controls_0 (a VTOL, MAV_TYPE 19-25: actuator_controls_1, its fixed-wing
//                  group): control[0..3] = roll, pitch, yaw (-1..1), throttle (0..1) as the uavbook's
//                  deflections through --max-deflection (import/surface_commands.hpp; without it none
//                  are written, one line says why); stamp: timestamp (the command's publication).
//                  PX4 v1.13+ without them: actuator_servos through CA_SV_CS<i>_TRQ_R/P/Y, throttle
//                  from actuator_motors (Conversion::add_servo_actuators)
// Times: PX4 timestamps are us since boot; stamp = (t - the header's start timestamp) in ns. A sensor
// sample's stamp is its timestamp_sample where the topic has one (the time PX4's EKF2 subtracts its
// EKF2_*_DELAY from), so the delays of sensor_log.yaml are PX4's EKF2_*_DELAY parameters. GNSS:
// stamp = timestamp, time_of_validity = timestamp_sample - EKF2_GPS_DELAY where timestamp_sample
// exists, else 0 (then the estimator's gnss_delay = EKF2_GPS_DELAY applies).
// Rows are put in time order per output topic through a 1 s window (ReorderWindow); rows older
// than the log's start or later than the window are dropped and counted.
//
// The file is read twice, streaming both times: a survey of which topics hold data (to choose
// each output's source), then the conversion.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <vector>

#include "tern/msg/sensors.hpp"
#include "tern/time.hpp"

namespace tern::core::ulog_import {

/// PX4's vehicle_gps_position.fix_type (0-1 no fix, 2 2-D, 3 3-D, 4 DGPS, 5 RTK float, 6 RTK fixed,
/// 8 extrapolated) as the sensor log's fix type: 0/1 none, 2 2-D, 3-6 3-D, 7/8 dead reckoning,
/// anything else none.
msg::FixType px4_fix_type(int px4);

struct Euler {
  double phi, theta, psi;  ///< rad, 3-2-1 (yaw, pitch, roll) of body FRD against NED
};
/// PX4's attitude quaternion q = (w, x, y, z), rotating body FRD vectors into NED, as 3-2-1 Euler
/// angles (psi in (-pi, pi]). Normalises q first.
Euler euler_from_px4_quaternion(double w, double x, double y, double z);

struct LatLon {
  double lat, lon;  ///< deg
};
/// A point `north_m`, `east_m` from a reference, as PX4's map projection (map_projection_reproject)
/// gives it: the azimuthal equidistant projection on a sphere of radius 6371000 m (Snyder's inverse
/// formulas). PX4's vehicle_local_position x/y are relative to ref_lat/ref_lon by this projection.
LatLon px4_reproject(double ref_lat_deg, double ref_lon_deg, double north_m, double east_m);

/// The ISO date ("2021-04-21") of a UTC time in us since 1970 (vehicle_gps_position.time_utc_usec);
/// "" for a time past 9999-12-31 (a corrupt field: sensor_log.yaml's date is YYYY-MM-DD).
std::string iso_date_from_utc_usec(std::uint64_t utc_usec);

/// Puts rows that arrive almost in time order into time order: a row is released once a row
/// `window` later has arrived. A row earlier than one already released is dropped and counted.
/// Holds at most the rows of one window.
template <class T>
class ReorderWindow {
 public:
  ReorderWindow(Nanos window, std::function<void(const T&)> emit) : window_(window), emit_(std::move(emit)) {}
  void push(const T& row) {
    if (released_any_ && row.stamp < last_released_) {
      ++dropped_;
      return;
    }
    heap_.push(row);
    newest_ = std::max(newest_, row.stamp);
    while (!heap_.empty() && heap_.top().stamp <= newest_ - window_) release();
  }
  void flush() {
    while (!heap_.empty()) release();
  }
  std::uint64_t dropped() const { return dropped_; }

 private:
  struct Later {
    bool operator()(const T& a, const T& b) const { return a.stamp > b.stamp; }
  };
  void release() {
    last_released_ = heap_.top().stamp;
    released_any_ = true;
    emit_(heap_.top());
    heap_.pop();
  }
  Nanos window_;
  std::function<void(const T&)> emit_;
  std::priority_queue<T, std::vector<T>, Later> heap_;
  Nanos newest_ = std::numeric_limits<Nanos>::min() / 2;
  Nanos last_released_ = 0;
  bool released_any_ = false;
  std::uint64_t dropped_ = 0;
};

}  // namespace tern::core::ulog_import
