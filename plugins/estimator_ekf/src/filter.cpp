// Filter propagation and the error-state correction (equations in filter.hpp).
#include "tern/estimator_ekf/filter.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "tern/avx_clones.hpp"

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

// The covariance's O(n^2) loops run over P's contiguous columns, each element by the same
// multiplications and additions in the same order whatever the vector width: on x86-64 they are
// also built for AVX (tern/avx_clones.hpp), with identical results. AVX-512 was slower here.
// One pass over each column with M <= 3 terms (the models' dimensions), a pass per term beyond.
TERN_AVX_CLONES
void downdate(Cov& P, const double* Wt, int M) {
  constexpr int n = kErrDim;
  for (int j = 0; j < n; ++j) {
    double* Pj = P.col(j).data();
    const double* w0 = Wt;
    const double a0 = w0[j];
    if (M == 1) {
      for (int i = 0; i < n; ++i) Pj[i] = Pj[i] - a0 * w0[i];
      continue;
    }
    const double *w1 = Wt + n, a1 = w1[j];
    if (M == 2) {
      for (int i = 0; i < n; ++i) Pj[i] = (Pj[i] - a0 * w0[i]) - a1 * w1[i];
      continue;
    }
    const double *w2 = Wt + 2 * n, a2 = w2[j];
    for (int i = 0; i < n; ++i) Pj[i] = ((Pj[i] - a0 * w0[i]) - a1 * w1[i]) - a2 * w2[i];
    for (int m = 3; m < M; ++m) {
      const double* w = Wt + m * n;
      for (int i = 0; i < n; ++i) Pj[i] = Pj[i] - w[j] * w[i];
    }
  }
}

TERN_AVX_CLONES
void P_times_Ht(const Cov& P, const double* H, int M, double* PHt) {
  constexpr int n = kErrDim;
  std::fill(PHt, PHt + n * M, 0.0);
  for (int k = 0; k < n; ++k) {
    const double* Pk = P.col(k).data();
    for (int m = 0; m < M; ++m) {
      const double h = H[m + k * M];
      if (h == 0.0) continue;
      double* out = PHt + m * n;
      for (int i = 0; i < n; ++i) out[i] = out[i] + h * Pk[i];
    }
  }
}

TERN_AVX_CLONES
bool all_finite(const Cov& P) {
  constexpr int N = kErrDim * kErrDim, L = 16;  // 16 running sums: four vectors' lanes, added in parallel
  const double* p = P.data();
  double acc[L] = {};
  int i = 0;
  for (; i + L <= N; i += L)
    for (int k = 0; k < L; ++k) acc[k] += p[i + k];
  double sum = 0.0;
  for (; i < N; ++i) sum += p[i];
  for (double a : acc) sum += a;
  return std::isfinite(sum);
}

bool Filter::propagate(const Vec3& accel, const Vec3& gyro, double dt, const ProcessNoise& noise, double gravity) {
  const Vec3 a = accel - x_.b_a;  // specific force, body
  accumulate(a, x_.rate(gyro), gyro - x_.b_g, dt, noise, (a - Vec3(0.0, 0.0, -gravity)).norm());
  x_ = propagate_nominal(x_, accel, gyro, dt, gravity, noise, &decays_for(noise, dt));
  if (pending_.dt < covariance_period_ * (1.0 - 1e-6)) return false;
  step_covariance();
  return true;
}

void Filter::accumulate(const Vec3& a, const Vec3& w, const Vec3& u, double dt, const ProcessNoise& noise, double load) {
  // Phi <- F Phi on the blocks Pending keeps, each from the old values (filter.hpp), with the
  // sample's F_v,theta = -dt R [a]x, F_v,ba = -dt R, F_theta,theta = Exp(-w dt),
  // F_theta,bg = -dt (I - S_g), F_theta,S = -dt U.
  Pending& f = pending_;
  const Mat3 R = x_.R();
  const Mat3 Fthth = quat_exp(-w * dt).toRotationMatrix();
  f.v_th.noalias() += (-dt * R * tern::skew(a)).lazyProduct(f.th_th);
  f.v_ba.noalias() -= dt * R;
  f.th_bg = (Fthth.lazyProduct(f.th_bg) - dt * (Mat3::Identity() - x_.S_g)).eval();
  f.th_sg = (Fthth.lazyProduct(f.th_sg) - dt * sensitivity_jacobian(u)).eval();
  f.th_th = Fthth.lazyProduct(f.th_th).eval();
  f.q += process_noise_diagonal(noise, dt, load, &decays_for(noise, dt));
  f.dt += dt;
  f.gnss_error_k = noise.gnss_error_k;
  f.vertical_wind_rate = noise.vertical_wind_rate();
  ++f.samples;
}

