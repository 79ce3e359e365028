// core/apps/sysid/output_error.cpp: the output-error refinement of the rotational axes (output_error.hpp).
#include "sysid/output_error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <fmt/format.h>
#include <unsupported/Eigen/LevenbergMarquardt>

#include "tern/aero/model.hpp"
#include "tern/math.hpp"

namespace tern::core::sysid {

namespace {

using M = AeroCoefficients;
using Member = double M::*;

const std::map<std::string, Member>& moment_table() {
  static const std::map<std::string, Member> table = {{"C_ell_0", &M::C_ell_0},
                                                      {"C_ell_beta", &M::C_ell_beta},
                                                      {"C_ell_p", &M::C_ell_p},
                                                      {"C_ell_r", &M::C_ell_r},
                                                      {"C_ell_delta_a", &M::C_ell_delta_a},
                                                      {"C_ell_delta_r", &M::C_ell_delta_r},
                                                      {"C_m_0", &M::C_m_0},
                                                      {"C_m_alpha", &M::C_m_alpha},
                                                      {"C_m_q", &M::C_m_q},
                                                      {"C_m_delta_e", &M::C_m_delta_e},
                                                      {"C_n_0", &M::C_n_0},
                                                      {"C_n_beta", &M::C_n_beta},
                                                      {"C_n_p", &M::C_n_p},
                                                      {"C_n_r", &M::C_n_r},
                                                      {"C_n_delta_a", &M::C_n_delta_a},
                                                      {"C_n_delta_r", &M::C_n_delta_r}};
  return table;
}

/// One free parameter: a moment coefficient, or the delay of one surface's commands (surface 0
/// aileron, 1 elevator, 2 rudder; s, on top of the delay the data was loaded with).
struct Param {
  Member member = nullptr;
  int surface = -1;
};

Param param_of(const std::string& name) {
  for (int s = 0; s < 3; ++s)
    if (name == kDelayNames[static_cast<std::size_t>(s)]) return {nullptr, s};
  return {moment_coefficient(name), -1};
}

/// The weights of a fractional delay of f samples (0 <= f < 1) by a Lanczos-windowed sinc of
/// kLanczosLobes lobes (shift_run: the tap k - whole - i weighs w[i + kLanczosLobes - 1], i from
/// 1 - kLanczosLobes to kLanczosLobes). Why not linear interpolation between samples, the former
/// shift: the commands are low-passed at filter_hz (10 Hz) before the output error samples them at
/// 50 Hz, and linear interpolation passed a 5-Hz component at 0.95 of its amplitude half a sample
/// off and whole at a whole sample; the fit's cost then favours delays near whole samples of the
/// series as loaded. The Anaconda's foreign-log bench flight (seed 2, true prior): the aileron's delay
/// 1.0 ms with linear interpolation, 1.9 ms with this kernel; the coefficients come right at 3.7-4 ms.
/// Duchon, "Lanczos filtering in one and two dimensions", J. Appl. Meteor. 18 (1979).
constexpr int kLanczosLobes = 4;
std::array<double, 2 * kLanczosLobes> lanczos_weights(double f) {
  auto sinc = [](double v) { return std::abs(v) < 1e-12 ? 1.0 : std::sin(kPi * v) / (kPi * v); };
  std::array<double, 2 * kLanczosLobes> w{};
  double sum = 0.0;
  for (int i = 1 - kLanczosLobes; i <= kLanczosLobes; ++i) {
    const double z = static_cast<double>(i) - f;
    w[static_cast<std::size_t>(i + kLanczosLobes - 1)] = sinc(z) * sinc(z / kLanczosLobes);
    sum += w[static_cast<std::size_t>(i + kLanczosLobes - 1)];
  }
  for (double& v : w) v /= sum;  // a constant passes unchanged
  return w;
}

}  // namespace

void shift_run(const std::vector<double>& t, const std::vector<double>& x, double tau, std::size_t b, std::size_t e,
               std::vector<double>& out) {
  if (e - b < 2) {
    for (std::size_t k = b; k < e; ++k) out[k] = x[k];
    return;
  }
  const double samples = tau / ((t[e - 1] - t[b]) / static_cast<double>(e - 1 - b));
  if (!std::isfinite(samples)) throw std::invalid_argument("shift_run: a run whose times do not increase, or a delay that is not a number");
  const double whole = std::floor(samples);
  const auto w = lanczos_weights(samples - whole);
  const auto first = static_cast<long>(b), last = static_cast<long>(e) - 1, back = static_cast<long>(whole);
  for (std::size_t k = b; k < e; ++k) {
    double sum = 0.0;
    for (int i = 1 - kLanczosLobes; i <= kLanczosLobes; ++i) {
      const long j = std::clamp(static_cast<long>(k) - back - i, first, last);
      sum += w[static_cast<std::size_t>(i + kLanczosLobes - 1)] * x[static_cast<std::size_t>(j)];
    }
    out[k] = sum;
  }
}

namespace {

/// The book's Gamma coefficients (eq. 3.13, tern/aircraft.hpp, as the uavbook model, tern/aero/model.hpp, uses them) and 1 / J_y.
struct Gammas : InertiaGammas {
  double inv_Jy;
};

Gammas gammas_of(const Aircraft& ac) { return {inertia_gammas(ac), 1.0 / ac.Jy}; }

/// One sample's inputs, the dimensional factors precomputed (interpolated linearly between samples).
struct Input {
  double qSb = 0, qSc = 0;  ///< qbar S b, qbar cos^2(beta) S c, N m
  double kb = 0, kc = 0;    ///< b / (2 Va), c / (2 V_xz), s
  double alpha = 0, beta = 0, da = 0, de = 0, dr = 0, Q_p = 0;
  Eigen::Vector3d w = Eigen::Vector3d::Zero();  ///< measured rates
};

Input lerp(const Input& a, const Input& b, double s) {
  auto l = [s](double x, double y) { return x + s * (y - x); };
  Input o;
  o.qSb = l(a.qSb, b.qSb), o.qSc = l(a.qSc, b.qSc), o.kb = l(a.kb, b.kb), o.kc = l(a.kc, b.kc);
  o.alpha = l(a.alpha, b.alpha), o.beta = l(a.beta, b.beta), o.da = l(a.da, b.da), o.de = l(a.de, b.de), o.dr = l(a.dr, b.dr);
  o.Q_p = l(a.Q_p, b.Q_p);
  o.w = a.w + s * (b.w - a.w);
  return o;
}

/// The rates' derivative (header's moment equations) at rates w: only the integrated ones (the
/// pitch axis's q', or the lateral axes' p' and r'), the others 0 (the simulation takes them as
/// measured, RateModel::simulate).
Eigen::Vector3d rate_derivative(const Gammas& G, const M& A, const Input& u, const Eigen::Vector3d& w, bool pitch) {
  const double p = w.x(), q = w.y(), r = w.z();
  if (pitch) {
    const double m = u.qSc * (A.C_m_0 + A.C_m_alpha * u.alpha + A.C_m_delta_e * u.de + u.kc * A.C_m_q * q);
    return {0.0, G.G5 * p * r - G.G6 * (p * p - r * r) + m * G.inv_Jy, 0.0};
  }
  const double l = u.qSb * (A.C_ell_0 + A.C_ell_beta * u.beta + A.C_ell_delta_a * u.da + A.C_ell_delta_r * u.dr +
                            u.kb * (A.C_ell_p * p + A.C_ell_r * r)) -
                   u.Q_p;
  const double n =
      u.qSb * (A.C_n_0 + A.C_n_beta * u.beta + A.C_n_delta_a * u.da + A.C_n_delta_r * u.dr + u.kb * (A.C_n_p * p + A.C_n_r * r));
  return {G.G1 * p * q - G.G2 * q * r + G.G3 * l + G.G4 * n, 0.0, G.G7 * p * q - G.G1 * q * r + G.G4 * l + G.G8 * n};
}

/// The simulation: inputs per sample, which rates are integrated, the held coefficients.
class RateModel {
 public:
  RateModel(const RateData& d, const Aircraft& ac, const M& base, RateAxes axes, const std::vector<Param>& free, bool hold_commands,
            const std::array<double, 3>& shift = {0.0, 0.0, 0.0})
      : d_(d), G_(gammas_of(ac)), base_(base), free_(free), shift_(shift), hold_commands_(hold_commands) {
    for (std::size_t k = 0; k < d.size(); ++k) {
      Input u;
      const double qbar = 0.5 * ac.rho * d.Va[k] * d.Va[k], cb = std::cos(d.beta[k]);
      u.qSb = qbar * ac.S * ac.b, u.qSc = qbar * cb * cb * ac.S * ac.c;
      u.kb = ac.b / (2.0 * d.Va[k]), u.kc = ac.c / (2.0 * d.Va[k] * cb);
      u.alpha = d.alpha[k], u.beta = d.beta[k], u.da = d.delta_a[k], u.de = d.delta_e[k], u.dr = d.delta_r[k], u.Q_p = d.Q_p[k];
      u.w = {d.p[k], d.q[k], d.r[k]};
      in_.push_back(u);
    }
    midpoints(in_, mid_);
    pitch_ = axes == RateAxes::pitch;
    outputs_ = pitch_ ? std::vector<int>{1} : std::vector<int>{0, 2};
    for (const auto& [b, e] : d.windows) residual_rows_ += e - b - 1;
    for (const auto& w : d.windows)  // runs of consecutive windows: a shifted command reaches back across their joins
      if (!runs_.empty() && runs_.back().second == w.first)
        runs_.back().second = w.second;
      else
        runs_.push_back(w);
  }
  const std::vector<int>& outputs() const { return outputs_; }
  Eigen::Index ny() const { return static_cast<Eigen::Index>(outputs_.size()); }
  /// Residual samples per output (every window sample but its first).
  Eigen::Index rows() const { return static_cast<Eigen::Index>(residual_rows_); }

