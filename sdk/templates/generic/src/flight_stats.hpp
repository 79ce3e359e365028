// flight_stats.hpp: running figures of a flight from its state (plain C++, no tern types):
// peak bank angle, lowest and mean airspeed, and the time spent below a stall-warning
// airspeed. Angles rad, speeds m/s, times s.
#pragma once

#include <cstdint>

namespace tern_@NAME@ {

class FlightStats {
 public:
  /// One sample at time t (s, increasing) of roll phi (rad) and airspeed Va (m/s) while the
  /// aircraft is airborne (the caller decides). Returns true when Va has just dropped below
  /// Va_warn (a new low-airspeed episode begins). Non-finite samples are ignored.
  bool add(double t, double phi, double Va, double Va_warn);
  void reset() { *this = FlightStats(); }

  double max_abs_phi() const { return max_abs_phi_; }
  double min_Va() const { return samples_ ? min_Va_ : 0.0; }
  double mean_Va() const { return samples_ ? sum_Va_ / static_cast<double>(samples_) : 0.0; }
  double time_below_warn() const { return time_below_; }  ///< s
  std::int64_t episodes() const { return episodes_; }       ///< low-airspeed episodes
  std::int64_t samples() const { return samples_; }

 private:
  double max_abs_phi_ = 0.0, min_Va_ = 0.0, sum_Va_ = 0.0, time_below_ = 0.0;
  double last_t_ = 0.0;
  bool below_ = false;
  std::int64_t samples_ = 0, episodes_ = 0;
};

}  // namespace tern_@NAME@
