// tern_sim_aero/wind.hpp: wind model (Beard & McLain, sec. 4.4): steady wind in NED, Dryden
// turbulence in body axes with the MIL-F-8785C parameter sets of the book's table 4.1, and
// discrete 1-cosine gusts. Random draws come from the caller's seeded Rng (random.hpp), normal
// ones through Boost's ziggurat distribution (as the sensors).
#pragma once

#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <boost/random/normal_distribution.hpp>

#include "tern_sim_aero/random.hpp"

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

/// Height (m) of the book's table 4.1: its parameters hold here and above.
inline constexpr double kDrydenTableHeight = 50.0;
/// Lowest height (m) of MIL-F-8785C's low-altitude figures 10 and 11 (10 ft); at and below it
/// the intensities are the MIL's for the steady wind (dryden_at_height).
inline constexpr double kDrydenGroundHeight = 3.048;
/// Lowest height (m) of the length-scale laws: MIL-F-8785C's surface roughness length for the
/// terminal flight phases (Category C, z0 = 0.15 ft), where its log wind profile reaches zero.
inline constexpr double kDrydenMinHeight = 0.0457;

/// The parameters p (given at kDrydenTableHeight, as the book's table 4.1) at height h above
/// the ground (m) in a steady wind of horizontal speed W (m/s). At and above 50 m: p unchanged
/// (the book's flight). Below, the MIL-F-8785C / MIL-HDBK-1797 low-altitude laws (h in ft)
///   L_w = h,  L_u = L_v = h / (0.177 + 0.000823 h)^1.2,
///   sigma_w = 0.1 W_20,  sigma_u = sigma_v = sigma_w / (0.177 + 0.000823 h)^0.4
/// shape the book's values: (1) every length scale and sigma_u, sigma_v take the MIL's ratio to
/// its value at 50 m (the eddies shrink with the height: L_w 0.1 m at a parked aircraft's CG,
/// instead of 50 m; sigma_u grows by up to 25 %), continued below 10 ft as the surface layer's
/// eddies keep scaling with the height, down to kDrydenMinHeight; (2) the intensities are not
/// more than the MIL's for the steady wind taken as W_20 (sigma_w <= 0.1 W): at 10 ft and below
/// in full, fading out in log height up to 50 m. Near the ground the turbulence is the wind's:
/// "moderate" at 0.8 m/s of wind is no longer 1.4 m/s of vertical gust at the wheels.
DrydenParams dryden_at_height(const DrydenParams& p, double h, double W);

/// Dryden gust generator: the book's transfer functions
///   H_u(s) = sigma_u sqrt(2 Va/L_u) / (s + Va/L_u)
///   H_v(s) = sigma_v sqrt(3 Va/L_v) (s + Va/(sqrt(3) L_v)) / (s + Va/L_v)^2   (H_w alike)
/// driven by unit white noise, discretised at the step dt (first order exactly, second order
/// by a state-space update). Output: gust velocity in body axes, m/s.
/// The filters run in eddy time tau = integral of Va/L dt (MIL-F-8785C gives the spectra in
/// spatial frequency, rad/m; in time they are those of the frozen field crossed at Va), with
/// states normalised so that each one's variance does not depend on Va/L: the first-order
/// Gauss-Markov u (variance sigma_u^2 whatever a), and x'' + 2 x' + x = w(tau) with output
/// sigma (x + sqrt3 x') for v and w. Va and L change every step (the airspeed; the length
/// scales below 50 m shrink to centimetres at the ground): the gust keeps its intensity sigma,
/// where the canonical form in t (a state of variance 1/(4 (Va/L)^3)) turned a faster Va/L into
/// a larger gust: 33 sigma at 1 m after a descent at 7 m/s, and without bound once that gust
/// pushed the airspeed up (a flight termination's glide diverged at 0.6 m).
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
  /// Advances by dt seconds at airspeed Va (m/s, through the mean air: the speed at which the
  /// aircraft crosses the frozen field; floored at 1 m/s), height h above the ground (m) and
  /// steady wind speed W (m/s): the parameters are dryden_at_height(params(), h, W), each
  /// length scale at least 2 Va dt (eddies the step cannot resolve). Returns the gust.
  const Eigen::Vector3d& step(double dt, double Va, double h, double W, Rng& rng);
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
  Eigen::Vector3d step(double t, Rng& rng);
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