  M coefficients(const Eigen::VectorXd& theta) const {
    M A = base_;
    for (std::size_t j = 0; j < free_.size(); ++j)
      if (free_[j].member) A.*free_[j].member = theta[static_cast<Eigen::Index>(j)];
    return A;
  }

  /// s, aileron, elevator, rudder: the delays theta carries (the held shift for those it does not)
  std::array<double, 3> delays(const Eigen::VectorXd& theta) const {
    std::array<double, 3> tau = shift_;
    for (std::size_t j = 0; j < free_.size(); ++j)
      if (free_[j].surface >= 0) tau[static_cast<std::size_t>(free_[j].surface)] = theta[static_cast<Eigen::Index>(j)];
    return tau;
  }

  /// Simulated rates at every sample (measured outside the windows), each surface's commands
  /// acting `tau` later than the data has them.
  std::vector<Eigen::Vector3d> simulate(const M& A, const std::array<double, 3>& tau = {0.0, 0.0, 0.0}) const {
    const bool shifted = tau != std::array<double, 3>{0.0, 0.0, 0.0};
    if (shifted) delay_into(tau, scratch_);
    const std::vector<Input>& in = shifted ? scratch_ : in_;
    const std::vector<Input>& mid = shifted ? scratch_mid_ : mid_;
    std::vector<Eigen::Vector3d> out(in.size());
    for (std::size_t k = 0; k < in.size(); ++k) out[k] = in[k].w;
    // the integrated rates from x, the others measured at the stage's time
    const auto at = [this](const Input& u, const Eigen::Vector3d& x) -> Eigen::Vector3d {
      return pitch_ ? Eigen::Vector3d(u.w.x(), x.y(), u.w.z()) : Eigen::Vector3d(x.x(), u.w.y(), x.z());
    };
    Input held1, heldm;  // hold_commands_: the next sample's and the midpoint's inputs with sample k's commands
    for (const auto& [b, e] : d_.windows) {
      Eigen::Vector3d w = in[b].w;
      for (std::size_t k = b; k + 1 < e; ++k) {
        const double h = d_.t[k + 1] - d_.t[k];
        const Input& u0 = in[k];
        const Input* u1 = &in[k + 1];
        const Input* um = &mid[k];
        if (hold_commands_) {  // the commands of sample k over the whole interval
          held1 = *u1, heldm = *um;
          heldm.da = held1.da = u0.da, heldm.de = held1.de = u0.de, heldm.dr = held1.dr = u0.dr;
          u1 = &held1, um = &heldm;
        }
        const Eigen::Vector3d k1 = rate_derivative(G_, A, u0, at(u0, w), pitch_);
        const Eigen::Vector3d k2 = rate_derivative(G_, A, *um, at(*um, w + 0.5 * h * k1), pitch_);
        const Eigen::Vector3d k3 = rate_derivative(G_, A, *um, at(*um, w + 0.5 * h * k2), pitch_);
        const Eigen::Vector3d k4 = rate_derivative(G_, A, *u1, at(*u1, w + h * k3), pitch_);
        w = at(*u1, w + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4));
        out[k + 1] = w;
      }
    }
    return out;
  }

