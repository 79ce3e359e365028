// core/apps/sysid/validate.hpp: the simulator scored against a flight log (`tern validate`): the
// uavbook 6-DOF model (tern/aero/model.hpp, never a second model) driven open loop by the
// logged surface and throttle commands, from the logged (estimated) state.
//
// Method (output error of a simulation, then equation error at each sample):
//  * Windows. The series (flight_data.hpp) is cut into windows of `window_s` seconds where the
//    aircraft is airborne at every sample: airborne.hpp's rule (the log's declared window, else
//    above the ground where it stood still, never above the estimator's origin), the estimate
//    finite, Va above `min_Va` (so no ground contact). Each
//    airborne stretch is tiled from its start; its last piece shorter than a window is not scored.
//  * Simulation. At each window's first sample the model's state is the logged one (position
//    p_n p_e p_d, ground velocity u v w in body FRD, Euler angles phi theta psi, body rates p q r
//    from the gyro less the estimated bias); the wind is the estimator's at that sample, held
//    steady; the commands in force at sample k (through the servo lag) are held until sample k+1;
//    RK4 (rk4_step) in steps of at most `max_step`. Re-initialising every window keeps one bad
//    second (a gust, an estimator reset) from ruining the score. A window whose state stops being
//    finite holds its last finite prediction to the window's end and is counted as diverged.
//  * Scored samples: every window sample but the first (where the prediction is the log).
//  * Per channel y (p q r Va alpha beta phi theta), measured y against predicted yhat over the
//    scored samples of every window (N samples, e = yhat - y; angles compared through wrap_pi):
//      RMS error   sqrt(mean(e^2))
//      NRMSE       RMS error / std(y), std the population standard deviation of the measured
//                  channel over the same samples (0: the model explains the motion; 1: no better
//                  than the measured mean)
//      Theil's U   RMS error / (sqrt(mean(y^2)) + sqrt(mean(yhat^2))), Theil's inequality
//                  coefficient, 0 (equal) .. 1 (no agreement); for a channel with a large mean
//                  (Va) it is small even for a poor fit, so read it with NRMSE
//    (Klein and Morelli, *Aircraft System Identification*, 2006, ch. 11: comparing measured and
//    model waveforms, Theil's inequality coefficient; Jategaonkar, *Flight Vehicle System
//    Identification*, ch. 11, model validation; H. Theil, *Economic Forecasts and Policy*, 1961.)
//  * Overall, to rank the files: per file the geometric mean of its NRMSE over the channels every
//    file has a finite NRMSE in (the same channels for all), exp(mean(ln NRMSE_c)). A file x %
//    better on every channel scores x % better; a channel the turbulence dominates, where every
//    file's NRMSE sits near 1 (p, r, beta in light turbulence: the true file and a x1.5 prior
//    0.245 / 0.243 in p on the Anaconda's sysid flight), moves it little, while the channels a
//    wrong model loses (q, Va, theta: 0.61 / 0.87, 0.12 / 0.70, 0.35 / 2.48 there) decide it. The
//    measured channels' std normalises each, so units and magnitudes do not weigh.
//  * One-step residuals (equation error: Klein and Morelli ch. 5), at every scored sample, from
//    the logged state, wind and commands at that sample: measured minus model specific force
//    (forces_moments(...).specific_force: what the accelerometer measures) against a_x a_y a_z,
//    and measured minus model angular acceleration (derivative()) against p_dot q_dot r_dot; RMS
//    per axis, and in coefficient units: m da / (qbar S) for C_X C_Y C_Z; (J dw)_x / (qbar S b),
//    (J dw)_y / (qbar S c), (J dw)_z / (qbar S b) for C_ell C_m C_n (qbar = rho Va^2 / 2 of the
//    file's rho; J the file's inertia: the moment the model misses, Beard & McLain eq. 3.17).
//    The accelerometer is taken to sit at the CG (flight_data.hpp applies no lever arm).
//
// Units SI, angles rad, body FRD, NED. Errors: ConfigError, one line naming the log, when the
// estimate is never valid or no window of `window_s` is airborne (airborne_windows).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "sysid/airborne.hpp"
#include "sysid/flight_data.hpp"
#include "tern/aircraft.hpp"

