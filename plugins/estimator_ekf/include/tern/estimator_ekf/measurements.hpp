// tern/estimator_ekf/measurements.hpp: the measurement models of the EKF, one small class each.
//
// A model of an M-dimensional measurement z derives from Measurement<Self, M> and provides
//   Vec   h(const NominalState& x) const       predicted measurement h(x)
//   Jac   jacobian(const NominalState& x) const  H = dh/d(dx), M x 21, at x (error-state Jacobian:
//                                              h(x [+] dx) = h(x) + H dx + O(|dx|^2))
//   Noise noise(const NominalState& x) const   measurement covariance R, M x M, positive definite
// and may redefine
//   bool  applicable(const NominalState& x, const Vec& z) const   default: always
//   Vec   residual(const NominalState& x, const Vec& z) const     default: z - h(x)
// Every model has a chi-square gate (`gate`, the largest accepted normalised innovation squared
// y^T S^-1 y; <= 0 disables it) and counters (`stats`). Filter::update(model, z) does the rest.
// docs/adding-a-sensor.md walks through adding one.
//
// Jacobians use the body-frame attitude error of filter.hpp: R_true = R (I + [dtheta]x), hence
//   d(R^T a)/d(dtheta) = [R^T a]x   for a fixed NED vector a.
#pragma once

#include <cmath>

#include "tern/estimator_ekf/filter.hpp"
#include "tern/atmosphere.hpp"
#include "tern/math.hpp"

namespace tern::ekf {

/// Chi-square quantiles at 99.9 % (default gates): 1, 2, 3 degrees of freedom.
inline constexpr double kChi2_999[4] = {0.0, 10.828, 13.816, 16.266};

template <class Derived, int M>
struct Measurement {
  static constexpr int kDim = M;
  using Vec = Eigen::Matrix<double, M, 1>;
  using Jac = Eigen::Matrix<double, M, kErrDim>;
  using Noise = Eigen::Matrix<double, M, M>;

  double gate = kChi2_999[M <= 3 ? M : 3];  ///< chi-square gate on the NIS (<= 0: none)
  UpdateStats stats;

