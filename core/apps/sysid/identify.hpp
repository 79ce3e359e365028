// core/apps/sysid/identify.hpp: the uavbook's aerodynamic coefficients (Beard and McLain, *Small
// Unmanned Aircraft*, ch. 4: C_L_*, C_D_*, C_Y_*, C_ell_*, C_m_*, C_n_*) from a flight, by the
// equation-error method (Klein and Morelli, *Aircraft System Identification*, 2006, ch. 5 and 7),
// after the estimator has given attitude, ground velocity and wind from kinematics alone (the
// two-step method; flight_data.hpp reconstructs alpha and beta against the steady wind).
//
// Built for real air. In turbulence the reconstructed alpha and beta miss the gusts: errors as
// large as what a manoeuvre moves them, which bias plain least squares by tens of per cent while
// its bounds read a few. So:
//  1. Lift and drag from the trim (time domain, the means of windows of trim_window_s) over the
//     flight's airspeeds: C_L_0 and C_L_alpha by instrumental variables, 1/qbar instrumenting alpha
//     (a window's gust does not average out; the trim's alpha at 1 g goes as m g / (qbar S));
//     C_L_q, C_L_delta_e from the band, alpha instrumented by the longitudinal model's alpha for
//     the commands (sideslip_instrument.hpp), taken only when the band's fit holds and its
//     C_L_alpha agrees with the trim's; then the polar's C_D_p and Oswald factor e on the lift,
//     optionally jointly with the accelerometer's x bias; every coefficient on the dynamic pressure
//     corrected by the pitot's scale from the wind triangle (instrumentation.hpp, K&M ch. 10).
//  2. The side force in the band, beta instrumented by the lateral model's sideslip for the
//     commands (sideslip_instrument.hpp; C_Y_p, C_Y_r held beside it). Then alpha and beta from
//     where they are observable: the accelerometers' lift, alpha = (C_L - C_L_0 - C_L_q q^ -
//     C_L_delta_e delta_e) / C_L_alpha (the flow the wing met, gusts included; the body forces
//     turned through it), beta likewise from the side force (flow_angles: accelerometer;
//     estimator: the reconstruction's). In the moment regressions they are instrumented by the
//     reconstruction's (instrumental variables: independent errors).
//  3. The moments and the side force in the frequency domain, over the band the excitation filled
//     (band_lo_hz .. band_hi_hz, each airborne stretch of min_segment_s or more, in pieces of at
//     most two minutes, transformed at the multiples of 1/T in the band): the trim, slow drifts and
//     the estimator's wind fall out. Bias terms (C_m_0, C_Y_0, C_ell_0, C_n_0) from the trim
//     windows' means with the rest fixed.
//  4. Output error on the rotational axes (output_error.hpp; K&M ch. 6): the pitch rate, then the
//     roll and yaw rates together, simulated over windows of the flight from the measured rates,
//     driven by step 2's alpha and beta, the commands and qbar; the moment coefficients the band
//     identified (and the bias terms) refined by Levenberg-Marquardt from their equation-error
//     values; a dominant derivative the band left poorly determined (excited, not collinear) is
//     freed from the prior and adopted if the output error determines it (identify_moments.hpp);
//     the others the band did not identify keep the prior.
//     The reported standard error is the output error's (coloured-residual) bound, never below
//     the equation error's when the two estimates disagree by more than their bounds combined;
//     an output-error estimate poorly determined (max_relative_error) is not adopted.
// Every sample pairs the command in force when it was taken, through the servo lag (flight_data).
//
// For each coefficient: the estimate, its standard error, the prior, and whether the data
// identified it. The standard error is the largest of the white-residual Cramer-Rao bound, the one
// that accounts for coloured residuals (the time domain's residual autocorrelation, the frequency
// domain's per-frequency residual power) and the delete-one-batch jackknife over the flight's
// two-minute pieces (the trim fits': over 30-s blocks of windows); the lift's also carries what
// the kept terms beside it, uncertain by half their prior, move it by. A coefficient is not
// identified (the prior is kept, with one line saying why) when its regressor was not excited
// (e.g. "pitch rate never above 5 deg/s"), when it is collinear with another regressor
// (|r| > max_correlation), or when its standard error exceeds max_relative_error of the estimate.
#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "sysid/aero_samples.hpp"
#include "sysid/flight_data.hpp"
#include "sysid/instrumentation.hpp"
#include "sysid/output_error.hpp"
#include "tern/aircraft.hpp"

