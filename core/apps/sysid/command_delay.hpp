// core/apps/sysid/command_delay.hpp: when the surfaces' commands act, estimated from the flight
// (issue 76: logs from other autopilots stamp a command when it was computed; the surface moves a
// servo bus, a mixer cycle or a servo's dead time later).
//
// Two passes of identify() (identify.hpp):
//  1. The timing pass (SysidOptions::estimate_delays) on the series loaded with the starting delays
//     (the prior's servos.delay_*): the equation error, then the output error of the pitch rate
//     and of the roll and yaw rates with each surface's delay free beside the axis's coefficients
//     (output_error.hpp, "The commands' timing"; Klein and Morelli, *Aircraft System
//     Identification*, 2006, ch. 10: the data's time shifts fitted with the model). The
//     equation error alone cannot do it in a closed loop: a controller that feeds the rate back
//     makes a command computed from the rate look like one acting early, so a least-squares
//     search over the delay is pulled toward commands acting before their stamps.
//  2. Each delay adopted when its standard error is at most max_std_error_s and it stays within
//     max_delay_s of a stamp. Where an adopted delay moved at all, the series is built again with
//     the adopted delays and identified (equation error and output error on the same timing); where
//     the first pass's verdicts (verdicts.hpp) let held terms move with their surface
//     (prior_update.hpp, SysidOptions::scale_held_priors), that identification is on the moved
//     prior (SysidResult::held_scaled; the caller's restore_prior after its verdicts); else the
//     first pass's identification stands. Not above a threshold: on a 47-ms roll mode (the
//     Aerosonde's) each millisecond moves C_ell_p by some 2 % and C_n_r by 3 %. The sysid mission
//     flown in the `ideal` world (no sensor error, no turbulence; the estimator told the IMU sits at
//     the CG, as that world's does), whose commands act 1.25 ms before their stamps (the
//     simulator's servo answers a command over the whole 2.5-ms step it arrives at): with the
//     commands at 0 ms, C_ell_p -3.0 %, C_ell_delta_a +3.0 %, C_n_r -5.1 %; the timing pass's
//     -0.5 ms gives -2.0, +2.1 and -3.0 %; the true -1.25 ms -0.5, +0.9 and -1.7 %.
//  3. A surface whose own delay is not adopted (a rudder the flight hardly moves) takes the adopted
//     surfaces' delay, weighted by their standard errors, when its own fit agrees with it within
//     shared_sigmas: one output loop (a mixer cycle, a servo bus) drives every surface. Else, or
//     when none was adopted, it keeps the prior's servos.delay_*.
// A surface whose delay is given (estimate[i] false) keeps it; so does every surface when the
// output error is off (its one line says so).
#pragma once

#include <array>
#include <functional>

#include "sysid/identify.hpp"

namespace tern::core::sysid {

/// The series with each command acting `command_delay_s` (s, aileron, elevator, rudder) after its stamp.
using SeriesLoader = std::function<FlightSeries(const std::array<double, 3>& command_delay_s)>;

struct DelayOptions {
  std::array<bool, 3> estimate = {true, true, true};  ///< aileron, elevator, rudder: estimated (else held at the start)
  double max_std_error_s = 0.005;                     ///< s, a delay less certain than this is not adopted
  double max_delay_s = 0.25;                          ///< s, |delay| beyond this is not adopted (a log's clocks, not a servo)
  /// a surface whose own delay is not adopted takes the adopted surfaces' (weighted) delay when its
  /// own fit, if it has one, lies within this many standard errors of it; else the prior's
  double shared_sigmas = 3.0;
};

/// The delays the timing pass's estimates lead to (steps 2 and 3 above).
struct DelayChoice {
  std::array<double, 3> delays;           ///< s, aileron, elevator, rudder: the start where nothing moved
  std::array<NuisanceEstimate, 3> shift;  ///< against the start; identified where adopted, else a note says why
  std::vector<std::string> lines;         ///< one per surface, for SysidResult::notes
  bool moved = false;                     ///< a delay moved: the series is loaded again
};
/// `shift`: the timing pass's SysidResult::delay_shift against `start_s` (s).
DelayChoice choose_delays(const std::array<double, 3>& start_s, std::array<NuisanceEstimate, 3> shift, const DelayOptions& d);

/// identify() with the commands' delays estimated (header); the result's command_delay_s are the
/// delays the identification used, delay_shift each one's estimate against the start, one note per
/// surface. Throws what identify() and `load` throw.
SysidResult identify_timed(const SeriesLoader& load, const std::array<double, 3>& start_s, const Aircraft& prior, const SysidOptions& o,
                           const DelayOptions& d);

}  // namespace tern::core::sysid