namespace {
/// step_covariance()'s step 1: B = P Phi^T on the columns of p, v and theta, in place:
///   P_p += T P_v;  P_v += P_th V_th^T + P_ba V_ba^T;  P_th = P_th Th^T + P_bg Bg^T + P_S S^T
/// (V_th = Phi_v,theta, ...), each sum over k in order k = 0, 1, ...
TERN_AVX_CLONES
void step_columns(Cov& P, double T, const Mat3& v_th, const Mat3& v_ba, const Mat3& th_th, const Mat3& th_bg, const Mat39& th_sg) {
  constexpr int n = kErrDim;
  auto col = [&P](int c) { return P.col(c).data(); };
  for (int c = 0; c < 3; ++c) {
    double* pc = col(idx::p + c);
    const double* vc = col(idx::v + c);
    for (int i = 0; i < n; ++i) pc[i] = pc[i] + T * vc[i];
  }
  const double *th0 = col(idx::th), *th1 = col(idx::th + 1), *th2 = col(idx::th + 2);
  const double *ba0 = col(idx::ba), *ba1 = col(idx::ba + 1), *ba2 = col(idx::ba + 2);
  for (int c = 0; c < 3; ++c) {
    double* vc = col(idx::v + c);
    const double a0 = v_th(c, 0), a1 = v_th(c, 1), a2 = v_th(c, 2);
    const double b0 = v_ba(c, 0), b1 = v_ba(c, 1), b2 = v_ba(c, 2);
    for (int i = 0; i < n; ++i) vc[i] = vc[i] + (((th0[i] * a0 + th1[i] * a1) + th2[i] * a2) + ((ba0[i] * b0 + ba1[i] * b1) + ba2[i] * b2));
  }
  const double *bg0 = col(idx::bg), *bg1 = col(idx::bg + 1), *bg2 = col(idx::bg + 2);
  const double* sg = col(idx::sg);  // 9 contiguous columns
  alignas(32) double out[3][n];
  for (int c = 0; c < 3; ++c) {
    const double a0 = th_th(c, 0), a1 = th_th(c, 1), a2 = th_th(c, 2);
    const double b0 = th_bg(c, 0), b1 = th_bg(c, 1), b2 = th_bg(c, 2);
    for (int i = 0; i < n; ++i) {
      double s = sg[i] * th_sg(c, 0);
      for (int k = 1; k < 9; ++k) s = s + sg[k * n + i] * th_sg(c, k);
      out[c][i] = (((th0[i] * a0 + th1[i] * a1) + th2[i] * a2) + ((bg0[i] * b0 + bg1[i] * b1) + bg2[i] * b2)) + s;
    }
  }
  for (int c = 0; c < 3; ++c) std::copy(out[c], out[c] + n, col(idx::th + c));
}

/// The error states Phi moves (rows of Phi other than the identity's): p, v, theta, e_gnss, w_d.
constexpr std::array<int, 13> kMoved = {idx::p,      idx::p + 1,  idx::p + 2, idx::v,      idx::v + 1,  idx::v + 2, idx::th,
                                        idx::th + 1, idx::th + 2, idx::eg,    idx::eg + 1, idx::eg + 2, idx::wd};
}  // namespace