  /// Measured less simulated rates, rows (sample, output) sample-major.
  Eigen::VectorXd residuals(const Eigen::VectorXd& theta) const {
    const std::vector<Eigen::Vector3d> y = simulate(coefficients(theta), delays(theta));
    Eigen::VectorXd v(rows() * ny());
    Eigen::Index i = 0;
    for (const auto& [b, e] : d_.windows)
      for (std::size_t k = b + 1; k < e; ++k)
        for (const int a : outputs_) v[i++] = in_[k].w[a] - y[k][a];
    return v;
  }

  /// The outputs' measured values in the residuals' order.
  Eigen::VectorXd measured() const {
    Eigen::VectorXd z(rows() * ny());
    Eigen::Index i = 0;
    for (const auto& [b, e] : d_.windows)
      for (std::size_t k = b + 1; k < e; ++k)
        for (const int a : outputs_) z[i++] = in_[k].w[a];
    return z;
  }

 private:
  /// The inputs with each surface's commands shifted by its delay over every run of windows, into
  /// `in`: a copy of in_ taken once, whose command fields are rewritten for the surfaces shifted
  /// now and restored for those shifted last time only.
  void delay_into(const std::array<double, 3>& tau, std::vector<Input>& in) const {
    bool changed = in.size() != in_.size();
    if (changed) in = in_, scratch_tau_ = {0.0, 0.0, 0.0};
    const std::array<const std::vector<double>*, 3> commands = {&d_.delta_a, &d_.delta_e, &d_.delta_r};
    const std::array<double Input::*, 3> fields = {&Input::da, &Input::de, &Input::dr};
    shifted_.resize(in_.size());
    for (std::size_t s = 0; s < 3; ++s) {
      if (tau[s] == scratch_tau_[s]) continue;
      if (tau[s] == 0.0) {
        for (std::size_t k = 0; k < in.size(); ++k) in[k].*fields[s] = in_[k].*fields[s];
      } else {
        for (const auto& [b, e] : runs_) shift_run(d_.t, *commands[s], tau[s], b, e, shifted_);
        for (const auto& [b, e] : runs_)
          for (std::size_t k = b; k < e; ++k) in[k].*fields[s] = shifted_[k];
      }
      scratch_tau_[s] = tau[s], changed = true;
    }
    if (!changed) return;  // scratch_ and scratch_mid_ hold these delays' inputs
    // the flow angles' parts of the commands move with them (RateData)
    if (d_.beta_per_delta_a != 0.0 || d_.beta_per_delta_r != 0.0 || d_.alpha_per_delta_e != 0.0)
      for (std::size_t k = 0; k < in.size(); ++k) {
        in[k].beta = in_[k].beta + d_.beta_per_delta_a * (in[k].da - in_[k].da) + d_.beta_per_delta_r * (in[k].dr - in_[k].dr);
        in[k].alpha = in_[k].alpha + d_.alpha_per_delta_e * (in[k].de - in_[k].de);
      }
    midpoints(in, scratch_mid_);
  }

