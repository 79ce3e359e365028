// core/apps/sysid/excitation_recovery.hpp: the excitation of a closed-loop flight recovered from
// its commands when the log carries no excitation table (every autopilot's but tern's: issue 76).
//
// A surface's command is the controller's answer to the states it feeds back plus whatever was
// added to it (a manoeuvre the pilot or the autopilot's identification mode injected). Only that
// second part is independent of the gusts, which the controller answers like any other motion;
// the moment regressions need it as their instrument (identify.hpp). The two-stage method of
// closed-loop identification (Ljung, *System Identification*, 2nd ed., 1999, sec. 13.5;
// Soderstrom and Stoica, *System Identification*, 1989, ch. 10) models the command first:
//  1. Every channel high-passed by subtracting its centred moving mean over highpass_s (the
//     references, trims and integrators of the outer loops move slower than the band).
//  2. Each command regressed by least squares on what a fixed-wing autopilot's inner loops feed
//     back, from the estimate (phi, theta, p, q, r, beta, Va and height), each at lags of 0 to
//     max_lag_s (the controller's own latency and the command's delay) and through first-order
//     low-passes of time constants lowpass_s (the memory a controller keeps of a state: a yaw
//     damper's washout, r less r low-passed, the book's at 0.5 rad/s; a PI loop's integrator,
//     which within the band acts as a low-pass of the error; a basis of first-order filters,
//     as Laguerre functions are, Heuberger, Van den Hof and Wahlberg, *Modelling and
//     Identification with Rational Orthogonal Basis Functions*, 2005), robustly: the samples whose
//     residual exceeds outlier_sigmas of the residuals' robust spread (1.4826 times their median
//     absolute deviation) are left out and the fit repeated, so that the manoeuvres (the part
//     the feedback does not explain) do not bend the controller's model.
//  3. The excitation is the command less that model's feedback, over every sample.
// The result goes where topics/excitation.csv's parts go (FlightSeries::exc_delta_*), with one
// line per surface in the series' notes: how the instrument was built and how much of the command
// the feedback explains. The feedback the model misses (a nonlinear or scheduled controller, the
// autopilot's own estimate against tern's) stays in the recovered excitation and, with it, some of
// the gusts: the instruments then remove less of the loop's bias than a logged excitation does.
//
// Errors: std::invalid_argument for a low-pass time constant that is not > 0; a surface with fewer
// valid samples than regressors keeps no excitation (its note says so).
#pragma once

#include <vector>

#include "sysid/flight_data.hpp"

namespace tern::core::sysid {

struct ExcitationRecoveryOptions {
  double highpass_s = 10.0;  ///< s, window of the moving mean subtracted (1 / the band's low edge)
  double max_lag_s = 0.06;   ///< s, the regressors' longest lag
  /// s, time constants (each > 0) of the first-order low-passes each state is fed back through besides its lags
  std::vector<double> lowpass_s = {0.5, 2.0, 8.0};
  double outlier_sigmas = 2.5;  ///< residual / robust spread beyond which a sample is left out of the fit
  int passes = 4;               ///< fits, each leaving out the previous one's outliers (>= 1; 1: none left out)
};

/// Fills s.exc_delta_a, _e, _r and _t from the commands (header) when they are empty; appends one
/// note per surface to s.notes.
void recover_excitation(FlightSeries& s, const ExcitationRecoveryOptions& o = {});

}  // namespace tern::core::sysid
