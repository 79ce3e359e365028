// core/apps/sysid/instrumentation.hpp: instrumentation-error parameters estimated beside the
// drag polar (Klein and Morelli, *Aircraft System Identification*, 2006, sec. 10.2 data
// compatibility: bias and scale-factor parameters of the sensors fitted with the model's).
//
// The drag at trim is some 1 % of the lift, so the sensors' small errors are large beside it:
//  * the pitot's scale (installation: probe position, tubes). The true airspeed is k times the
//    pitot's, Va = k Va_pitot, so the dynamic pressure is k^2 qbar_pitot and the propeller's
//    inflow k V. k is found from the wind triangle (airspeed_scale): the estimator's ground
//    velocity (GNSS-aided), turned into the body axes, less a wind constant over the flight equals
//    the air velocity along body x, k Va_pitot cos(alpha) cos(beta). Linear in (k, w_n, w_e, w_d).
//    Separable when the flight turns (the wind's projection changes with heading while k Va_pitot
//    does not); on one heading only the airspeeds' spread about their mean separates k from the
//    along-track wind, rarely enough, and a straight line at one airspeed leaves them collinear:
//    k is then not identified (kept at 1). A wind that drifts
//    over the flight colours the residuals; the coloured-residual bound widens with it.
//  * the accelerometer's x bias b (m/s^2; the residual of its calibration, and a calibration tilt's
//    share of gravity at 1 g, which a constant force along body x cannot tell from a bias). It
//    adds m b to the measured x force, so the measured drag coefficient of a trim window is
//      C_D_measured = C_D_p + K C_Lw^2 - b m cos(alpha) / (qbar S),  K = 1 / (pi e AR)
//    (drag_polar). Across airspeeds the three regressors are 1, ~1/Va^4 (C_Lw at 1 g) and ~1/Va^2:
//    three distinct shapes, so three airspeeds (or one airspeed with load factors that move C_Lw
//    apart from qbar) separate them; at one airspeed and 1 g all three are constant and only their
//    sum is known: b is then not identified, fixed at 0, and C_D_p and e carry it (one line says so).
//    The bias is only as good as the polar's model: a drag error shaped like 1/qbar (the lift's
//    alpha, whose error moves the drag by C_L delta_alpha, the prior's C_D_delta_e times the trim
//    elevator) goes into b with a small bound. On the shipped bench it did (b +0.04..+0.25 m/s^2
//    against -0.09..+0.02 in truth), so identify.hpp fits it only on request (fit_accel_x_bias).
// Standard errors are the coloured-residual least-squares bounds of the joint fit, so each
// coefficient's includes the nuisance parameters' uncertainty; the pitot scale's own uncertainty
// is added by the caller (identify.cpp) as a consider term: the polar refitted at k + sigma_k.
// Units SI; angles rad. Errors: std::invalid_argument for inputs of mismatched lengths.
#pragma once

#include <string>
#include <vector>

#include "sysid/flight_data.hpp"

