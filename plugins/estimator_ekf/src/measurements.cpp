// Measurement models: Jacobians and noise (equations in measurements.hpp).
#include "tern/estimator_ekf/measurements.hpp"

#include <algorithm>
#include <cmath>

#include "tern/math.hpp"

namespace tern::ekf {

GnssPosition::Jac GnssPosition::jacobian(const NominalState& x) const {
  Jac H = Jac::Zero();
  H.block<3, 3>(0, idx::p).setIdentity();
  H.block<3, 3>(0, idx::th) = -x.R() * tern::skew(antenna);
  H.block<3, 3>(0, idx::eg).setIdentity();
  return H;
}

GnssPosition::Noise GnssPosition::noise(const NominalState& /*x*/) const {
  const double sh = sigma_h, sv = sigma_v;
  return Eigen::Vector3d(sh * sh, sh * sh, sv * sv).asDiagonal();
}

GnssVelocity::Jac GnssVelocity::jacobian(const NominalState& x) const {
  const Mat3 R = x.R();
  Jac H = Jac::Zero();
  H.block<3, 3>(0, idx::v).setIdentity();
  H.block<3, 3>(0, idx::th) = -R * tern::skew(x.rate(gyro).cross(antenna));
  const Mat3 Rr = R * tern::skew(antenna);
  H.block<3, 3>(0, idx::bg) = Rr * (Mat3::Identity() - x.S_g);
  H.block<3, 9>(0, idx::sg) = Rr * sensitivity_jacobian(gyro - x.b_g);
  return H;
}

GnssVelocity::Noise GnssVelocity::noise(const NominalState& /*x*/) const {
  return Eigen::Vector3d(sigma_h * sigma_h, sigma_h * sigma_h, sigma_v * sigma_v).asDiagonal();
}

Vec3 field_direction_ned(double declination, double inclination) {
  return {std::cos(inclination) * std::cos(declination), std::cos(inclination) * std::sin(declination), std::sin(inclination)};
}

Vec3 Magnetometer::field_direction_ned() const { return ekf::field_direction_ned(declination, inclination); }

Magnetometer::Vec Magnetometer::h(const NominalState& x) const { return x.q.conjugate() * field_direction_ned() + x.b_m; }

Magnetometer::Jac Magnetometer::jacobian(const NominalState& x) const {
  Jac H = Jac::Zero();
  H.block<3, 3>(0, idx::th) = tern::skew(x.q.conjugate() * field_direction_ned());
  H.block<3, 3>(0, idx::bm).setIdentity();
  return H;
}

Magnetometer::Noise Magnetometer::noise(const NominalState& /*x*/) const {
  const double s = sigma / field_strength;
  return Noise::Identity() * (s * s);
}

namespace {

/// L(phi, theta) = R_y(theta) R_x(phi): body FRD -> the level, yaw-only frame (heading_from_field).
Mat3 levelling(double phi, double theta) {
  const double cf = std::cos(phi), sf = std::sin(phi), ct = std::cos(theta), st = std::sin(theta);
  Mat3 L;
  L << ct, st * sf, st * cf, 0.0, cf, -sf, -st, ct * sf, ct * cf;
  return L;
}

/// Rows of d(phi, theta, psi) / d(dtheta): the Euler-angle change of a body-frame rotation
/// dtheta (Beard & McLain eq. 3.3):
///   dphi = dtheta_x + sin(phi) tan(theta) dtheta_y + cos(phi) tan(theta) dtheta_z,
///   dtheta_pitch = cos(phi) dtheta_y - sin(phi) dtheta_z,  dpsi = (sin(phi) dtheta_y + cos(phi) dtheta_z) / cos(theta).
Mat3 euler_rates(double phi, double theta) {
  const double cf = std::cos(phi), sf = std::sin(phi), ct = std::cos(theta), tt = std::tan(theta);
  Mat3 W;
  W << 1.0, sf * tt, cf * tt, 0.0, cf, -sf, 0.0, sf / ct, cf / ct;
  return W;
}

}  // namespace

double MagHeading::heading_from_field(const Vec3& m, double phi, double theta, double declination) {
  const Vec3 l = levelling(phi, theta) * m;
  return declination - std::atan2(l.y(), l.x());
}

MagHeading::Vec MagHeading::h(const NominalState& x) const {
  const Vec3 e = tern::euler_from_quaternion(x.q);
  const Vec3 n = field_direction_ned(declination, inclination);
  return Vec(heading_from_field(x.q.conjugate() * n + x.b_m, e.x(), e.y(), declination));
}

MagHeading::Vec MagHeading::residual(const NominalState& x, const Vec& z) const {
  const double d = z(0) - h(x)(0);
  // std::remainder is exact for |d| <= pi; tern::wrap_pi rounds (d + pi) - pi by up to 2e-16 rad,
  // and fused on the ground each flight that would move every shipped flight log's last bits.
  return Vec(std::remainder(d, 2.0 * kPi));
}

MagHeading::Jac MagHeading::jacobian(const NominalState& x) const {
  const Vec3 e = tern::euler_from_quaternion(x.q);
  const double cf = std::cos(e.x()), sf = std::sin(e.x()), ct = std::cos(e.y()), st = std::sin(e.y());
  const Vec3 n = field_direction_ned(declination, inclination);
  const Mat3 L = levelling(e.x(), e.y());
  const Vec3 a = L * (x.q.conjugate() * n);  // R_z(psi)^T m_n
  const Vec3& b = x.b_m;
  const Vec3 l = a + L * b;
  // h = D - atan2(l_y, l_x): dh = g . dl with g = (l_y, -l_x, 0) / (l_x^2 + l_y^2).
  const Vec3 g = Vec3(l.y(), -l.x(), 0.0) / (l.x() * l.x() + l.y() * l.y());
  const Vec3 dl_dpsi(a.y(), -a.x(), 0.0);  // d(R_z(psi)^T m_n)/dpsi = -e3 x a
  const Vec3 dl_dphi(st * (cf * b.y() - sf * b.z()), -sf * b.y() - cf * b.z(), ct * (cf * b.y() - sf * b.z()));
  const Vec3 dl_dtheta(-st * b.x() + ct * (sf * b.y() + cf * b.z()), 0.0, -ct * b.x() - st * (sf * b.y() + cf * b.z()));
  Jac H = Jac::Zero();
  H.block<1, 3>(0, idx::th) = Eigen::RowVector3d(g.dot(dl_dphi), g.dot(dl_dtheta), g.dot(dl_dpsi)) * euler_rates(e.x(), e.y());
  H.block<1, 3>(0, idx::bm) = g.transpose() * L;
  return H;
}

MagHeading::Noise MagHeading::noise(const NominalState& /*x*/) const {
  const double s = sigma / (field_strength * std::cos(inclination));
  return Noise(s * s + tilt_variance);
}

double MagHeading::tilt_variance_of(const Vec3& m, double phi, double theta, const Mat3& P_theta) {
  constexpr double h = 1e-6;  // rad: the heading is smooth in the levelling angles
  const double dphi = (heading_from_field(m, phi + h, theta, 0.0) - heading_from_field(m, phi - h, theta, 0.0)) / (2.0 * h);
  const double dtheta = (heading_from_field(m, phi, theta + h, 0.0) - heading_from_field(m, phi, theta - h, 0.0)) / (2.0 * h);
  // d psi_m / d dtheta (body) through the roll and pitch rows of the Euler rates
  const Eigen::RowVector3d J = Eigen::RowVector3d(dphi, dtheta, 0.0) * euler_rates(phi, theta);
  return J * P_theta * J.transpose();
}

BaroAltitude::Jac BaroAltitude::jacobian(const NominalState& /*x*/) const {
  Jac H = Jac::Zero();
  H(0, idx::p + 2) = -1.0;
  H(0, idx::bb) = 1.0;
  H(0, idx::sp) = -(dynamic_pressure - q_datum) / rho_g;
  return H;
}

Eigen::Matrix<double, 3, kErrDim> air_velocity_jacobian(const NominalState& x) {
  Eigen::Matrix<double, 3, kErrDim> J = Eigen::Matrix<double, 3, kErrDim>::Zero();
  const Mat3 Rt = x.R().transpose();
  J.block<3, 3>(0, idx::v) = Rt;
  J.block<3, 3>(0, idx::th) = tern::skew(x.air_velocity_body());
  J.block<3, 2>(0, idx::w) = -Rt.leftCols<2>();
  J.col(idx::wd) = -Rt.col(2);
  return J;
}

PitotAirspeed::Jac PitotAirspeed::jacobian(const NominalState& x) const { return air_velocity_jacobian(x).row(0); }

PitotAirspeed::Noise PitotAirspeed::noise(const NominalState& x) const {
  const double s = sigma / (rho * std::max(x.air_velocity_body().x(), min_airspeed));
  return Noise(s * s + gust_sigma * gust_sigma);
}

bool ZeroSideslip::applicable(const NominalState& x, const Vec& /*z*/) const { return x.air_velocity_body().norm() >= min_airspeed; }

ZeroSideslip::Jac ZeroSideslip::jacobian(const NominalState& x) const { return air_velocity_jacobian(x).row(1); }

bool SideForce::applicable(const NominalState& x, const Vec& /*z*/) const {
  return k != 0.0 && x.air_velocity_body().norm() >= min_airspeed;
}

SideForce::Vec SideForce::h(const NominalState& x) const {
  const Vec3 a = x.air_velocity_body();
  return Vec(k * (a.x() * a.x() * c0() + C_Y_beta * a.x() * a.y()) + x.b_a.y());
}

SideForce::Jac SideForce::jacobian(const NominalState& x) const {
  const Vec3 a = x.air_velocity_body();
  const Eigen::RowVector3d dh_da(k * (2.0 * a.x() * c0() + C_Y_beta * a.y()), k * C_Y_beta * a.x(), 0.0);
  Jac H = dh_da * air_velocity_jacobian(x);
  H(0, idx::ba + 1) += 1.0;
  return H;
}

SideForce::Noise SideForce::noise(const NominalState& x) const {
  const double g = k * C_Y_beta * x.air_velocity_body().x() * gust_sigma;  // m/s^2 of a gust_sigma sideslip gust
  return Noise(sigma * sigma + g * g);
}

bool NormalForce::applicable(const NominalState& x, const Vec& /*z*/) const {
  return k != 0.0 && C_L_alpha != 0.0 && x.air_velocity_body().x() >= min_airspeed;
}

Vec3 NormalForce::airframe_air_velocity(const NominalState& x) const {
  const Vec3 v_r = x.air_velocity_body();
  return v_r + (level_G * x.b_a).cross(v_r);
}

NormalForce::Vec NormalForce::h(const NominalState& x) const {
  const Vec3 a = airframe_air_velocity(x);
  return Vec(-k * (c0() * a.x() * a.x() + C_L_alpha * a.x() * a.z() + C_L_q * 0.5 * chord * q * a.x()) + x.b_a.z());
}

NormalForce::Jac NormalForce::jacobian(const NominalState& x) const {
  const Vec3 a = airframe_air_velocity(x);
  const Vec3 v_r = x.air_velocity_body();
  const Eigen::RowVector3d dh_da(-k * (2.0 * c0() * a.x() + C_L_alpha * a.z() + C_L_q * 0.5 * chord * q), 0.0, -k * C_L_alpha * a.x());
  Jac H = dh_da * (Mat3::Identity() + tern::skew(level_G * x.b_a)) * air_velocity_jacobian(x);
  H.block<1, 3>(0, idx::ba) -= dh_da * tern::skew(v_r) * level_G;
  H(0, idx::ba + 2) += 1.0;
  return H;
}

}  // namespace tern::ekf