  /// mid[k]: the inputs halfway between samples k and k + 1 (RK4's middle stages), taken once per
  /// set of inputs rather than at every step of every simulation.
  static void midpoints(const std::vector<Input>& in, std::vector<Input>& mid) {
    mid.resize(in.empty() ? 0 : in.size() - 1);
    for (std::size_t k = 0; k + 1 < in.size(); ++k) mid[k] = lerp(in[k], in[k + 1], 0.5);
  }

  const RateData& d_;
  Gammas G_;
  M base_;
  std::vector<Param> free_;
  std::array<double, 3> shift_;
  std::vector<Input> in_;
  std::vector<Input> mid_;                       ///< in_'s midpoints (midpoints)
  mutable std::vector<Input> scratch_;           ///< the shifted inputs of the last simulation (no allocation per simulation)
  mutable std::vector<Input> scratch_mid_;       ///< scratch_'s midpoints
  mutable std::array<double, 3> scratch_tau_{};  ///< s, the shifts scratch_ holds
  mutable std::vector<double> shifted_;          ///< one surface's shifted commands
  std::vector<std::pair<std::size_t, std::size_t>> runs_;
  std::vector<int> outputs_;
  std::size_t residual_rows_ = 0;
  bool hold_commands_ = false;
  bool pitch_ = false;  ///< the pitch rate integrated (else roll and yaw)
};

/// The residuals v (rows x ny, sample-major) as a matrix.
Eigen::MatrixXd as_rows(const Eigen::VectorXd& v, Eigen::Index ny) {
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(v.data(), v.size() / ny, ny);
}

Eigen::MatrixXd covariance(const Eigen::VectorXd& v, Eigen::Index ny) {
  const Eigen::MatrixXd V = as_rows(v, ny);
  return V.transpose() * V / static_cast<double>(V.rows());
}

/// Whitened residuals L^-1 v_k (R = L L^T) and their central-difference Jacobian, for Eigen's LM.
struct Whitened : Eigen::DenseFunctor<double> {
  Whitened(const RateModel& model, const Eigen::MatrixXd& R, const Eigen::VectorXd& scale, int& evaluations)
      : Eigen::DenseFunctor<double>(static_cast<int>(scale.size()), static_cast<int>(model.rows() * model.ny())),
        model_(model),
        Linv_(R.llt().matrixL().solve(Eigen::MatrixXd::Identity(R.rows(), R.cols()))),
        scale_(scale),
        evaluations_(evaluations) {}