namespace tern::core::sysid {

enum class FlowAngles { accelerometer, estimator };

struct SysidOptions {
  AirborneFilter airborne;
  double band_lo_hz = 0.1;      ///< Hz, lowest frequency of the frequency-domain regressions
  double band_hi_hz = 4.0;      ///< Hz, highest (sysid.yaml's chirps reach 4 Hz)
  double trim_window_s = 4.0;   ///< s, window of the trim (lift, drag, bias) regressions
  double min_segment_s = 10.0;  ///< s, shortest airborne stretch transformed
  FlowAngles flow_angles = FlowAngles::accelerometer;
  double max_correlation = 0.95;    ///< |r| between two regressors beyond which both are suspect
  double max_relative_error = 0.5;  ///< standard error / |estimate| beyond which the prior is kept
  OutputErrorOptions output_error;  ///< step 4, the rotational axes' output-error refinement
  bool fit_accel_x_bias = false;    ///< the accelerometer's x bias as a parameter of the polar (instrumentation.hpp)
  /// Va_true / Va_pitot stated by the user (a calibration) and its standard error, held
  /// (stated_airspeed_scale); NaN: estimated from the wind triangle (airspeed_scale)
  double pitot_scale = std::numeric_limits<double>::quiet_NaN();
  double pitot_scale_std_error = 0.0;
  /// rad/rad, >= 0: the largest share of one gyro axis's rate in another's reading (the datasheet's
  /// cross-axis sensitivity plus the board's mounting error; MEMS gyros: 1-2 %). Not identifiable
  /// from the moments (consider_gyro_coupling): it widens the rolling and yawing moments' bounds.
  double gyro_cross_axis = 0.02;
  /// The timing pass (command_delay.hpp): before each output-error refinement, an output-error
  /// fit of each surface's delay beside its axis's moment coefficients (those the band identified
  /// and the damping and control derivatives), into SysidResult::delay_shift; the refinement itself
  /// is on the delays the series was loaded with.
  bool estimate_delays = false;
  /// identify_timed (command_delay.hpp): the held terms of prior_update.hpp's pairs moved with the
  /// identified derivative of the same surface, and the flight identified again on them
  bool scale_held_priors = true;
};

struct CoefficientEstimate {
  std::string name;  ///< the aircraft file's key, e.g. "C_m_q"
  double prior = 0.0;
  double estimate = 0.0;   ///< the identified value (the prior when not identified)
  double std_error = 0.0;  ///< 1 sigma (0 when not identified)
  bool identified = false;
  std::string method;                     ///< "trim", "band" or "output error"
  std::string note;                       ///< why not identified, or "" when it was
  double equation_error = 0.0;            ///< the equation-error estimate (trim or band), before any output error
  double equation_error_std_error = 0.0;  ///< its standard error
};

/// How well one regression's model fits its measured coefficient.
struct AxisFit {
  std::string axis;    ///< "lift", "drag", "side force", "roll", "pitch", "yaw"; output error: "roll rate", "pitch rate", "yaw rate"
  std::string domain;  ///< "trim" (time domain, window means), "band" (frequency domain) or "output error" (simulated rates)
  double r_squared = 0.0;
  double rms_residual = 0.0;  ///< coefficient units (band: per frequency row); output error: rad/s
  std::size_t rows = 0;
  /// An instrumental-variable fit's generalized R^2 (regression.hpp), which the verdicts judge it
  /// by; r_squared for the others.
  double r_squared_generalized = 0.0;
};

/// A measured coefficient and the identified model's over the longest airborne stretch (plots).
struct AxisSeries {
  std::string axis;  ///< "C_L", "C_D", "C_Y", "C_ell", "C_m", "C_n"
  std::vector<double> t, measured, predicted;
};

/// The parts of the drag at trim's bound (identify_drag.hpp's drag_at_trim), from the polar's fit.
struct TrimDragBound {
  double C_Lw_squared_mean = 0.0;  ///< the polar's trim windows' mean C_Lw^2 (DragPolar)
  NuisanceEstimate C_D_at_mean;    ///< the polar there, the pitot scale's shift in its bound (DragPolar)
  double K_std_error = 0.0;        ///< the polar's slope's bound, the pitot scale's shift in it
  double pitot_shift = 0.0;        ///< what one standard error of the pitot scale moves the polar at the mean by
  double kept_terms = 0.0;         ///< what the kept C_D_q, C_D_delta_e's prior uncertainty moves the drag at trim by
};

/// A held term's prior moved with an identified derivative of the same surface (prior_update.hpp).
struct HeldScaling {
  std::string held, reference;  ///< the aircraft file's keys
  double ratio = 1.0;           ///< the reference's identified value over its prior
  double given = 0.0;           ///< the held term's prior as given
  std::string note;             ///< what its note says
};

struct SysidResult {
  Aircraft aircraft;  ///< the prior with the identified coefficients
  std::vector<CoefficientEstimate> coefficients;
  std::vector<AxisFit> fits;
  std::size_t samples = 0;   ///< airborne samples used
  std::size_t segments = 0;  ///< airborne stretches transformed
  double airborne_s = 0.0;
  double C_D_trim_prior = 0.0, C_D_trim = 0.0;  ///< drag at the flight's mean trim, prior and identified
  /// C_D_trim's standard error: the trim windows' bound on the polar there, with the pitot scale's
  /// (identify_drag.hpp); NaN where the polar is the prior's (neither C_D_p nor e adopted)
  double C_D_trim_std_error = std::numeric_limits<double>::quiet_NaN();
  double C_D_per_deg = 0.0;                     ///< how much 1 deg of alpha (or pitch) bias moves C_D at trim, fraction
  double trim_alpha = 0.0, trim_delta_e = 0.0;  ///< rad: the flight's mean alpha and elevator, where the drag at trim is taken
  TrimDragBound trim_drag_bound;                ///< what C_D_trim_std_error is made of (identify_drag.hpp)
  NuisanceEstimate pitot_scale;                 ///< Va_true = k Va_pitot, from the wind triangle (instrumentation.hpp)
  double wind_n = 0.0, wind_e = 0.0;            ///< m/s, the constant wind fitted beside the pitot scale
  NuisanceEstimate accel_x_bias;                ///< m/s^2, the accelerometer's x bias, jointly with the polar
  NuisanceEstimate motor_tau;                   ///< s, the thrust's lag behind the throttle (motor_lag.hpp; set by the caller)
  NuisanceEstimate oswald;                      ///< e, from the polar's slope
  /// e from the polar's slope fitted again with C_D_p at the prior: what the verdicts adopt in
  /// oswald's place when they reject C_D_p (verdicts.hpp), so that the polar keeps the drag the
  /// trim windows measured
  NuisanceEstimate oswald_C_D_p_held;
  /// s, aileron, elevator, rudder: the delay between a command's stamp and its effect with which the
  /// series was loaded (FlightSeriesOptions::command_delay_s; set by the caller)
  std::array<double, 3> command_delay_s = {0.0, 0.0, 0.0};
  /// s, aileron, elevator, rudder: how much later than command_delay_s the commands act, from the
  /// output error (SysidOptions::estimate_delays; command_delay.hpp), with its standard error;
  /// identified false where not estimated (given, or the axis not fitted)
  std::array<NuisanceEstimate, 3> delay_shift;
  /// the held terms identified on a prior moved with their surface's identified derivative
  /// (prior_update.hpp); their `prior` is the moved one until restore_prior
  std::vector<HeldScaling> held_scaled;
  std::vector<std::string> notes;  ///< one line each: what the log could not support, and why
  std::vector<AxisSeries> series;
};

/// Identifies the coefficients (header). Throws std::runtime_error with one line when the flight
/// cannot support any identification: no airborne samples, no stretch of min_segment_s.
SysidResult identify(const FlightSeries& series, const Aircraft& prior, const SysidOptions& options);

}  // namespace tern::core::sysid
