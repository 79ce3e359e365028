// tern_sim_aero/gnss_sky.hpp: what the GNSS antenna sees of the sky, and what the receiver makes of
// it (issue 77). A patch antenna on top of the aircraft tracks the satellites above its own plane;
// rolled or looped past the vertical it faces the ground and loses them. With fewer satellites
// the solution's geometry is worse (the dilutions of precision grow, the receiver reports larger
// accuracies), its position and velocity jump to another combination of the satellites' range
// errors, and with fewer than four it has no fix. A satellite back in view is tracked again after
// the receiver's reacquisition time. The receiver's navigation filter (u-blox's dynamic platform
// model) follows accelerations up to its model's bound; the velocity change beyond the bound
// enters a lag that decays with lag_tau: under more acceleration than the model allows the output
// velocity lags the truth, and catches up after.
//
// The model (Kaplan & Hegarty, "Understanding GPS/GNSS", 3rd ed., sec. 7.2 and 11.2): each
// satellite's range error is a first-order Gauss-Markov process (the atmosphere, the orbit and
// clock, multipath) and its range-rate error is white; the least-squares solution from the set S
// of tracked satellites, with the line-of-sight matrix H_S (rows [-los_i^T, 1], NED, plus the
// receiver clock), has the error (H_S^T H_S)^-1 H_S^T e_S. What this adds to the world's GNSS
// errors (Sensors: the Gauss-Markov position error of the whole sky) is the solution from S less
// the solution from every satellite: zero while the antenna sees the whole sky, so a flight that
// never turns its antenna away is the flight it was without the sky model.
//
// The constellation: `satellites` directions above the elevation mask, azimuths spread evenly
// around the horizon and elevations uniform in sin(el), drawn from the seed. They stay put for the
// flight: a GPS satellite moves ~0.5 deg/min across the sky (a 12-hour orbit), a few degrees in a
// flight, against the tens of degrees an aircraft's attitude changes the antenna's view by.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "tern_sim_aero/random.hpp"

namespace tern::sim {

struct GnssSkyParams {
  int satellites = 0;           ///< satellites above the elevation mask (0: the sky is not modelled)
  double elevation_mask = 0.0;  ///< rad above the horizon; the receiver ignores lower satellites
  double antenna_cutoff = 0.0;  ///< rad above the antenna's plane below which a satellite is not tracked
  double reacquisition = 0.0;   ///< s a satellite must stay in view before it is tracked again
  double pdop_mask = 0.0;       ///< the receiver outputs no fix with a larger PDOP (0: no mask)
  /// The whole sky's solution error per horizontal axis (steady sigma, m) and per velocity axis
  /// (m/s): the satellites' range errors are sized to give them (range sigma = horizontal_sigma
  /// sqrt(2) / HDOP, range-rate sigma = velocity_sigma sqrt(3) / PDOP, both of the whole sky).
  double horizontal_sigma = 0.0;
  double velocity_sigma = 0.0;
  double range_tau = 0.0;         ///< correlation time of the range errors, s (the range-rate errors are white)
  double max_acceleration = 0.0;  ///< the dynamic platform model's acceleration bound, m/s^2 (0: none)
  double lag_tau = 0.0;           ///< s: how fast the velocity change beyond the bound catches up (> 0 with a bound)
};

/// What the receiver makes of the sky at one fix.
struct GnssSkyFix {
  int tracked = 0;                                              ///< satellites used in the solution
  bool fix = true;                                              ///< at least four tracked
  double hdop = 0.0, vdop = 0.0, pdop = 0.0;                    ///< of the tracked set (0 without a fix)
  double hdop_ratio = 1.0, vdop_ratio = 1.0, pdop_ratio = 1.0;  ///< to the whole sky's (1 with every satellite)
  Eigen::Vector3d position_error = Eigen::Vector3d::Zero();     ///< NED, m: the tracked set's solution less the whole sky's
  Eigen::Vector3d velocity_error = Eigen::Vector3d::Zero();     ///< NED, m/s: the same for the velocity, plus the platform model's lag
  double velocity_lag = 0.0;                                    ///< m/s: |the platform model's lag| (in velocity_error)
};

/// Dilutions of precision of a set of lines of sight (unit, NED): horizontal, vertical and
/// position (Kaplan & Hegarty sec. 11.2.1, G = (H^T H)^-1). Fewer than four: every one infinite.
struct Dops {
  double h, v, p;
};
Dops dilutions_of_precision(const std::vector<Eigen::Vector3d>& los);

class GnssSky {
 public:
  /// Draws the constellation from `seed` (a stream of its own: the world's other draws do not
  /// change with it). Throws std::invalid_argument for satellites < 0 or > 64, or a negative
  /// sigma, time or acceleration.
  GnssSky(const GnssSkyParams& p, std::uint64_t seed);
  /// Every satellite tracked, the errors restarted (drawn from their steady state), the lag cleared.
  void reset();
  /// The fix at flight time t (s), dt after the previous one, with the antenna's boresight (unit,
  /// NED: the body's up, R (0, 0, -1)) and its true velocity (NED, m/s).
  GnssSkyFix step(double t, double dt, const Eigen::Vector3d& boresight_ned, const Eigen::Vector3d& velocity_ned);
  bool modelled() const { return p_.satellites > 0; }
  /// Unit lines of sight from the receiver to each satellite, NED.
  const std::vector<Eigen::Vector3d>& lines_of_sight() const { return los_; }

 private:
  void update_tracking(double t, const Eigen::Vector3d& boresight_ned);
  Eigen::Vector3d platform_lag(double dt, const Eigen::Vector3d& velocity_ned);
  Eigen::VectorXd advance_errors(double dt);
  void solution_errors(const Eigen::VectorXd& rate_error, GnssSkyFix& f) const;
  GnssSkyParams p_;
  std::uint64_t seed_;
  Dops whole_{};                                       ///< of every satellite
  double range_sigma_ = 0.0, range_rate_sigma_ = 0.0;  ///< per satellite, from the whole sky's DOPs
  Rng rng_;
  std::vector<Eigen::Vector3d> los_;
  std::vector<double> range_error_;
  std::vector<double> in_view_since_;  ///< s; NaN while out of view
  std::vector<bool> tracked_;
  Eigen::Vector3d velocity_prev_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d lag_ = Eigen::Vector3d::Zero();  ///< output less the truth, NED, m/s
  bool velocity_started_ = false;
};

}  // namespace tern::sim