namespace tern::core::sysid {

/// One instrumentation parameter: estimate, 1-sigma standard error, whether the data separated it.
struct NuisanceEstimate {
  double estimate = 0.0;
  double std_error = 0.0;
  bool identified = false;
  std::string note;  ///< why not identified, or ""
};

struct AirspeedScale {
  NuisanceEstimate k;                      ///< Va_true = k Va_pitot (1 when not identified)
  double w_n = 0.0, w_e = 0.0, w_d = 0.0;  ///< m/s, the flight's constant wind, NED (fitted beside k)
  double rms_residual = 0.0;               ///< m/s, body-x air velocity residual
  std::size_t samples = 0;
};

/// The pitot's scale from the wind triangle over the samples `idx` of `s` (header). Va_pitot is
/// sqrt(2 qbar / rho); samples without a pitot reading are skipped. k is not identified (1 kept)
/// when the wind's columns explain its regressor with a multiple correlation beyond
/// `max_correlation` (no turn), or fewer than ten samples hold a pitot reading.
AirspeedScale airspeed_scale(const FlightSeries& s, const std::vector<std::size_t>& idx, double rho, double max_correlation);

/// The stated pitot scale's valid range (Va_true / Va_pitot) and its standard error's upper limit.
inline constexpr double kMinPitotScale = 0.5, kMaxPitotScale = 2.0, kMaxPitotScaleStdError = 0.5;

/// Throws std::invalid_argument naming the value for a stated pitot scale k outside kMinPitotScale ..
/// kMaxPitotScale or a standard error outside 0 .. kMaxPitotScaleStdError (what stated_airspeed_scale
/// and `tern sysid --pitot-scale` accept).
void check_stated_pitot_scale(double k, double std_error);

/// The note of a pitot scale the user stated (tern sysid --pitot-scale: a calibration run), not estimated.
inline constexpr const char* kStatedPitotScale = "given (--pitot-scale)";

/// A stated pitot scale k +- std_error (not identified: its note kStatedPitotScale), the flight's
/// constant wind fitted beside it over the same rows as airspeed_scale's. Where turbulence leaves
/// the wind triangle's k uncertain (the body-axis gusts' mean over the flight looks like a scale:
/// 0.8 % in ten minutes of light turbulence) and the drag at trim with it (identify_drag.hpp), a
/// calibrated pitot's scale narrows both. Throws what check_stated_pitot_scale throws.
AirspeedScale stated_airspeed_scale(const FlightSeries& s, const std::vector<std::size_t>& idx, double rho, double k, double std_error);

/// One trim window's means for the polar: the measured drag coefficient (thrust removed, forces
/// turned through alpha), the lift model's C_Lw squared, and the bias regressor -m cos(alpha) /
/// (qbar S) (s^2/m: times b in m/s^2 gives a drag coefficient). The mean of C_Lw^2, not the square
/// of its mean: in turbulence alpha moves about its trim within a window, and the induced drag
/// follows the square of each moment's lift (the window's mean drag is K (mean^2 + variance)).
struct PolarWindow {
  double C_D = 0.0;
  double C_Lw_squared = 0.0;
  double bias_regressor = 0.0;
};

struct DragPolar {
  NuisanceEstimate C_D_p;
  NuisanceEstimate K;  ///< the polar's slope 1 / (pi e AR)
  NuisanceEstimate e;  ///< Oswald factor from K (standard error by first-order propagation)
  /// the slope and Oswald factor with C_D_p held at the prior (`C_D_p_prior`): z - C_D_p_prior =
  /// K C_Lw^2 (+ the bias when fitted). Their bounds are the joint fit's K bound (it carries C_D_p's
  /// uncertainty), propagated at K_held.
  NuisanceEstimate K_held, e_held;
  NuisanceEstimate bias_x;  ///< m/s^2, accelerometer x bias (0, not identified, at one airspeed)
  /// The polar at the windows' mean C_Lw^2 (C_Lw_squared_mean): the fit again with that regressor
  /// centred, whose intercept is the drag there and its bound the data's, whatever the split between
  /// C_D_p and the slope (the two are correlated: their bounds added overstate it). The drag at trim's
  /// bound (identify_drag.hpp) starts from it.
  double C_Lw_squared_mean = 0.0;
  NuisanceEstimate C_D_at_mean;
  double r_squared = 0.0, rms_residual = 0.0;
  std::size_t rows = 0;
};

/// The polar and the accelerometer's x bias jointly on the trim windows (header). `AR` the aspect
/// ratio; `max_lag` windows for the coloured-residual bound. The bias is dropped from the fit (0,
/// not identified) when its regressor does not vary across the windows (one airspeed: its spread
/// below 1 % of its mean), or when its standard error moves the mean measured drag coefficient by
/// more than `max_relative_error` of it (the data did not separate it). e is identified when K > 0
/// and K's standard error is below `max_relative_error` of K. Throws std::invalid_argument with
/// fewer than four windows. `fit_bias` false: the bias is not a parameter (0, not identified).
/// K_held and e_held: the same with C_D_p held at `C_D_p_prior` (DragPolar), for a C_D_p the
/// verdicts reject. Without them, a rejected C_D_p beside the joint slope moves the polar at trim by
/// the C_D_p dropped (on the book's Aerosonde C_D_p is 0 and the joint fit's 0.0021 +- 0.0024, half
/// the drag at trim).
DragPolar drag_polar(const std::vector<PolarWindow>& w, double AR, double max_relative_error, std::size_t max_lag, bool fit_bias = true,
                     double C_D_p_prior = 0.0);

}  // namespace tern::core::sysid
