// complementary_filter.hpp: a small attitude and position estimator (plain C++, no tern host types).
//
// Attitude (Beard & McLain, ch. 8; Mahony-style complementary filter on Euler angles):
//   propagate   phi' = p + (q sin(phi) + r cos(phi)) tan(theta),  theta' = q cos(phi) - r sin(phi),
//               psi' = (q sin(phi) + r cos(phi)) / cos(theta)                           (eq. 3.3)
//   correct     roll and pitch towards the gravity direction seen by the accelerometer, with the
//               centripetal term removed using the airspeed (the accelerometer model of
//               sec. 7.1 with v = (Va, 0, 0): a = omega x v - g_body):
//                 g_b = omega x (Va, 0, 0) - a,  phi_a = atan2(g_b_y, g_b_z),
//                 theta_a = atan2(-g_b_x, |(g_b_y, g_b_z)|),
//               with time constant tau_att (s); heading towards the GNSS course (no wind: psi =
//               chi) with time constant tau_psi when the ground speed is above min_gnss_speed.
// Position and velocity: GNSS position (flat-earth from the origin) and NED velocity, blended
// at each fix with weight gnss_blend, dead-reckoned with the GNSS velocity between fixes.
// Airspeed from the pitot: Va = sqrt(2 dp / rho), rho from the barometer (p / (R T)) when one
// is available, else rho_default.
// Not estimated: wind (0), alpha and beta (0), gyro biases (0).
// Units SI; angles rad; NED positions m relative to the origin (lat0, lon0, alt0).
#pragma once

#include <Eigen/Core>

#include "tern/atmosphere.hpp"
#include "tern/param.hpp"  // ParamSpec only: FilterParams::describe names the plugin's parameters

namespace tern_@NAME@ {

/// The filter's constants; each is a plugin parameter (describe(): name, unit, range; the member
/// initialiser is the default), declared with declare_struct() in plugin.hpp.
struct FilterParams {
  double tau_att = 2.0;         ///< s, roll/pitch correction time constant (> 0)
  double tau_psi = 3.0;         ///< s, heading correction time constant (> 0)
  double gnss_blend = 0.5;      ///< weight of a GNSS position fix, (0, 1]
  double min_gnss_speed = 5.0;  ///< m/s, below it the GNSS course does not correct the heading
  double rho_default = tern::kIsaSeaLevelDensity;  ///< kg/m^3, air density without a barometer

  template <class V> static void describe(V& v) {
    using tern::ParamSpec;
    v(&FilterParams::tau_att, "tau_att", ParamSpec("s", 0.05, 100.0, "roll/pitch correction time constant"));
    v(&FilterParams::tau_psi, "tau_psi", ParamSpec("s", 0.1, 100.0, "heading correction time constant"));
    v(&FilterParams::gnss_blend, "gnss_blend", ParamSpec("", 0.01, 1.0, "weight of a GNSS position fix"));
    v(&FilterParams::min_gnss_speed, "min_gnss_speed",
      ParamSpec("m/s", 0.5, 50.0, "ground speed above which the GNSS course corrects the heading"));
    v(&FilterParams::rho_default, "rho_default", ParamSpec("kg/m^3", 0.3, 1.5, "air density without a barometer"));
  }
};

struct Estimate {
  double p_n = 0, p_e = 0, p_d = 0;      ///< NED position, m
  double v_n = 0, v_e = 0, v_d = 0;      ///< NED ground velocity, m/s
  double phi = 0, theta = 0, psi = 0;    ///< Euler angles, rad
  double p = 0, q = 0, r = 0;            ///< body rates, rad/s
  double Va = 0;                         ///< airspeed, m/s
  bool attitude_valid = false;           ///< at least one IMU sample
  bool position_valid = false;           ///< at least one 3-D GNSS fix
};

class ComplementaryFilter {
 public:
  ComplementaryFilter() = default;
  explicit ComplementaryFilter(const FilterParams& p) : prm_(p) {}
  void set_params(const FilterParams& p) { prm_ = p; }
  /// Back to no estimate (as constructed with the current parameters).
  void reset() { *this = ComplementaryFilter(prm_); }

  /// IMU sample at time t (s): specific force accel (m/s^2, FRD) and rates gyro (rad/s, FRD).
  /// The first sample initialises roll and pitch from the accelerometer.
  void imu(double t, const Eigen::Vector3d& accel, const Eigen::Vector3d& gyro);
  /// GNSS fix: position NED (m) relative to the origin and velocity NED (m/s).
  void gnss(const Eigen::Vector3d& p_ned, const Eigen::Vector3d& v_ned);
  /// Pitot differential pressure dp (Pa) and air density rho (kg/m^3; <= 0: rho_default).
  void airspeed(double dp, double rho);

  const Estimate& estimate() const { return x_; }

 private:
  FilterParams prm_;
  Estimate x_;
  double last_imu_ = -1.0;
};

/// Flat-earth conversion (sec. 7.5 style, small distances): geodetic lat/lon (deg), alt (m MSL)
/// -> NED (m) relative to the origin (lat0, lon0, alt0).
Eigen::Vector3d geodetic_to_ned(double lat, double lon, double alt, double lat0, double lon0, double alt0);

}  // namespace tern_@NAME@
