// tern/msg/state.hpp: the vehicle state, on topics `state` (estimator) and `truth` (simulator).
// Mirrors ROSplane's State message (rosplane_msgs/State) in the uavbook's symbols, in double
// precision and SI units. NED position is relative to the origin (origin_lat/lon/alt).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "tern/time.hpp"

namespace tern::msg {

/// How far the estimate can be trusted (estimator_ekf; the simulator's truth is always ok).
enum class StateStatus : std::uint8_t {
  invalid = 0,  ///< not initialised, or attitude/position lost (e.g. IMU silent): do not fly on it
  ok = 1,       ///< every expected sensor is fused
  degraded = 2  ///< usable, but a sensor is missing (degraded_sensors says which): e.g. dead
                ///< reckoning without GNSS, covariance growing
};

/// Bits of State::degraded_sensors.
namespace sensor_bit {
inline constexpr std::uint8_t imu = 1, gnss = 2, baro = 4, diff_pressure = 8, mag = 16;
}

struct State {
  static constexpr std::string_view type_name = "tern/State";
  Nanos stamp = 0;
  double p_n = 0.0, p_e = 0.0, p_d = 0.0;                    ///< position NED relative to the origin, m
  double u = 0.0, v = 0.0, w = 0.0;                          ///< ground velocity in body FRD, m/s
  double v_n = 0.0, v_e = 0.0, v_d = 0.0;                    ///< ground velocity in NED, m/s
  double phi = 0.0, theta = 0.0, psi = 0.0;                  ///< roll, pitch, yaw (3-2-1 Euler), rad
  Eigen::Quaterniond quat = Eigen::Quaterniond::Identity();  ///< body -> NED attitude
  double p = 0.0, q = 0.0, r = 0.0;                          ///< body rates, FRD, rad/s (bias removed)
  double Va = 0.0;                                           ///< airspeed, m/s
  double alpha = 0.0;                                        ///< angle of attack, rad
  double beta = 0.0;                                         ///< sideslip, rad
  double chi = 0.0;                                          ///< course over ground, rad, [-pi, pi)
  double Vg = 0.0;                                           ///< ground speed, m/s
  double gamma = 0.0;                                        ///< flight-path angle, rad
  double w_n = 0.0, w_e = 0.0, w_d = 0.0;                    ///< wind in NED, m/s
  double b_x = 0.0, b_y = 0.0, b_z = 0.0;                    ///< gyro bias, rad/s
  double origin_lat = 0.0;                                   ///< origin latitude, deg
  double origin_lon = 0.0;                                   ///< origin longitude, deg
  double origin_alt = 0.0;                                   ///< origin altitude (MSL), m
  bool origin_valid = false;                                 ///< the origin is set (after the first 3-D GNSS fix)
  bool valid = false;                                        ///< the estimate is initialised and usable
                                                             ///< (status ok or degraded)
  StateStatus status = StateStatus::invalid;
  std::uint8_t degraded_sensors = 0;  ///< sensor_bit flags of the sensors timed out or
                                      ///< persistently rejected (0 when status is ok)
  /// Diagonal of the estimator's error-state covariance (zeros when the publisher has none, e.g.
  /// truth). Layout of estimator_ekf: position NED (3, m^2), velocity NED (3, (m/s)^2), attitude
  /// error (3, rad^2), gyro bias (3, (rad/s)^2), accelerometer bias (3, (m/s^2)^2), wind north,
  /// east (2, (m/s)^2), barometer bias (1, m^2), GNSS position error (3, m^2). The published
  /// figures are about the body and the frame: the body's attitude (with a level-calibrated
  /// accelerometer: the filter's less the board tilt in its offset, roll and pitch widened by the
  /// calibration floor's level, yaw by the mounting uncertainty; otherwise all three by the
  /// mounting uncertainty), down position by the uncertainty of the barometer's calibration
  /// datum (the origin, a GNSS fix).
  std::array<double, 21> P_diag{};
  /// First index of each block of P_diag (estimator_ekf's layout above; P_wind: north, east).
  static constexpr std::size_t P_position = 0, P_velocity = 3, P_attitude = 6, P_gyro_bias = 9, P_wind = 15;

  double altitude() const { return -p_d; }  ///< height above the origin, m

  template <class V>
  static constexpr void describe(V& x) {
    x(&State::stamp, "stamp", "ns");
    x(&State::p_n, "p_n", "m");
    x(&State::p_e, "p_e", "m");
    x(&State::p_d, "p_d", "m");
    x(&State::u, "u", "m/s");
    x(&State::v, "v", "m/s");
    x(&State::w, "w", "m/s");
    x(&State::v_n, "v_n", "m/s");
    x(&State::v_e, "v_e", "m/s");
    x(&State::v_d, "v_d", "m/s");
    x(&State::phi, "phi", "rad");
    x(&State::theta, "theta", "rad");
    x(&State::psi, "psi", "rad");
    x(&State::quat, "quat", "");
    x(&State::p, "p", "rad/s");
    x(&State::q, "q", "rad/s");
    x(&State::r, "r", "rad/s");
    x(&State::Va, "Va", "m/s");
    x(&State::alpha, "alpha", "rad");
    x(&State::beta, "beta", "rad");
    x(&State::chi, "chi", "rad");
    x(&State::Vg, "Vg", "m/s");
    x(&State::gamma, "gamma", "rad");
    x(&State::w_n, "w_n", "m/s");
    x(&State::w_e, "w_e", "m/s");
    x(&State::w_d, "w_d", "m/s");
    x(&State::b_x, "b_x", "rad/s");
    x(&State::b_y, "b_y", "rad/s");
    x(&State::b_z, "b_z", "rad/s");
    x(&State::origin_lat, "origin_lat", "deg");
    x(&State::origin_lon, "origin_lon", "deg");
    x(&State::origin_alt, "origin_alt", "m");
    x(&State::origin_valid, "origin_valid", "bool");
    x(&State::valid, "valid", "bool");
    x(&State::status, "status", "enum");
    x(&State::degraded_sensors, "degraded_sensors", "bits");
    x(&State::P_diag, "P_diag", "");
  }
};

}  // namespace tern::msg
