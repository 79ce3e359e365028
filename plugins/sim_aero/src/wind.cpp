// Wind model: Dryden turbulence and 1-cosine gusts (see wind.hpp).
#include "tern_sim_aero/wind.hpp"

#include <algorithm>
#include <cmath>
#include "tern/math.hpp"

namespace tern::sim {
namespace {
using tern::kPi;
}

DrydenParams dryden_preset(const std::string& level) {
  DrydenParams p;  // low altitude (50 m) length scales
  if (level == "none") return p;
  if (level == "light") {
    p.sigma_u = p.sigma_v = 1.06;
    p.sigma_w = 0.7;
    return p;
  }
  if (level == "moderate") {
    p.sigma_u = p.sigma_v = 2.12;
    p.sigma_w = 1.4;
    return p;
  }
  throw std::invalid_argument("turbulence level '" + level + "' is not one of none, light, moderate");
}

namespace {
// MIL-F-8785C's low-altitude factor 0.177 + 0.000823 h (h in ft).
double mil_k(double h_m) { return 0.177 + 0.000823 * h_m / 0.3048; }
// a, or the smaller of a and cap, by the weight g in [0, 1].
double capped(double a, double cap, double g) { return (1.0 - g) * a + g * std::min(a, cap); }
}  // namespace

DrydenParams dryden_at_height(const DrydenParams& p, double h, double W) {
  if (!(h < kDrydenTableHeight)) return p;  // the book's table (NaN too: no silent change)
  const double hc = std::max(h, kDrydenMinHeight);
  const double k = mil_k(hc), k50 = mil_k(kDrydenTableHeight);
  const double s_l = hc / kDrydenTableHeight;        // L_w = h
  const double s_uv = s_l * std::pow(k50 / k, 1.2);  // L_u = h / k^1.2
  const double s_sigma = std::pow(k50 / k, 0.4);     // sigma_u = sigma_w / k^0.4
  // the weight of the wind's cap: 1 at and below 10 ft, 0 at 50 m, linear in log height
  const double g = std::clamp(std::log(kDrydenTableHeight / hc) / std::log(kDrydenTableHeight / kDrydenGroundHeight), 0.0, 1.0);
  const double w_sigma = 0.1 * W, uv_sigma = w_sigma / std::pow(k, 0.4);  // MIL, W taken as W_20
  DrydenParams q = p;
  q.L_u = p.L_u * s_uv;
  q.L_v = p.L_v * s_uv;
  q.L_w = p.L_w * s_l;
  q.sigma_u = capped(p.sigma_u * s_sigma, uv_sigma, g);
  q.sigma_v = capped(p.sigma_v * s_sigma, uv_sigma, g);
  q.sigma_w = capped(p.sigma_w, w_sigma, g);
  return q;
}

double Dryden::second_order(Eigen::Vector2d& x, double sigma, double L, double Va, double dt, double n) {
  // K (s + a/sqrt3)/(s + a)^2, a = Va/L, K = sigma sqrt(3 a), driven by unit-intensity white
  // noise, in eddy time tau = a t with the states normalised (wind.hpp): x'' + 2 x' + x = w(tau),
  // output sigma (x + sqrt3 x'), each state of a variance that does not depend on a. For a
  // constant a this is the controllable canonical form in t with x = a^1.5 x_t, x' = a^0.5 x_t'
  // (the same filter and the same semi-implicit Euler step: stable for a dt < 0.83, step()
  // keeps a dt <= 0.5). In t the canonical state x_t has a variance 1/(4 a^3): when a grew (the
  // length scale shrinking near the ground, the airspeed rising) the output sigma a^1.5 x_t grew
  // with it, and with the airspeed it pushed up, without bound (issue: a terminated glide's
  // gust reached 10 km/s at 0.6 m and the simulation diverged).
  const double dtau = Va / L * dt;
  x.y() += dtau * (-x.x() - 2.0 * x.y()) + std::sqrt(dtau) * n;
  x.x() += dtau * x.y();
  return sigma * (x.x() + std::sqrt(3.0) * x.y());
}

const Eigen::Vector3d& Dryden::step(double dt, double Va, double h, double W, Rng& rng) {
  const double n1 = n_(rng), n2 = n_(rng), n3 = n_(rng);  // drawn always: the stream stays aligned
  if (p_.sigma_u == 0 && p_.sigma_v == 0 && p_.sigma_w == 0) {
    out_.setZero();
    return out_;
  }
  Va = std::max(Va, 1.0);
  DrydenParams p = dryden_at_height(p_, h, W);
  const double L_min = 2.0 * Va * dt;  // a dt <= 0.5: the second-order update stays stable
  p.L_u = std::max(p.L_u, L_min);
  p.L_v = std::max(p.L_v, L_min);
  p.L_w = std::max(p.L_w, L_min);
  const double au = Va / p.L_u;
  const double phi = std::exp(-au * dt);
  u_ = phi * u_ + p.sigma_u * std::sqrt(1.0 - phi * phi) * n1;
  out_.x() = u_;
  out_.y() = second_order(xv_, p.sigma_v, p.L_v, Va, dt, n2);
  out_.z() = second_order(xw_, p.sigma_w, p.L_w, Va, dt, n3);
  return out_;
}

Eigen::Vector3d CosineGust::at(double t) const {
  if (t < start || t > start + duration) return Eigen::Vector3d::Zero();
  return 0.5 * amplitude * (1.0 - std::cos(2.0 * kPi * (t - start) / duration));
}

void GustField::set_random(double rate, double max_amplitude, double min_duration, double max_duration) {
  rate_ = rate;
  max_amp_ = max_amplitude;
  min_dur_ = min_duration;
  max_dur_ = std::max(max_duration, min_duration);
  next_random_ = -1;
}

Eigen::Vector3d GustField::step(double t, Rng& rng) {
  if (rate_ > 0 && max_amp_ > 0) {
    std::exponential_distribution<double> gap(rate_);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    if (next_random_ < 0) next_random_ = t + gap(rng);
    while (t >= next_random_) {
      CosineGust g;
      g.start = next_random_;
      g.duration = min_dur_ + (max_dur_ - min_dur_) * u01(rng);
      const double dir = 2.0 * kPi * u01(rng);
      const double amp = max_amp_ * u01(rng);
      g.amplitude = Eigen::Vector3d(amp * std::cos(dir), amp * std::sin(dir), 0.0);
      gusts_.push_back(g);
      next_random_ += gap(rng);
    }
    // Forget random gusts that are over (scheduled ones are kept for reset()).
    gusts_.erase(std::remove_if(gusts_.begin() + static_cast<std::ptrdiff_t>(scheduled_), gusts_.end(),
                                [t](const CosineGust& g) { return t > g.start + g.duration; }),
                 gusts_.end());
  }
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& g : gusts_) sum += g.at(t);
  return sum;
}

}  // namespace tern::sim