void Filter::step_covariance() {
  Pending& f = pending_;
  if (f.samples == 0) return;
  // P <- Phi P Phi^T + Q, Phi = I except its blocks (Pending, filter.hpp) and the Gauss-Markov
  // decays exp(-k T) I (GNSS error) and exp(-T / tau_w) (vertical wind). Phi's rows differ from
  // the identity's only for the 13 states kMoved (set M), so:
  //  1. B = P Phi^T: the columns of M, as column block operations (contiguous, vectorised);
  //  2. Phi B differs from B only on the rows of M; on the columns outside M those rows are
  //     B's columns of M transposed (P' is symmetric and Phi's row there is the identity's);
  //  3. on M x M, Phi B is formed from B's columns of M with Phi's blocks and symmetrised.
  // A few thousand multiply-adds instead of 2 kErrDim^3 for dense products.
  Cov& P = P_;
  // steps 2 and 3 take P's columns for its rows (a reset's blocks may differ by an ulp)
  if (!P_symmetric_) symmetrize(P);
  P_symmetric_ = true;
  const double T = f.dt;
  const double fe = std::exp(-f.gnss_error_k * T), fw = std::exp(-f.vertical_wind_rate * T);
  // 1. Columns (order matters: each block uses the old values of the blocks after it).
  step_columns(P, T, f.v_th, f.v_ba, f.th_th, f.th_bg, f.th_sg);
  P.middleCols<3>(idx::eg) *= fe;
  P.col(idx::wd) *= fw;
  // 2. Rows of M outside M x M: the mirror of the columns.
  Eigen::Matrix<double, kErrDim, 13> B;
  for (int j = 0; j < 13; ++j) B.col(j) = P.col(kMoved[j]);
  for (int j = 0; j < 13; ++j) P.row(kMoved[j]) = B.col(j).transpose();
  // 3. M x M: (Phi B) on the rows of M (in kMoved's order), then symmetrised.
  Eigen::Matrix<double, 13, 13> PB;
  PB.middleRows<3>(0) = B.middleRows<3>(idx::p) + T * B.middleRows<3>(idx::v);
  PB.middleRows<3>(3) =
      B.middleRows<3>(idx::v) + f.v_th.lazyProduct(B.middleRows<3>(idx::th)) + f.v_ba.lazyProduct(B.middleRows<3>(idx::ba));
  PB.middleRows<3>(6) = f.th_th.lazyProduct(B.middleRows<3>(idx::th)) + f.th_bg.lazyProduct(B.middleRows<3>(idx::bg)) +
                        f.th_sg.lazyProduct(B.middleRows<9>(idx::sg));
  PB.middleRows<3>(9) = fe * B.middleRows<3>(idx::eg);
  PB.row(12) = fw * B.row(idx::wd);
  for (int j = 0; j < 13; ++j)
    for (int i = 0; i <= j; ++i) P(kMoved[i], kMoved[j]) = P(kMoved[j], kMoved[i]) = 0.5 * (PB(i, j) + PB(j, i));

  P.diagonal() += f.q;
  f = Pending{};
}

Filter::Decays Filter::decays(const ProcessNoise& noise, double dt) {
  return {std::exp(-noise.gnss_error_k * dt), std::exp(-noise.vertical_wind_rate() * dt),
          1.0 - std::exp(-2.0 * noise.vertical_wind_rate() * dt)};
}

const Filter::Decays& Filter::decays_for(const ProcessNoise& noise, double dt) {
  auto& c = decays_;
  if (dt != c.dt || noise.gnss_error_k != c.gnss_error_k || noise.vertical_wind_time != c.vertical_wind_time) {
    c.dt = dt;
    c.gnss_error_k = noise.gnss_error_k;
    c.vertical_wind_time = noise.vertical_wind_time;
    c.d = decays(noise, dt);
  }
  return c.d;
}

NominalState Filter::propagate_nominal(const NominalState& x, const Vec3& accel, const Vec3& gyro, double dt, double gravity,
                                       const ProcessNoise& noise, const Decays* d) {
  const Decays dd = d != nullptr ? *d : decays(noise, dt);
  NominalState r = x;
  const Vec3 a_n = x.R() * (accel - x.b_a) + Vec3(0.0, 0.0, gravity);
  r.p += x.v * dt + (0.5 * dt * dt) * a_n;
  r.v += a_n * dt;
  r.q = (x.q * quat_exp(x.rate(gyro) * dt)).normalized();
  r.e_gnss *= dd.gnss_error;  // expectations of the Gauss-Markov processes
  r.wind_d *= dd.vertical_wind;
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

ErrVec Filter::process_noise_diagonal(const ProcessNoise& noise, double dt, double load, const Decays* d) {
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
  q(idx::wd) = sw * sw * (d != nullptr ? d->vertical_wind_var : decays(noise, dt).vertical_wind_var);
  return q;
}

}  // namespace tern::ekf