namespace tern::core::sysid {

struct ValidateOptions {
  double window_s = 5.0;    ///< s, re-initialisation interval (window length), > 0
  AirborneRule ground;      ///< off the ground (airborne.hpp): the log's window, else above where it stood still
  double min_Va = 8.0;      ///< m/s, airspeed for a sample to count as airborne
  double max_step = 0.005;  ///< s, longest RK4 step between two samples
};

/// The scored channels, in the order of every table: body rates, air data, attitude.
inline constexpr std::size_t kChannels = 8;
struct ChannelSpec {
  const char* name;  ///< uavbook symbol
  const char* unit;  ///< SI unit of the channel (JSON, plots)
  bool angle;        ///< compared through wrap_pi
  std::vector<double> FlightSeries::*measured;
};
extern const std::array<ChannelSpec, kChannels> kChannelSpecs;

/// The one-step residuals' axes: specific force, then angular acceleration.
inline constexpr std::size_t kAxes = 6;
struct AxisSpec {
  const char* name;         ///< measured channel of FlightSeries
  const char* unit;         ///< its SI unit
  const char* coefficient;  ///< the residual in coefficient units
  std::vector<double> FlightSeries::*measured;
};
extern const std::array<AxisSpec, kAxes> kAxisSpecs;

/// Samples [begin, end) of a series, airborne from begin to end inclusive (end, airborne too, closes
/// it and starts the next window): t[end - 1] - t[begin] < window_s <= t[end] - t[begin].
struct Window {
  std::size_t begin = 0, end = 0;
};

/// The model's prediction of every channel at every sample of the series (NaN outside windows).
struct Prediction {
  std::array<std::vector<double>, kChannels> channel;
  std::size_t diverged = 0;  ///< windows whose simulated state stopped being finite
};

/// Fit of one channel (header: definitions). NaN where undefined (no samples; std(y) = 0).
struct ChannelFit {
  double rms_error = 0, std_measured = 0, nrmse = 0, theil_u = 0;
  std::size_t samples = 0;
};

/// One-step residual of one axis: RMS of measured minus model, in the axis's unit and as a
/// coefficient.
struct AxisResidual {
  double rms = 0, coefficient_rms = 0;
  std::size_t samples = 0;
};

/// Everything scored for one aircraft file on one log.
struct AircraftScore {
  std::string file;        ///< the aircraft file as given
  std::string name;        ///< the file's `name`
  double servo_tau = 0.0;  ///< s, the file's servo lag, through which the series' commands were passed
  std::array<ChannelFit, kChannels> fit;
  std::array<AxisResidual, kAxes> one_step;
  Prediction prediction;
};

/// The files' overall scores on one log (header, "Overall").
struct OverallScores {
  std::vector<std::string> channels;  ///< the channels averaged over (kChannelSpecs' names): finite for every file
  std::vector<double> nrmse;          ///< per file, in the files' order: the geometric mean of its NRMSE over `channels`; NaN if none
  std::vector<std::size_t> ranking;   ///< indices of the files, best (smallest) first; ties in the files' order
};

/// The overall scores of `files` (header). A channel whose NRMSE is 0 for a file counts as 1e-12.
OverallScores overall_scores(const std::vector<AircraftScore>& files);

/// True at each sample where the aircraft counts as airborne (header).
std::vector<unsigned char> airborne(const FlightSeries& s, const ValidateOptions& o);

/// The windows of the series (header). Throws ConfigError naming `log` when the estimate is
/// never valid, or when no window of o.window_s is airborne.
std::vector<Window> airborne_windows(const FlightSeries& s, const ValidateOptions& o, const std::string& log);

/// The open-loop simulation of every window (header).
Prediction simulate_windows(const FlightSeries& s, const Aircraft& ac, const std::vector<Window>& windows, const ValidateOptions& o);

/// NRMSE, Theil's U and RMS error of `predicted` against `measured` over the scored samples of
/// `windows` (header); `angle`: errors through wrap_pi.
ChannelFit channel_fit(const std::vector<double>& measured, const std::vector<double>& predicted, const std::vector<Window>& windows,
                       bool angle);

/// The one-step residuals of every axis over the scored samples of `windows` (header).
std::array<AxisResidual, kAxes> one_step_residuals(const FlightSeries& s, const Aircraft& ac, const std::vector<Window>& windows);

/// Simulation, fits and residuals of one aircraft file on the series (loaded with its servo lag).
AircraftScore score_aircraft(const FlightSeries& s, const Aircraft& ac, const std::string& file, const std::vector<Window>& windows,
                             const ValidateOptions& o);

}  // namespace tern::core::sysid
