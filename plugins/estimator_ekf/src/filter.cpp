// Filter propagation and the error-state correction (equations in filter.hpp).
#include "tern/estimator_ekf/filter.hpp"

#include <cmath>

namespace tern::ekf {

NominalState boxplus(const NominalState& x, const ErrVec& dx) {
  NominalState r = x;
  r.p += dx.segment<3>(idx::p);
  r.v += dx.segment<3>(idx::v);
  r.q = (x.q * quat_exp(dx.segment<3>(idx::th))).normalized();
  r.b_g += dx.segment<3>(idx::bg);
  r.b_a += dx.segment<3>(idx::ba);
  r.wind += dx.segment<2>(idx::w);
  r.b_baro += dx(idx::bb);
  r.e_gnss += dx.segment<3>(idx::eg);
  r.S_g += Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(dx.data() + idx::sg);
  r.b_m += dx.segment<3>(idx::bm);
  r.k_sp += dx(idx::sp);
  r.wind_d += dx(idx::wd);
  return r;
}

void Filter::propagate(const Vec3& accel, const Vec3& gyro, double dt, const ProcessNoise& noise, double gravity) {
  const Vec3 a = accel - x_.b_a;  // specific force, body
  const Vec3 w = x_.rate(gyro);   // body rate
  const Mat3 R = x_.R();
  const Mat3 Fthbg = -dt * (Mat3::Identity() - x_.S_g);
  const Mat39 Fthsg = -dt * sensitivity_jacobian(gyro - x_.b_g);
  const Mat3 Fvba = -dt * R;

  x_ = propagate_nominal(x_, accel, gyro, dt, gravity, noise);

  // Covariance P <- F P F^T + Q, with F = I except the blocks
  //   F_p,v = dt I, F_v,theta = -dt R [a]x, F_v,ba = -dt R, F_theta,theta = Exp(-w dt),
  //   F_theta,bg = -dt (I - S_g), F_theta,S = -dt U,
  //   F_eg,eg = exp(-k dt) I, F_wd,wd = exp(-dt / tau_w) (Gauss-Markov GNSS error, vertical wind).
  // Done as row then column block operations (F P, then (F P) F^T): a few thousand multiply-adds
  // instead of 2 kErrDim^3 for dense products.
  const Mat3 Fvth = -dt * R * tern::skew(a);
  const Mat3 Fthth = quat_exp(-w * dt).toRotationMatrix();
  Cov& P = P_;
  // Rows (order matters: each row block uses the old values of the blocks below it).
  P.middleRows<3>(idx::p) += dt * P.middleRows<3>(idx::v);
  P.middleRows<3>(idx::v) += Fvth * P.middleRows<3>(idx::th) + Fvba * P.middleRows<3>(idx::ba);
  P.middleRows<3>(idx::th) =
      (Fthth * P.middleRows<3>(idx::th) + Fthbg * P.middleRows<3>(idx::bg) + Fthsg * P.middleRows<9>(idx::sg)).eval();
  const double fe = std::exp(-noise.gnss_error_k * dt), fw = std::exp(-noise.vertical_wind_rate() * dt);
  P.middleRows<3>(idx::eg) *= fe;
  P.row(idx::wd) *= fw;
  // Columns.
  P.middleCols<3>(idx::p) += dt * P.middleCols<3>(idx::v);
  P.middleCols<3>(idx::v) += P.middleCols<3>(idx::th) * Fvth.transpose() + P.middleCols<3>(idx::ba) * Fvba.transpose();
  P.middleCols<3>(idx::th) = (P.middleCols<3>(idx::th) * Fthth.transpose() + P.middleCols<3>(idx::bg) * Fthbg.transpose() +
                              P.middleCols<9>(idx::sg) * Fthsg.transpose())
                                 .eval();
  P.middleCols<3>(idx::eg) *= fe;
  P.col(idx::wd) *= fw;

  P.diagonal() += process_noise_diagonal(noise, dt, (a - Vec3(0.0, 0.0, -gravity)).norm());
  symmetrize(P);
}

NominalState Filter::propagate_nominal(const NominalState& x, const Vec3& accel, const Vec3& gyro, double dt, double gravity,
                                       const ProcessNoise& noise) {
  NominalState r = x;
  const Vec3 a_n = x.R() * (accel - x.b_a) + Vec3(0.0, 0.0, gravity);
  r.p += x.v * dt + (0.5 * dt * dt) * a_n;
  r.v += a_n * dt;
  r.q = (x.q * quat_exp(x.rate(gyro) * dt)).normalized();
  r.e_gnss *= std::exp(-noise.gnss_error_k * dt);  // expectations of the Gauss-Markov processes
  r.wind_d *= std::exp(-noise.vertical_wind_rate() * dt);
  return r;
}

Cov Filter::transition(const NominalState& x, const Vec3& accel, const Vec3& gyro, double dt, const ProcessNoise& noise) {
  const Mat3 R = x.R();
  Cov F = Cov::Identity();
  F.block<3, 3>(idx::p, idx::v) = dt * Mat3::Identity();
  F.block<3, 3>(idx::v, idx::th) = -dt * R * tern::skew(accel - x.b_a);
  F.block<3, 3>(idx::v, idx::ba) = -dt * R;
  F.block<3, 3>(idx::th, idx::th) = quat_exp(-x.rate(gyro) * dt).toRotationMatrix();
  F.block<3, 3>(idx::th, idx::bg) = -dt * (Mat3::Identity() - x.S_g);
  F.block<3, 9>(idx::th, idx::sg) = -dt * sensitivity_jacobian(gyro - x.b_g);
  F.block<3, 3>(idx::eg, idx::eg) = std::exp(-noise.gnss_error_k * dt) * Mat3::Identity();
  F(idx::wd, idx::wd) = std::exp(-noise.vertical_wind_rate() * dt);
  return F;
}

ErrVec Filter::process_noise_diagonal(const ProcessNoise& noise, double dt, double load) {
  // R sigma^2 I R^T = sigma^2 I for the isotropic accelerometer noise.
  ErrVec q;
  q.segment<3>(idx::p).setConstant(noise.position * noise.position * dt);
  const double accel_scale = noise.accel_scale * load;  // m/s^2: scale, cross-axis, mount error at this load
  q.segment<3>(idx::v).setConstant(noise.accel * noise.accel * dt * dt + accel_scale * accel_scale * noise.maneuver_time * dt);
  q.segment<3>(idx::th).setConstant(noise.gyro * noise.gyro * dt * dt);
  q.segment<3>(idx::bg).setConstant(noise.gyro_bias_walk * noise.gyro_bias_walk * dt);
  q.segment<3>(idx::ba).setConstant(noise.accel_bias_walk * noise.accel_bias_walk * dt);
  q.segment<2>(idx::w).setConstant(noise.wind_walk * noise.wind_walk * dt);
  q(idx::bb) = noise.baro_bias_walk * noise.baro_bias_walk * dt;
  const double eh = noise.gnss_error_walk_h, ev = noise.gnss_error_walk_v;
  q.segment<3>(idx::eg) << eh * eh * dt, eh * eh * dt, ev * ev * dt;
  q.segment<9>(idx::sg).setConstant(noise.gyro_scale_walk * noise.gyro_scale_walk * dt);
  q.segment<3>(idx::bm).setConstant(noise.mag_bias_walk * noise.mag_bias_walk * dt);
  q(idx::sp) = noise.static_error_walk * noise.static_error_walk * dt;
  const double sw = noise.vertical_wind_sigma;  // steady sigma: the exact discrete Gauss-Markov variance
  q(idx::wd) = sw * sw * (1.0 - std::exp(-2.0 * noise.vertical_wind_rate() * dt));
  return q;
}

}  // namespace tern::ekf
