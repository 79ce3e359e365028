#include "tern/estimator_ekf/yaw_gsf.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "tern/math.hpp"

namespace tern::ekf {

namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

double wrap(double a) { return std::remainder(a, 2.0 * tern::kPi); }

/// Yaw of a body -> NED rotation: the 3-2-1 yaw, or near pitch +-90 deg the 3-1-2 one.
double yaw_of(const Mat3& R) {
  if (std::fabs(R(2, 0)) < 0.99) return std::atan2(R(1, 0), R(0, 0));
  return std::atan2(-R(0, 1), R(1, 1));
}

Mat3 rotate_yaw(double dpsi) { return Eigen::AngleAxisd(dpsi, Vec3::UnitZ()).toRotationMatrix(); }

}  // namespace

void YawGsf::predict(const Vec3& accel, const Vec3& gyro, double dt, double airspeed) {
  if (!(dt > 0.0)) return;
  airspeed_ = airspeed;
  const double coef = std::min(10.0 * dt * c_.tilt_gain, 1.0);  // a tenth of the tilt time constant
  accel_lp_ = tilt_aligned_ ? Vec3(accel_lp_ * (1.0 - coef) + accel * coef) : accel;
  if (!tilt_aligned_) {
    const double n = accel.norm();
    if (n > 0.9 * c_.gravity && n < 1.1 * c_.gravity) align_tilt(accel);  // not accelerating: tilt from gravity
    return;
  }
  for (Model& m : models_) {
    predict_attitude(m, gyro, dt, airspeed);
    if (fusing_) predict_ekf(m, accel * dt, dt);
  }
  if (fusing_) combine();
}

void YawGsf::fuse_velocity(const Eigen::Vector2d& v_ne, double sigma) {
  if (!tilt_aligned_ || !v_ne.allFinite() || !(sigma > 0.0)) return;
  if (!fusing_) {
    start(v_ne, sigma);
    return;
  }
  std::array<double, kModels> density{};
  for (int i = 0; i < kModels; ++i) {
    density[i] = update_ekf(models_[i], v_ne, sigma);
    if (density[i] <= 0.0) return;  // a singular innovation covariance: skip this fix
  }
  constexpr double kMinWeight = 1e-5;
  double total = 0.0;
  int clipped = 0;
  for (int i = 0; i < kModels; ++i) {
    Model& m = models_[i];
    m.weight *= density[i];
    if (!(m.weight >= kMinWeight)) {
      m.weight = kMinWeight;
      ++clipped;
    }
    total += m.weight;
  }
  if (clipped == kModels) {  // every model's innovations excessive: start again from this fix
    start(v_ne, sigma);
    return;
  }
  for (Model& m : models_) m.weight /= total;
  combine();
}

void YawGsf::align_tilt(const Vec3& accel) {
  // The NED axes in body axes: down against the specific force, north the body x axis levelled.
  const Vec3 down = -accel.normalized();
  Vec3 north = Vec3::UnitX() - down * down.x();
  if (north.norm() < 1e-3) north = Vec3::UnitY() - down * down.y();
  north.normalize();
  const Vec3 east = down.cross(north);
  Mat3 R;
  R.row(0) = north.transpose();
  R.row(1) = east.transpose();
  R.row(2) = down.transpose();
  for (Model& m : models_) m.R = R;
  tilt_aligned_ = true;
}

void YawGsf::start(const Eigen::Vector2d& v_ne, double sigma) {
  // Five headings evenly spread over the circle, each half an interval uncertain.
  const double step = 2.0 * tern::kPi / kModels;
  for (int i = 0; i < kModels; ++i) {
    Model& m = models_[i];
    const double psi = -tern::kPi + 0.5 * step + i * step;
    m.R = rotate_yaw(wrap(psi - yaw_of(m.R))) * m.R;
    m.x << v_ne.x(), v_ne.y(), psi;
    m.P = Eigen::Vector3d(sigma * sigma, sigma * sigma, 0.25 * step * step).asDiagonal();
    m.weight = 1.0 / kModels;
  }
  fusing_ = true;
  combine();
}

