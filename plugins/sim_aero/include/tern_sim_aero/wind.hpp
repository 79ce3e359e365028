// tern_sim_aero/wind.hpp: wind model (Beard & McLain, sec. 4.4): steady wind in NED, Dryden
// turbulence in body axes with the MIL-F-8785C parameter sets of the book's table 4.1, and
// discrete 1-cosine gusts. Random draws come from the caller's std::mt19937_64 (seeded), normal
// ones through Boost's ziggurat distribution (as the sensors).
#pragma once

#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <boost/random/normal_distribution.hpp>

namespace tern::sim {

/// Dryden parameters: length scales L (m) and intensities sigma (m/s) of u, v, w.
struct DrydenParams {
  double L_u = 200, L_v = 200, L_w = 50;
  double sigma_u = 0, sigma_v = 0, sigma_w = 0;
};

/// MIL-F-8785C sets of the book's table 4.1: "none", "light" or "moderate" at low altitude
/// (50 m: L_u = L_v = 200 m, L_w = 50 m; sigma_u = sigma_v = 1.06 / 2.12 m/s,
/// sigma_w = 0.7 / 1.4 m/s). Throws std::invalid_argument for another name.
DrydenParams dryden_preset(const std::string& level);

/// Dryden gust generator: the book's transfer functions
///   H_u(s) = sigma_u sqrt(2 Va/L_u) / (s + Va/L_u)
///   H_v(s) = sigma_v sqrt(3 Va/L_v) (s + Va/(sqrt(3) L_v)) / (s + Va/L_v)^2   (H_w alike)
/// driven by unit white noise, discretised at the step dt (first order exactly, second order
/// by a state-space update). Output: gust velocity in body axes, m/s.
class Dryden {
 public:
  Dryden() = default;
  explicit Dryden(const DrydenParams& p) : p_(p) {}
  void set_params(const DrydenParams& p) { p_ = p; }
  const DrydenParams& params() const { return p_; }
  void reset() {
    u_ = 0;
    xv_.setZero();
    xw_.setZero();
    out_.setZero();
  }
  /// Advances by dt seconds at airspeed Va (floored at 1 m/s) and returns the gust.
  const Eigen::Vector3d& step(double dt, double Va, std::mt19937_64& rng);
  const Eigen::Vector3d& gust() const { return out_; }

 private:
  double second_order(Eigen::Vector2d& x, double sigma, double L, double Va, double dt, double n);
  DrydenParams p_;
  double u_ = 0;
  Eigen::Vector2d xv_ = Eigen::Vector2d::Zero(), xw_ = Eigen::Vector2d::Zero();
  Eigen::Vector3d out_ = Eigen::Vector3d::Zero();
  boost::random::normal_distribution<double> n_{0.0, 1.0};
};

/// A discrete 1-cosine gust in NED: w(t) = amplitude/2 (1 - cos(2 pi (t - start)/duration))
/// for start <= t <= start + duration, 0 otherwise.
struct CosineGust {
  double start = 0;                                     ///< s
  double duration = 1;                                  ///< s, > 0
  Eigen::Vector3d amplitude = Eigen::Vector3d::Zero();  ///< peak NED wind, m/s
  Eigen::Vector3d at(double t) const;
};

/// Random 1-cosine gusts: Poisson arrivals at `rate` (1/s), duration uniform in
/// [min_duration, max_duration] s, horizontal direction uniform, peak speed uniform in
/// [0, max_amplitude] m/s. Plus any number of scheduled gusts.
class GustField {
 public:
  void add(const CosineGust& g) { gusts_.push_back(g); }
  void set_random(double rate, double max_amplitude, double min_duration, double max_duration);
  /// Advances to time t (s, non-decreasing), drawing new random gusts, and returns the sum.
  Eigen::Vector3d step(double t, std::mt19937_64& rng);
  void reset() {
    gusts_.resize(scheduled_);
    next_random_ = -1;
  }
  void freeze_schedule() { scheduled_ = gusts_.size(); }

 private:
  std::vector<CosineGust> gusts_;
  std::size_t scheduled_ = 0;
  double rate_ = 0, max_amp_ = 0, min_dur_ = 1, max_dur_ = 3;
  double next_random_ = -1;
};

}  // namespace tern::sim
