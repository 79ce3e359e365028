// tern/msg/sensors.hpp: raw sensor messages on the default topics imu, gnss, baro,
// diff_pressure, mag, range, rc and fcu_status. Published by the I/O plugin (sim_aero or fcu_serial).
// SI units; body vectors in FRD; `stamp` is the flight time of the measurement in ns.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>

#include <Eigen/Core>

#include "tern/time.hpp"

namespace tern::msg {

/// Inertial measurement unit, topic `imu` (ROSflight: 400 Hz).
struct Imu {
  static constexpr std::string_view type_name = "tern/Imu";
  Nanos stamp = 0;
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();  ///< specific force, body FRD, m/s^2 (level at rest: (0, 0, -g))
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   ///< angular rate p, q, r, body FRD, rad/s
  double temperature = 288.15;                      ///< sensor temperature, K
  template <class V>
  static constexpr void describe(V& v) {
    v(&Imu::stamp, "stamp", "ns");
    v(&Imu::accel, "accel", "m/s^2", "x,y,z");
    v(&Imu::gyro, "gyro", "rad/s", "x,y,z");
    v(&Imu::temperature, "temperature", "K");
  }
};

/// GNSS fix type, as u-blox and ROSflight report it.
enum class FixType : std::uint8_t { none = 0, dead_reckoning = 1, fix_2d = 2, fix_3d = 3 };

/// The range of a GNSS fix's values that a fixed wing's receiver can report (deg, deg, m above
/// mean sea level, m/s): the estimator refuses a fix beyond it, `tern replay` a table whose median
/// is (a unit other than the documented one: core/apps/replay/sensor_units.hpp).
inline constexpr double kGnssMaxAbsLat = 90.0, kGnssMaxAbsLon = 180.0, kGnssMinAlt = -1000.0, kGnssMaxAlt = 20000.0, kGnssMaxSpeed = 200.0;

/// GNSS receiver solution, topic `gnss` (ROSflight: 10 Hz).
struct Gnss {
  static constexpr std::string_view type_name = "tern/Gnss";
  Nanos stamp = 0;
  FixType fix_type = FixType::none;
  std::uint8_t num_sats = 0;
  double lat = 0.0;                               ///< WGS-84 latitude, deg
  double lon = 0.0;                               ///< WGS-84 longitude, deg
  double alt = 0.0;                               ///< altitude above mean sea level, m
  Eigen::Vector3d vel = Eigen::Vector3d::Zero();  ///< ground velocity in NED, m/s
  double h_acc = 0.0;                             ///< horizontal accuracy (1 sigma), m
  double v_acc = 0.0;                             ///< vertical accuracy (1 sigma), m
  double s_acc = 0.0;                             ///< speed accuracy (1 sigma), m/s
  /// Dilutions of precision the receiver reports (horizontal, vertical; 0: not reported): what a
  /// log without accuracies says of its fixes (the estimator's start-up checks, gnss_checks.hpp).
  double hdop = 0.0;
  double vdop = 0.0;
  /// When the fix was valid (the receiver's measurement epoch), flight time ns. `stamp` is when
  /// it was delivered; stamp - time_of_validity is the receiver's latency (0 when unknown).
  Nanos time_of_validity = 0;
  template <class V>
  static constexpr void describe(V& v) {
    v(&Gnss::stamp, "stamp", "ns");
    v(&Gnss::time_of_validity, "time_of_validity", "ns");
    v(&Gnss::fix_type, "fix_type", "enum");
    v(&Gnss::num_sats, "num_sats", "");
    v(&Gnss::lat, "lat", "deg");
    v(&Gnss::lon, "lon", "deg");
    v(&Gnss::alt, "alt", "m");
    v(&Gnss::vel, "vel", "m/s", "n,e,d");
    v(&Gnss::h_acc, "h_acc", "m");
    v(&Gnss::v_acc, "v_acc", "m");
    v(&Gnss::s_acc, "s_acc", "m/s");
    v(&Gnss::hdop, "hdop", "");
    v(&Gnss::vdop, "vdop", "");
  }
};

/// Static pressure, topic `baro` (ROSflight: 100 Hz).
struct Baro {
  static constexpr std::string_view type_name = "tern/Baro";
  Nanos stamp = 0;
  double pressure = 101325.0;   ///< absolute static pressure, Pa
  double temperature = 288.15;  ///< K
  template <class V>
  static constexpr void describe(V& v) {
    v(&Baro::stamp, "stamp", "ns");
    v(&Baro::pressure, "pressure", "Pa");
    v(&Baro::temperature, "temperature", "K");
  }
};

/// Pitot-static differential pressure, topic `diff_pressure` (ROSflight: 100 Hz).
/// Ideally 0.5 rho u_r^2 (u_r: body-x airspeed component).
struct DiffPressure {
  static constexpr std::string_view type_name = "tern/DiffPressure";
  Nanos stamp = 0;
  double pressure = 0.0;        ///< Pa
  double temperature = 288.15;  ///< K
  template <class V>
  static constexpr void describe(V& v) {
    v(&DiffPressure::stamp, "stamp", "ns");
    v(&DiffPressure::pressure, "pressure", "Pa");
    v(&DiffPressure::temperature, "temperature", "K");
  }
};

/// Magnetometer, topic `mag` (ROSflight: 50 Hz).
struct Mag {
  static constexpr std::string_view type_name = "tern/Mag";
  Nanos stamp = 0;
  Eigen::Vector3d field = Eigen::Vector3d::Zero();  ///< magnetic flux density, body FRD, T
  template <class V>
  static constexpr void describe(V& v) {
    v(&Mag::stamp, "stamp", "ns");
    v(&Mag::field, "field", "T", "x,y,z");
  }
};

/// Downward range finder (a lidar such as Garmin's LIDAR-Lite v3), topic `range`: the distance
/// along the sensor's axis, body +z (down, FRD), to the ground. As sensor_msgs/Range: a distance
/// outside [min_range, max_range] is no measurement (+inf: no return, beyond max_range); NaN: a
/// failing sensor. On flat ground the height of the sensor is distance cos(phi) cos(theta).
struct Range {
  static constexpr std::string_view type_name = "tern/Range";
  Nanos stamp = 0;
  double distance = std::numeric_limits<double>::infinity();  ///< m
  double min_range = 0.05;                                    ///< m, the sensor's
  double max_range = 40.0;                                    ///< m, the sensor's
  /// Consumers (the flare, the phase machine) take a measurement as current this long, ns (5
  /// samples at sim_aero's 50 Hz); older, they fall back on the altitude estimate.
  static constexpr Nanos kFresh = 100'000'000;
  /// The sensor's height above flat ground, m, given roll and pitch (rad); NaN without a valid
  /// measurement.
  double height(double phi, double theta) const {
    if (!(distance >= min_range && distance <= max_range)) return std::numeric_limits<double>::quiet_NaN();
    return distance * std::cos(phi) * std::cos(theta);
  }
  /// height() of a measurement at most kFresh old at flight time `now`, else NaN.
  double height_at(Nanos now, double phi, double theta) const {
    return now - stamp <= kFresh ? height(phi, theta) : std::numeric_limits<double>::quiet_NaN();
  }
  template <class V>
  static constexpr void describe(V& v) {
    v(&Range::stamp, "stamp", "ns");
    v(&Range::distance, "distance", "m");
    v(&Range::min_range, "min_range", "m");
    v(&Range::max_range, "max_range", "m");
  }
};

/// Radio-control receiver, topic `rc`, channels already mapped and normalised.
struct Rc {
  static constexpr std::string_view type_name = "tern/Rc";
  Nanos stamp = 0;
  double roll = 0.0;            ///< aileron stick, -1..1 (right positive)
  double pitch = 0.0;           ///< elevator stick, -1..1 (nose up positive)
  double yaw = 0.0;             ///< rudder stick, -1..1 (nose right positive)
  double throttle = 0.0;        ///< 0..1
  std::array<double, 4> aux{};  ///< auxiliary channels, -1..1
  bool rc_override = false;     ///< the pilot's override switch is on (FCU flies RC, not tern)
  bool failsafe = false;        ///< receiver lost the transmitter
  template <class V>
  static constexpr void describe(V& v) {
    v(&Rc::stamp, "stamp", "ns");
    v(&Rc::roll, "roll", "");
    v(&Rc::pitch, "pitch", "");
    v(&Rc::yaw, "yaw", "");
    v(&Rc::throttle, "throttle", "");
    v(&Rc::aux, "aux", "");
    v(&Rc::rc_override, "rc_override", "bool");
    v(&Rc::failsafe, "failsafe", "bool");
  }
};

/// Flight-control unit status, topic `fcu_status` (ROSflight's ROSFLIGHT_STATUS).
struct FcuStatus {
  static constexpr std::string_view type_name = "tern/FcuStatus";
  Nanos stamp = 0;
  bool armed = false;
  bool failsafe = false;
  bool rc_override = false;
  bool offboard = false;         ///< the FCU follows tern's commands
  std::uint32_t error_code = 0;  ///< FCU error bit field
  double battery_voltage = 0.0;  ///< V (0 when not measured)
  double battery_current = 0.0;  ///< A (0 when not measured)
  template <class V>
  static constexpr void describe(V& v) {
    v(&FcuStatus::stamp, "stamp", "ns");
    v(&FcuStatus::armed, "armed", "bool");
    v(&FcuStatus::failsafe, "failsafe", "bool");
    v(&FcuStatus::rc_override, "rc_override", "bool");
    v(&FcuStatus::offboard, "offboard", "bool");
    v(&FcuStatus::error_code, "error_code", "");
    v(&FcuStatus::battery_voltage, "battery_voltage", "V");
    v(&FcuStatus::battery_current, "battery_current", "A");
  }
};

}  // namespace tern::msg