  int operator()(const Eigen::VectorXd& theta, Eigen::VectorXd& f) const {
    ++evaluations_;
    f = whiten(model_.residuals(theta));
    return f.allFinite() ? 0 : -1;
  }

  int df(const Eigen::VectorXd& theta, Eigen::MatrixXd& J) const {
    J.resize(values(), inputs());
    for (Eigen::Index j = 0; j < theta.size(); ++j) {
      const double h = 1e-4 * scale_[j];
      Eigen::VectorXd up = theta, down = theta;
      up[j] += h, down[j] -= h;
      evaluations_ += 2;
      J.col(j) = (whiten(model_.residuals(up)) - whiten(model_.residuals(down))) / (2.0 * h);
    }
    return J.allFinite() ? 0 : -1;
  }

  /// Each sample's ny outputs times L^-1 (written out: Eigen's product of a dynamic matrix and a
  /// segment allocated a temporary per sample, a tenth of a sysid run).
  Eigen::VectorXd whiten(const Eigen::VectorXd& v) const {
    const Eigen::Index ny = model_.ny();
    Eigen::VectorXd out(v.size());
    for (Eigen::Index i = 0; i < v.size(); i += ny)
      for (Eigen::Index a = 0; a < ny; ++a) {
        double s = 0.0;
        for (Eigen::Index b = 0; b < ny; ++b) s += Linv_(a, b) * v[i + b];
        out[i + a] = s;
      }
    return out;
  }