  bool applicable(const NominalState& /*x*/, const Vec& /*z*/) const { return true; }
  Vec residual(const NominalState& x, const Vec& z) const { return z - static_cast<const Derived&>(*this).h(x); }
};

/// GNSS position: z = NED position of the antenna relative to the origin, m (the geodetic fix
/// converted by a local tangent plane at the origin). The antenna sits at r_a (body FRD, m) from
/// the CG: h(x) = p + R r_a + e_gnss (e_gnss: the slowly wandering GNSS error, a state);
/// H = [I (p), -R [r_a]x (dtheta), I (e_gnss)]. sigma_*: the white part.
struct GnssPosition : Measurement<GnssPosition, 3> {
  double sigma_h = 0.1;         ///< horizontal white noise, 1 sigma, m
  double sigma_v = 0.2;         ///< vertical white noise, 1 sigma, m
  Vec3 antenna = Vec3::Zero();  ///< r_a, antenna position from the CG, body FRD, m
  Vec h(const NominalState& x) const { return x.p + x.q * antenna + x.e_gnss; }
  Jac jacobian(const NominalState& x) const;
  Noise noise(const NominalState& x) const;
};

/// GNSS velocity: z = NED ground velocity of the antenna, m/s. With the body rate
/// omega = (I - S_g) (w_m - b_g) (w_m: the measured gyro, set before each update) the antenna
/// moves at h(x) = v + R (omega x r_a);
/// H = [I (v), -R [omega x r_a]x (dtheta), R [r_a]x (I - S_g) (db_g), R [r_a]x U (dS_g)]
/// (d(omega x r_a) = -[r_a]x d omega, d omega = -(I - S_g) db_g - U dS_g; U: sensitivity_jacobian).
struct GnssVelocity : Measurement<GnssVelocity, 3> {
  double sigma_h = 0.01;        ///< horizontal noise, 1 sigma, m/s
  double sigma_v = 0.01;        ///< vertical noise, 1 sigma, m/s
  Vec3 antenna = Vec3::Zero();  ///< r_a, body FRD, m
  Vec3 gyro = Vec3::Zero();     ///< w_m, measured body rate (bias not removed), FRD, rad/s
  Vec h(const NominalState& x) const { return x.v + x.q * x.rate(gyro).cross(antenna); }
  Jac jacobian(const NominalState& x) const;
  Noise noise(const NominalState& x) const;
};

/// GNSS velocity of a receiver or log without the vertical component (mavros' GPS_RAW_INT, a
/// ground speed and course alone): z = the antenna's north and east ground velocity, m/s (NED);
/// h, H and the noise are GnssVelocity's north and east rows (`full` holds the antenna, the gyro
/// and sigma_h; its sigma_v is unused). 2 dof.
struct GnssVelocityNE : Measurement<GnssVelocityNE, 2> {
  GnssVelocity full;
  Vec h(const NominalState& x) const { return full.h(x).head<2>(); }
  Jac jacobian(const NominalState& x) const { return full.jacobian(x).topRows<2>(); }
  Noise noise(const NominalState& x) const { return full.noise(x).topLeftCorner<2, 2>(); }
};

/// The unit field direction in NED from declination D (east of north) and inclination I (down
/// from horizontal), rad: (cos I cos D, cos I sin D, sin I).
Vec3 field_direction_ned(double declination, double inclination);

/// Magnetometer, 3-axis: z = field / field_strength (body FRD, in units of the Earth's field).
/// h(x) = R^T m_n + b_m with the unit field direction in NED from declination D (east of north)
/// and inclination I (down from horizontal): m_n = (cos I cos D, cos I sin D, sin I), and the
/// offset b_m (a state: hard iron, motor current).
/// H_theta = [R^T m_n]x, H_bm = I. Noise: sigma / field_strength on each axis (sigma in tesla).
struct Magnetometer : Measurement<Magnetometer, 3> {
  double declination = 0.1857972802;   ///< rad (ROSflight simulator default, Provo UT)
  double inclination = 1.139436457;    ///< rad
  double sigma = 3e-6;                 ///< noise of each axis, 1 sigma, T
  double field_strength = 5.07163e-5;  ///< total intensity, T (the unit of z and b_m)
  Vec3 field_direction_ned() const;
  Vec h(const NominalState& x) const;
  Jac jacobian(const NominalState& x) const;
  Noise noise(const NominalState& x) const;
};

/// Magnetometer, tilt-compensated heading: z = psi_m, the yaw (rad) at which the measured field
/// m_b, levelled with the estimated roll and pitch, points at the declination:
///   m_l = L(phi, theta) m_b = R_y(theta) R_x(phi) m_b,   psi_m = D - atan2(m_l,y, m_l,x)
/// (heading_from_field). The model is the same function of the field the state predicts,
/// m_b = R^T m_n + b_m (Magnetometer):
///   h(x) = D - atan2(l_y, l_x),   l = L m_b = R_z(psi)^T m_n + L b_m,
/// which is psi itself when b_m = 0. H through the Euler angles (phi, theta, psi) of x: the
/// offset's levelling L b_m depends on roll and pitch, so a large offset estimate lets the heading
/// touch them slightly (exactly zero at b_m = 0: a magnetic disturbance cannot tilt the estimate);
/// H_bm = -(l_x L_1 - l_y L_0) / (l_x^2 + l_y^2) (L_i: rows of L).
/// Noise: sigma / (field_strength cos I) rad, plus tilt_variance: z is levelled with the
/// estimate's roll and pitch, whose error turns into heading error (about tan I times it: 2x at
/// ROSflight's field), set before each update from the filter's covariance (tilt_variance_of()).
struct MagHeading : Measurement<MagHeading, 1> {
  double declination = 0.1857972802;   ///< rad
  double inclination = 1.139436457;    ///< rad
  double sigma = 3e-6;                 ///< field noise per axis, 1 sigma, T
  double field_strength = 5.07163e-5;  ///< T
  double tilt_variance = 0.0;          ///< rad^2, the levelling's share of z's variance
  /// Variance (rad^2) of the heading from a field m_body (any unit) levelled with (phi, theta)
  /// whose body-frame attitude error has covariance P_theta (3x3, rad^2): J W P_theta W^T J^T,
  /// J = d psi_m / d(phi, theta), W the Euler rates of a body rotation (Beard & McLain eq. 3.3).
  static double tilt_variance_of(const Vec3& m_body, double phi, double theta, const Mat3& P_theta);
  static double heading_from_field(const Vec3& m_body, double phi, double theta, double declination);
  Vec h(const NominalState& x) const;
  Vec residual(const NominalState& x, const Vec& z) const;
  Jac jacobian(const NominalState& x) const;
  Noise noise(const NominalState& x) const;
};

/// Barometric altitude: z = altitude above the origin from static pressure (after the ground
/// calibration), m. The static port reads the ambient pressure plus k_sp times the dynamic
/// pressure q_bar (its position error: the flow around the fuselage; PX4 EKF2's EKF2_PCOEF_*,
/// calibrated there by flight test, estimated here). The calibration took the error at its own
/// q_0 into the datum, so the altitude is lowered by k_sp (q_bar - q_0) / (rho g):
///   h(x) = -p_d + b_baro - k_sp (q_bar - q_0) / (rho g);
///   H_pd = -1, H_bb = 1, H_ksp = -(q_bar - q_0) / (rho g).
/// q_bar is the pitot's measured differential pressure, set before each update (dynamic_pressure);
/// it varies with the airspeed where b_baro does not, which separates the two: the takeoff run
/// (q_bar from 0 to ~100 Pa at a constant height) and every change of airspeed. At a constant
/// airspeed k_sp stays its prior and out of the altitude.
/// The port's error from the flow across the body (PX4's EKF2_PCOEF_Y*/Z terms: K_y v_r^2 +
/// K_z w_r^2, times rho / 2) is not modelled; its coefficients, unknown, are taken as zero with
/// sigma cross_flow_sigma, and the noise carries what they may add: cross_flow_sigma
/// (v_r^2 + w_r^2) / (2 g), m, in root-sum-square with sigma (a consider term: in a knife edge or a
/// pull the barometer is trusted less rather than rejected).
struct BaroAltitude : Measurement<BaroAltitude, 1> {
  double sigma = 0.33;                                    ///< m (4 Pa / (rho g))
  double cross_flow_sigma = 0.0;                          ///< the cross-flow coefficients' uncertainty, fraction of their dynamic pressure
  double gravity = kStandardGravity;                      ///< m/s^2
  double rho_g = kIsaSeaLevelDensity * kStandardGravity;  ///< Pa per metre of height (air density times gravity)
  double dynamic_pressure = 0.0;                          ///< q_bar, Pa (>= 0)
  double q_datum = 0.0;                                   ///< q_0, the mean dynamic pressure of the calibration, Pa
  Vec h(const NominalState& x) const { return Vec(-x.p.z() + x.b_baro - x.k_sp * (dynamic_pressure - q_datum) / rho_g); }
  Jac jacobian(const NominalState& x) const;
  Noise noise(const NominalState& x) const {
    const Vec3 va = x.air_velocity_body();
    const double cross = cross_flow_sigma * (va.y() * va.y() + va.z() * va.z()) / (2.0 * gravity);
    return Noise(sigma * sigma + cross * cross);
  }
};

/// Pitot airspeed: z = sqrt(2 p_diff / rho), m/s, the airspeed along the pitot tube from the
/// differential pressure (Beard & McLain eq. 7.3). h(x) = u_r with (u_r, v_r, w_r) = R^T (v - w).
/// Linear in u_r where the pressure 0.5 rho u_r^2 is not: from a poor start (the wind unknown at
/// takeoff, u_r estimated at 3 m/s for a true 9) the pressure's Jacobian rho u_r is a third of
/// the truth's and one update overshoots by metres per second, and its u_r -> -u_r symmetry holds
/// a tailwind solution (bench_estimation, aggressive, a seed settled on a wind 25 m/s off).
/// Applicable when z >= min_airspeed. H = e1^T J_air (air_velocity_jacobian).
/// Noise: the pressure's sigma as airspeed, sigma / (rho Va) (dp = rho Va dVa, Va >= min_airspeed),
/// plus turbulence the wind state does not follow (gust_sigma along x).
struct PitotAirspeed : Measurement<PitotAirspeed, 1> {
  double rho = kIsaSeaLevelDensity;  ///< air density, kg/m^3
  double sigma = 1.15;               ///< differential-pressure noise, Pa
  double gust_sigma = 1.0;           ///< m/s, unmodelled gusts along body x
  double min_airspeed = 8.0;         ///< m/s
  /// The airspeed (m/s) a differential pressure (Pa) gives; 0 for p <= 0.
  double airspeed(double pressure) const { return pressure > 0.0 ? std::sqrt(2.0 * pressure / rho) : 0.0; }
  bool applicable(const NominalState& /*x*/, const Vec& z) const { return z(0) >= min_airspeed; }
  Vec h(const NominalState& x) const { return Vec(x.air_velocity_body().x()); }
  Jac jacobian(const NominalState& x) const;
  Noise noise(const NominalState& x) const;
};

/// Zero-sideslip pseudo-measurement: z = 0 = v_r, the body-y air velocity (coordinated flight,
/// Beard & McLain section 8.10.2). Applicable when the estimated airspeed >= min_airspeed.
/// H = e2^T J_air (air_velocity_jacobian).
struct ZeroSideslip : Measurement<ZeroSideslip, 1> {
  double sigma = 2.0;         ///< m/s: how far from coordinated the aircraft flies (gusts)
  double min_airspeed = 8.0;  ///< m/s
  bool applicable(const NominalState& x, const Vec& z) const;
  Vec h(const NominalState& x) const { return Vec(x.air_velocity_body().y()); }
  Jac jacobian(const NominalState& x) const;
  Noise noise(const NominalState& /*x*/) const { return Noise(sigma * sigma); }
};

/// Side force: z = a_y, the body-y specific force from the accelerometer (averaged over the
/// samples since the previous update), m/s^2. The lateral aerodynamic force of Beard & McLain
/// eq. 4.14 over the mass, with beta ~ v_r / Va and Va ~ u_r (|alpha|, |beta| small):
///   h(x) = k (u_r^2 c_0 + C_Y_beta u_r v_r) + b_a,y,   k = rho S / (2 m),
///   c_0 = C_Y_0 + C_Y_delta_a delta_a + C_Y_delta_r delta_r   (deflections from `actuators`),
/// (u_r, v_r, w_r) = R^T (v - w). The rate terms C_Y_p, C_Y_r are left to the noise (zero for
/// the Anaconda and small for most aircraft). Where the zero-sideslip pseudo-measurement assumes
/// v_r = 0, this measures v_r (the aircraft's response to lateral gusts), so the wind state
/// follows turbulence across the flight path too. Needs the aircraft's S, m and C_Y_*: the
/// estimator_ekf plugin reads them from the mission's aircraft file.
/// H = k [2 u_r c_0 + C_Y_beta v_r, C_Y_beta u_r, 0] J_air + e(b_a,y), J_air from
/// air_velocity_jacobian(). Applicable when the estimated airspeed >= min_airspeed.
/// Noise: sigma plus the lateral turbulence the wind state does not follow, a gust of gust_sigma
/// across the aircraft: R = sigma^2 + (k C_Y_beta u_r gust_sigma)^2 (without it the side force's
/// mean NIS was 8 on the aggressive mission, moderate turbulence, and it rejected 11 %).
struct SideForce : Measurement<SideForce, 1> {
  double k = 0.0;  ///< rho S / (2 m), 1/m
  double C_Y_0 = 0.0;
  double C_Y_beta = 0.0;      ///< per rad
  double C_Y_delta_a = 0.0;   ///< per rad
  double C_Y_delta_r = 0.0;   ///< per rad
  double delta_a = 0.0;       ///< current aileron deflection, rad (set before each update)
  double delta_r = 0.0;       ///< current rudder deflection, rad
  double sigma = 0.3;         ///< m/s^2: averaged accelerometer noise plus model error
  double gust_sigma = 1.0;    ///< m/s, unmodelled gusts across body y
  double min_airspeed = 8.0;  ///< m/s
  bool applicable(const NominalState& x, const Vec& z) const;
  double c0() const { return C_Y_0 + C_Y_delta_a * delta_a + C_Y_delta_r * delta_r; }
  Vec h(const NominalState& x) const;
  Jac jacobian(const NominalState& x) const;
  Noise noise(const NominalState& x) const;
};

/// Normal force: z = a_z, the body-z specific force from the accelerometer (averaged over the
/// samples since the previous update), m/s^2. The aerodynamic force along body z over the mass,
/// Beard & McLain eq. 4.19 with C_Z ~ -C_L (|alpha| small: the drag's share C_D sin(alpha) is a
/// few thousandths of C_L) and alpha ~ w_r / u_r:
///   h(x) = -k (c_0 u_r^2 + C_L_alpha u_r w_r + C_L_q (c / 2) q u_r) + b_a,z,   k = rho S / (2 m),
///   c_0 = C_L_0 + C_L_delta_e delta_e   (delta_e and the pitch rate q set before each update),
/// (u_r, v_r, w_r) = R^T (v - w). It measures w_r, the air's velocity along body z, that no other
/// sensor sees: with the vertical wind state, the vertical gust and in a bank the horizontal
/// wind's share of body z (the lift-model wind estimation of Johansen et al., "On estimation of
/// wind velocity, angle-of-attack and sideslip angle of small UAVs using standard sensors",
/// ICUAS 2015). Needs the aircraft's S, m, chord and C_L_* (the plugin reads the aircraft file).
/// On the ground the wheels carry the weight: applicable from min_airspeed (estimated), and the
/// gate rejects the takeoff run's remaining ground reaction.
/// The lift acts on the airframe, whose attitude differs from the board's (the filter's) by the
/// tilt a level calibration put into the accelerometer offset, mu = level_G b_a
/// (Estimator::body_attitude): the air velocity is taken in the airframe, a = v_r + mu x v_r
/// (first order). So the angle of attack ties the airframe's pitch to the flight path and the
/// offset's x component (the board's pitch) becomes observable, weakly: a constant offset of the
/// angle of attack also fits a mean vertical wind, which turbulence leaves uncertain.
/// H = dh/da [(I + [mu]x) J_air - [v_r]x level_G (db_a)] + e(b_a,z),
/// dh/da = -k [2 u_r c_0 + C_L_alpha w_r + C_L_q (c / 2) q, 0, C_L_alpha u_r].
struct NormalForce : Measurement<NormalForce, 1> {
  double k = 0.0;  ///< rho S / (2 m), 1/m
  double C_L_0 = 0.0;
  double C_L_alpha = 0.0;       ///< per rad
  double C_L_q = 0.0;           ///< per rad (with the rate normalised by c / (2 Va))
  double C_L_delta_e = 0.0;     ///< per rad
  double chord = 0.0;           ///< m, mean aerodynamic chord
  double delta_e = 0.0;         ///< current elevator deflection, rad (set before each update)
  double q = 0.0;               ///< current pitch rate, rad/s (set before each update)
  double sigma = 1.0;           ///< m/s^2: averaged accelerometer noise (vibration) plus model error
  double min_airspeed = 8.0;    ///< m/s
  Mat3 level_G = Mat3::Zero();  ///< mu = level_G b_a, the board's tilt in the offset (zero: none)
  bool applicable(const NominalState& x, const Vec& z) const;
  double c0() const { return C_L_0 + C_L_delta_e * delta_e; }
  /// The air velocity in the airframe's axes, m/s.
  Vec3 airframe_air_velocity(const NominalState& x) const;
  Vec h(const NominalState& x) const;
  Jac jacobian(const NominalState& x) const;
  Noise noise(const NominalState& /*x*/) const { return Noise(sigma * sigma); }
};

/// Jacobian of the body air velocity v_r = R^T (v - w) with respect to the error state
/// (3 x kErrDim): J_air = [R^T (dv), [v_r]x (dtheta), -R^T[:, 0:2] (dw), -R^T[:, 2] (dw_d)].
Eigen::Matrix<double, 3, kErrDim> air_velocity_jacobian(const NominalState& x);

}  // namespace tern::ekf
