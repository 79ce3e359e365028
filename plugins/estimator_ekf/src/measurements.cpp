// Measurement models: Jacobians and noise (equations in measurements.hpp).
#include "tern/estimator_ekf/measurements.hpp"

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

Vec3 Magnetometer::field_direction_ned() const {
  return {std::cos(inclination) * std::cos(declination), std::cos(inclination) * std::sin(declination), std::sin(inclination)};
}

Magnetometer::Vec Magnetometer::h(const NominalState& x) const { return x.q.conjugate() * field_direction_ned(); }

Magnetometer::Jac Magnetometer::jacobian(const NominalState& x) const {
  Jac H = Jac::Zero();
  H.block<3, 3>(0, idx::th) = tern::skew(h(x));
  return H;
}

Magnetometer::Noise Magnetometer::noise(const NominalState& /*x*/) const {
  const double s = sigma / field_strength;
  return Noise::Identity() * (s * s);
}

double MagHeading::heading_from_field(const Vec3& m, double phi, double theta, double declination) {
  // m_l = R_y(theta) R_x(phi) m_b (the field in the level, yaw-only frame).
  const double cf = std::cos(phi), sf = std::sin(phi), ct = std::cos(theta), st = std::sin(theta);
  const double my = cf * m.y() - sf * m.z();
  const double mz1 = sf * m.y() + cf * m.z();
  const double mx = ct * m.x() + st * mz1;
  return declination - std::atan2(my, mx);
}

MagHeading::Vec MagHeading::h(const NominalState& x) const {
  const Mat3 R = x.R();
  return Vec(std::atan2(R(1, 0), R(0, 0)));
}

MagHeading::Vec MagHeading::residual(const NominalState& x, const Vec& z) const {
  const double d = z(0) - h(x)(0);
  return Vec(std::remainder(d, 2.0 * 3.14159265358979323846));
}

MagHeading::Jac MagHeading::jacobian(const NominalState& x) const {
  // psi = atan2(R10, R00); dR = R [dtheta]x, so dR_i0 = R_i1 dtheta_z - R_i2 dtheta_y.
  const Mat3 R = x.R();
  const double den = R(0, 0) * R(0, 0) + R(1, 0) * R(1, 0);
  Jac H = Jac::Zero();
  H(0, idx::th + 1) = (R(1, 0) * R(0, 2) - R(0, 0) * R(1, 2)) / den;
  H(0, idx::th + 2) = (R(0, 0) * R(1, 1) - R(1, 0) * R(0, 1)) / den;
  return H;
}

MagHeading::Noise MagHeading::noise(const NominalState& /*x*/) const {
  const double s = sigma / (field_strength * std::cos(inclination));
  return Noise(s * s);
}

BaroAltitude::Jac BaroAltitude::jacobian(const NominalState& /*x*/) const {
  Jac H = Jac::Zero();
  H(0, idx::p + 2) = -1.0;
  H(0, idx::bb) = 1.0;
  return H;
}

Eigen::Matrix<double, 3, kErrDim> air_velocity_jacobian(const NominalState& x) {
  Eigen::Matrix<double, 3, kErrDim> J = Eigen::Matrix<double, 3, kErrDim>::Zero();
  const Mat3 Rt = x.R().transpose();
  J.block<3, 3>(0, idx::v) = Rt;
  J.block<3, 3>(0, idx::th) = tern::skew(x.air_velocity_body());
  J.block<3, 2>(0, idx::w) = -Rt.leftCols<2>();
  return J;
}

bool DiffPressure::applicable(const NominalState& /*x*/, const Vec& z) const { return z(0) >= 0.5 * rho * min_airspeed * min_airspeed; }

DiffPressure::Vec DiffPressure::h(const NominalState& x) const {
  const double u_r = x.air_velocity_body().x();
  return Vec(0.5 * rho * u_r * u_r);
}

DiffPressure::Jac DiffPressure::jacobian(const NominalState& x) const {
  const double u_r = x.air_velocity_body().x();
  return rho * u_r * air_velocity_jacobian(x).row(0);
}

DiffPressure::Noise DiffPressure::noise(const NominalState& x) const {
  const double g = rho * x.air_velocity_body().x() * gust_sigma;
  return Noise(sigma * sigma + g * g);
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

}  // namespace tern::ekf