 private:
  const RateModel& model_;
  Eigen::MatrixXd Linv_;
  Eigen::VectorXd scale_;
  int& evaluations_;
};

/// The three bounds' largest (header): white Cramer-Rao, Morelli-Klein with the residual
/// autocorrelation up to max_lag samples, and each window's residuals as one batch. J is the
/// whitened residuals' Jacobian, e the whitened residuals, both sample-major with ny outputs.
void bounds(const Eigen::MatrixXd& J, const Eigen::VectorXd& e, Eigen::Index ny, const RateData& d, Eigen::Index max_lag,
            OutputErrorFit& fit) {
  const Eigen::Index n = e.size() / ny, np = J.cols();
  std::vector<Eigen::MatrixXd> G(static_cast<std::size_t>(ny));  // per output: n x np
  for (Eigen::Index a = 0; a < ny; ++a) {
    G[static_cast<std::size_t>(a)].resize(n, np);
    for (Eigen::Index k = 0; k < n; ++k) G[static_cast<std::size_t>(a)].row(k) = J.row(k * ny + a);
  }
  const Eigen::MatrixXd E = as_rows(e, ny);
  const Eigen::MatrixXd Minv = (J.transpose() * J).inverse();
  fit.std_error_white = Minv.diagonal().cwiseMax(0.0).cwiseSqrt();
  // mk = C_0 + sum over lags >= 1 of (C_lag + C_lag^T), C_lag = sum_ab Ree_lag(a, b) G_a[0, n - lag)^T
  // G_b[lag, n): with S = sum over lags >= 0 of C_lag = sum_ab G_a^T H_ab, H_ab[k] = sum_lag
  // Ree_lag(a, b) G_b[k + lag] (each G_b filtered once by the lags' weights, not multiplied out per
  // lag), mk = S + S^T - C_0 (C_0 symmetric)
  const Eigen::Index lags = std::min(max_lag, n - 1);
  std::vector<Eigen::MatrixXd> Ree(static_cast<std::size_t>(lags + 1));
  for (Eigen::Index lag = 0; lag <= lags; ++lag)
    Ree[static_cast<std::size_t>(lag)] = E.topRows(n - lag).transpose() * E.bottomRows(n - lag) / static_cast<double>(n);
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(np, np), C0 = Eigen::MatrixXd::Zero(np, np), H(n, np);
  for (Eigen::Index a = 0; a < ny; ++a)
    for (Eigen::Index b = 0; b < ny; ++b) {
      const Eigen::MatrixXd& Ga = G[static_cast<std::size_t>(a)];
      const Eigen::MatrixXd& Gb = G[static_cast<std::size_t>(b)];
      H.setZero();
      for (Eigen::Index lag = 0; lag <= lags; ++lag)
        H.topRows(n - lag) += Ree[static_cast<std::size_t>(lag)](a, b) * Gb.bottomRows(n - lag);
      S += Ga.transpose() * H;
      C0 += Ree[0](a, b) * Ga.transpose() * Gb;
    }
  const Eigen::MatrixXd mk = S + S.transpose() - C0;
  Eigen::MatrixXd batches = Eigen::MatrixXd::Zero(np, np);
  Eigen::Index at = 0;
  for (const auto& [b, end] : d.windows) {
    const auto rows = static_cast<Eigen::Index>(end - b - 1);
    const Eigen::VectorXd s = J.middleRows(at * ny, rows * ny).transpose() * e.segment(at * ny, rows * ny);
    batches += s * s.transpose();
    at += rows;
  }
  const Eigen::VectorXd se_mk = (Minv * mk * Minv).diagonal().cwiseMax(0.0).cwiseSqrt();
  const Eigen::VectorXd se_batch = (Minv * batches * Minv).diagonal().cwiseMax(0.0).cwiseSqrt();
  fit.std_error = fit.std_error_white.cwiseMax(se_mk).cwiseMax(se_batch);
}

Eigen::VectorXd rms_per_output(const Eigen::VectorXd& v, Eigen::Index ny) {
  const Eigen::MatrixXd V = as_rows(v, ny);
  return (V.colwise().squaredNorm().transpose() / static_cast<double>(V.rows())).cwiseSqrt();
}

}  // namespace