double YawGsf::accel_gain() const {
  // Full tilt correction at 1 g, none at 1.5 g or 0.5 g (quadratic in between); with the
  // centripetal acceleration removed (airspeed known), up to 2 g above.
  const double n = accel_lp_.norm();
  const double attenuation = (airspeed_ > 0.0 && n > c_.gravity) ? 1.0 : 2.0;
  const double d = std::min(attenuation * std::fabs(n - c_.gravity) / c_.gravity, 1.0);
  return c_.tilt_gain * (1.0 - d) * (1.0 - d);
}

void YawGsf::predict_attitude(Model& m, const Vec3& gyro, double dt, double airspeed) const {
  const Vec3 rate = gyro - m.gyro_bias;
  const double n = accel_lp_.norm();
  Vec3 tilt = Vec3::Zero();
  const double gain = accel_gain();
  if (gain > 0.0 && n > 0.0) {
    // a fixed wing's centripetal acceleration omega x (V, 0, 0), airspeed along body x
    const Vec3 a = accel_lp_ - (airspeed > 0.0 ? Vec3(0.0, airspeed * rate.z(), -airspeed * rate.y()) : Vec3::Zero());
    const Vec3 down_body = m.R.row(2).transpose();
    tilt = down_body.cross(a) * (gain / n);
  }
  if (rate.norm() < 0.175) {  // learn the bias only while turning slowly
    m.gyro_bias -= tilt * (c_.gyro_bias_gain * dt);
    m.gyro_bias = m.gyro_bias.cwiseMax(-0.05).cwiseMin(0.05);
  }
  const Vec3 dtheta = (rate + tilt) * dt;
  const double angle = dtheta.norm();
  if (angle > 0.0) m.R = m.R * Eigen::AngleAxisd(angle, dtheta / angle).toRotationMatrix();
}

void YawGsf::predict_ekf(Model& m, const Vec3& dv_body, double dt) const {
  m.x(2) = yaw_of(m.R);
  const Vec3 dv = m.R * dv_body;  // NED; the vertical is not a state
  m.x(0) += dv.x();
  m.x(1) += dv.y();
  // d(dv_ne)/dpsi: the horizontal delta velocity turns with the yaw
  Mat3 F = Mat3::Identity();
  F(0, 2) = -dv.y();
  F(1, 2) = dv.x();
  const double qa = c_.accel_noise * dt, qg = c_.gyro_noise * dt;
  m.P = F * m.P * F.transpose();
  m.P.diagonal() += Vec3(qa * qa, qa * qa, qg * qg);
  m.P.diagonal() = m.P.diagonal().cwiseMax(1e-6);
}

double YawGsf::update_ekf(Model& m, const Eigen::Vector2d& v_ne, double sigma) const {
  const double r2 = std::max(sigma, 0.01) * std::max(sigma, 0.01);
  const Eigen::Vector2d y = v_ne - m.x.head<2>();
  const Eigen::Matrix2d S = m.P.topLeftCorner<2, 2>() + r2 * Eigen::Matrix2d::Identity();
  const double det = S.determinant();
  if (!(det > 1e-12)) return 0.0;
  const Eigen::Matrix2d S_inv = S.inverse();
  const Eigen::Matrix<double, 3, 2> K = m.P.leftCols<2>() * S_inv;
  const double psi_before = m.x(2);
  m.x += K * y;
  m.x(2) = wrap(m.x(2));
  m.P -= K * m.P.topRows<2>();
  m.P = 0.5 * (m.P + m.P.transpose()).eval();
  m.P.diagonal() = m.P.diagonal().cwiseMax(1e-6);
  m.R = rotate_yaw(wrap(m.x(2) - psi_before)) * m.R;  // the attitude follows the yaw state
  const double nis = y.dot(S_inv * y);
  return std::exp(-0.5 * nis) / (2.0 * tern::kPi * std::sqrt(det));
}

void YawGsf::combine() {
  double s = 0.0, c = 0.0;
  for (const Model& m : models_) {
    s += m.weight * std::sin(m.x(2));
    c += m.weight * std::cos(m.x(2));
  }
  yaw_ = std::atan2(s, c);
  yaw_variance_ = 0.0;
  for (const Model& m : models_) {
    const double d = wrap(m.x(2) - yaw_);
    yaw_variance_ += m.weight * (m.P(2, 2) + d * d);
  }
}

}  // namespace tern::ekf
