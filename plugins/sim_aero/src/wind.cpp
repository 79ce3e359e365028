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

double Dryden::second_order(Eigen::Vector2d& x, double sigma, double L, double Va, double dt, double n) {
  // Controllable canonical form of K (s + a/sqrt3)/(s + a)^2, a = Va/L, K = sigma sqrt(3 a),
  // driven by unit-intensity white noise (increment sqrt(dt) n), semi-implicit Euler.
  const double a = Va / L;
  x.y() += dt * (-a * a * x.x() - 2.0 * a * x.y()) + std::sqrt(dt) * n;
  x.x() += dt * x.y();
  return sigma * std::sqrt(3.0 * a) * (a / std::sqrt(3.0) * x.x() + x.y());
}

const Eigen::Vector3d& Dryden::step(double dt, double Va, std::mt19937_64& rng) {
  const double n1 = n_(rng), n2 = n_(rng), n3 = n_(rng);  // drawn always: the stream stays aligned
  if (p_.sigma_u == 0 && p_.sigma_v == 0 && p_.sigma_w == 0) {
    out_.setZero();
    return out_;
  }
  Va = std::max(Va, 1.0);
  const double au = Va / p_.L_u;
  const double phi = std::exp(-au * dt);
  u_ = phi * u_ + p_.sigma_u * std::sqrt(1.0 - phi * phi) * n1;
  out_.x() = u_;
  out_.y() = second_order(xv_, p_.sigma_v, p_.L_v, Va, dt, n2);
  out_.z() = second_order(xw_, p_.sigma_w, p_.L_w, Va, dt, n3);
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

Eigen::Vector3d GustField::step(double t, std::mt19937_64& rng) {
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