double AeroCoefficients::*moment_coefficient(const std::string& name) {
  const auto it = moment_table().find(name);
  if (it == moment_table().end()) throw std::invalid_argument(fmt::format("output error: '{}' is not a moment coefficient", name));
  return it->second;
}

RateData rate_data(const AeroSamples& a, const std::vector<double>& alpha, const std::vector<double>& beta,
                   const std::vector<std::pair<std::size_t, std::size_t>>& segments, const Aircraft& prior, double window_s) {
  if (alpha.size() != a.size() || beta.size() != a.size())
    throw std::invalid_argument("rate_data: alpha, beta and the samples differ in length");
  if (!(window_s > 0.0)) throw std::invalid_argument("rate_data: window_s must be > 0");
  RateData d;
  d.t = a.t, d.Va = a.Va, d.alpha = alpha, d.beta = beta;
  d.delta_a = a.delta_a, d.delta_e = a.delta_e, d.delta_r = a.delta_r;
  d.p = a.p, d.q = a.q, d.r = a.r;
  for (std::size_t k = 0; k < a.size(); ++k) d.Q_p.push_back(sim::propulsion(prior, a.Va[k] * std::cos(beta[k]), a.delta_t[k]).Q_p);
  for (const auto& [b, e] : segments) {
    std::size_t w = b;
    for (std::size_t k = b + 1; k < e; ++k)
      if (a.t[k] - a.t[w] >= window_s) {
        d.windows.emplace_back(w, k);
        w = k;
      }
    if (e - w >= 3 && a.t[e - 1] - a.t[w] >= 0.5 * window_s)
      d.windows.emplace_back(w, e);
    else if (!d.windows.empty() && d.windows.back().second == w)
      d.windows.back().second = e;
  }
  return d;
}

std::vector<Eigen::Vector3d> simulate_rates(const RateData& d, const Aircraft& prior, const AeroCoefficients& aero, RateAxes axes) {
  return RateModel(d, prior, aero, axes, {}, false).simulate(aero);
}

OutputErrorFit output_error(const RateData& d, const Aircraft& prior, const AeroCoefficients& start, RateAxes axes,
                            const std::vector<std::string>& free, const OutputErrorOptions& o) {
  for (const auto* v : {&d.Va, &d.alpha, &d.beta, &d.delta_a, &d.delta_e, &d.delta_r, &d.Q_p, &d.p, &d.q, &d.r})
    if (v->size() != d.size()) throw std::invalid_argument("output error: the data's channels differ in length");
  std::size_t usable = 0;
  for (const auto& [b, e] : d.windows) {
    if (e > d.size() || b >= e) throw std::invalid_argument("output error: a window outside the data");
    usable += e - b >= 3 ? 1 : 0;
  }
  if (usable == 0) throw std::invalid_argument("output error: no window of 3 samples or more");
  std::vector<Param> params;
  OutputErrorFit fit;
  fit.axes = axes, fit.names = free;
  fit.start.resize(static_cast<Eigen::Index>(free.size()));
  for (std::size_t j = 0; j < free.size(); ++j) {
    params.push_back(param_of(free[j]));
    const bool pitch = params.back().member ? free[j].rfind("C_m_", 0) == 0 : params.back().surface == 1;
    if (pitch != (axes == RateAxes::pitch))
      throw std::invalid_argument(
          fmt::format("output error: {} is not in the {} axes' moments", free[j], axes == RateAxes::pitch ? "pitch" : "lateral"));
    const int surface = params.back().surface;
    fit.start[static_cast<Eigen::Index>(j)] =
        params.back().member ? start.*params.back().member : o.command_shift_s[static_cast<std::size_t>(surface)];
  }
  const RateModel model(d, prior, start, axes, params, o.hold_commands, o.command_shift_s);
  const Eigen::Index ny = model.ny();
  Eigen::VectorXd theta = fit.start;
  Eigen::VectorXd scale = theta.cwiseAbs().cwiseMax(1e-3);
  for (std::size_t j = 0; j < params.size(); ++j)  // a delay's difference step: 1e-4 of 10 ms
    if (params[j].surface >= 0) scale[static_cast<Eigen::Index>(j)] = 0.01;
  Eigen::VectorXd v = model.residuals(theta);
  fit.rms_start = rms_per_output(v, ny);
  Eigen::MatrixXd R = covariance(v, ny);
  Eigen::MatrixXd J;
  const int per_step = 1 + static_cast<int>(params.size());  // a residual and a finite-difference Jacobian
  for (fit.relaxations = 1; fit.relaxations <= std::max(1, o.max_relaxations); ++fit.relaxations) {
    const int left = o.max_simulations - fit.evaluations;
    if (fit.relaxations > 1 && left < per_step) {
      fit.budget_spent = true;
      --fit.relaxations;  // this one not made
      break;
    }
    Whitened f(model, R, scale, fit.evaluations);
    Eigen::LevenbergMarquardt<Whitened> lm(f);
    lm.setMaxfev(std::max(1, std::min(o.max_evaluations, left / per_step)));
    const Eigen::VectorXd before = theta;
    lm.minimize(theta);
    v = model.residuals(theta);
    R = covariance(v, ny);
    Whitened g(model, R, scale, fit.evaluations);
    g.df(theta, J);
    const Eigen::VectorXd se = (J.transpose() * J).inverse().diagonal().cwiseMax(0.0).cwiseSqrt();
    if (((theta - before).cwiseAbs().array() <= o.theta_tolerance * se.array()).all()) break;
  }
  fit.relaxations = std::min(fit.relaxations, std::max(1, o.max_relaxations));
  fit.theta = theta;
  fit.residual_covariance = R;
  fit.rms = rms_per_output(v, ny);
  fit.samples = static_cast<std::size_t>(model.rows());
  const Eigen::MatrixXd Z = as_rows(model.measured(), ny);
  const Eigen::MatrixXd V = as_rows(v, ny);
  fit.r_squared.resize(ny);
  for (Eigen::Index a = 0; a < ny; ++a)
    fit.r_squared[a] = 1.0 - V.col(a).squaredNorm() / (Z.col(a).array() - Z.col(a).mean()).matrix().squaredNorm();
  Whitened white(model, R, scale, fit.evaluations);
  const auto first = std::find_if(d.windows.begin(), d.windows.end(), [](const auto& w) { return w.second - w.first >= 3; });
  const double dt = d.t[first->first + 1] - d.t[first->first];
  bounds(J, white.whiten(v), ny, d, static_cast<Eigen::Index>(std::lround(o.max_lag_s / dt)), fit);
  return fit;
}

}  // namespace tern::core::sysid
