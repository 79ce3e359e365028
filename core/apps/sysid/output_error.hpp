// core/apps/sysid/output_error.hpp: the output-error refinement of the rotational axes (Klein and
// Morelli, *Aircraft System Identification*, 2006, ch. 6), after the equation-error estimates
// (identify.hpp).
//
// The model. The body rates w = (p, q, r), rad/s, integrated from the uavbook's moment equations
// (Beard and McLain, *Small Unmanned Aircraft*, eqs. 3.13 and 3.17, the Gamma terms of the prior's
// inertia, J with -Jxz off the diagonal):
//   p' = G1 p q - G2 q r + G3 l + G4 n,  q' = G5 p r - G6 (p^2 - r^2) + m / Jy,
//   r' = G7 p q - G1 q r + G4 l + G8 n,
//   l = qbar S b (C_ell_0 + C_ell_beta beta + C_ell_p b p / (2 Va) + C_ell_r b r / (2 Va) + C_ell_delta_a delta_a
//       + C_ell_delta_r delta_r) - Q_p,
//   m = qbar cos^2(beta) S c (C_m_0 + C_m_alpha alpha + C_m_q c q / (2 V_xz) + C_m_delta_e delta_e),
//   n = qbar S b (C_n_0 + ... the same terms as l with C_n_*),
// (the uavbook model in its linear range, tern/aero/model.hpp), driven by the measured Va (from
// qbar), alpha, beta, the commands in force and the prior's propeller torque Q_p, all linearly
// interpolated between samples, RK4 over each sample interval. A group of axes is integrated (pitch:
// q; lateral: p and r, coupled through Jxz and the cross derivatives); the other rates enter the
// inertial coupling as measured. Each window of the data restarts from the measured rates (the
// simulation does not carry one gust's error through the flight).
//
// The commands' timing. Besides the coefficients, theta can carry a delay per surface
// ("delay_a", "delay_e", "delay_r", s): the surface's commands act that much later than the data
// has them, shifted over each run of consecutive windows by a windowed-sinc fractional delay
// (shift_run; held at the run's ends), the flow angles' parts of them with them (RateData). Klein and Morelli ch. 10 (data compatibility)
// fit such a time shift beside the model's parameters: in a closed loop the equation error cannot tell a late command from a controller
// that feeds the rate back (the command is computed from the rate it is regressed beside), while the simulated rates, integrated from the
// commands alone, depend on when the commands act.
//
// The fit. theta (the free coefficients) minimises J = sum_k v_k^T R^-1 v_k, v_k the measured less
// the simulated rates, by Eigen's Levenberg-Marquardt (unsupported/Eigen/LevenbergMarquardt, MINPACK's
// lmder) with central-difference sensitivities; R, the residual covariance, is re-estimated from
// the residuals after each fit and the fit repeated until theta settles (K&M sec. 6.2, the
// relaxation technique). It starts from the equation-error estimates.
//
// The bounds. The Cramer-Rao bound M^-1, M = sum_k S_k^T R^-1 S_k (S the output sensitivities),
// assumes white residuals; flight residuals are coloured (turbulence, model error), so the reported
// standard error is the largest of: that bound; Morelli and Klein's correction (J. Guidance 20(1),
// 1997; K&M sec. 6.3) M^-1 [sum_i sum_j S_i^T R^-1 R_vv(i - j) R^-1 S_j] M^-1 with the residual
// autocorrelation R_vv up to max_lag_s; and the same sandwich with each window's residuals taken
// as one independent batch (what a residual correlated across a whole window does).
//
// Units SI, rad, rad/s. Errors: std::invalid_argument for mismatched lengths, an unknown coefficient
// name, a coefficient not in the axes' moments, or no window with at least 3 samples.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "sysid/aero_samples.hpp"
#include "tern/aircraft.hpp"

namespace tern::core::sysid {

/// x (sampled at t) at t_k - tau for each k of one run of consecutive samples [b, e), into
/// out[b, e): a fractional delay by a Lanczos-windowed sinc over the run's mean interval (at 50 Hz
/// within 0.4 % of a sinusoid up to 5 Hz and 0.8 % at 10 Hz, where linear interpolation between
/// samples loses 5 and 17 %), the run's first and last samples held beyond its ends. How the output
/// error shifts a surface's commands by its delay (header). out.size() >= e. Errors:
/// std::invalid_argument for a run whose times do not increase or a tau that is not a number.
void shift_run(const std::vector<double>& t, const std::vector<double>& x, double tau, std::size_t b, std::size_t e,
               std::vector<double>& out);

/// The names of the commands' delays among output_error's free parameters (header): aileron, elevator, rudder.
inline constexpr std::array<const char*, 3> kDelayNames = {"delay_a", "delay_e", "delay_r"};
/// The surfaces those delays are of, in the same order, as notes name them.
inline constexpr std::array<const char*, 3> kSurfaceNames = {"aileron", "elevator", "rudder"};

/// Which rates the model integrates.
enum class RateAxes { pitch, lateral };

struct OutputErrorOptions {
  bool enabled = true;
  double window_s = 5.0;      ///< s, the simulation restarts from the measured rates this often (> 0)
  double max_lag_s = 2.0;     ///< s, longest lag of the residual autocorrelation in the coloured bound
  int max_relaxations = 5;    ///< fits with R fixed, R re-estimated after each (>= 1)
  int max_evaluations = 400;  ///< model simulations per Levenberg-Marquardt fit
  /// model simulations in all, the finite-difference Jacobians' included: no further relaxation
  /// once spent. Tern's and the foreign benches' flights take 25-90 (pitch) and 336-506 (roll and
  /// yaw); a log the model cannot follow took 3529 (21 s of a 28-s sysid run).
  int max_simulations = 1200;
  double theta_tolerance = 1e-3;  ///< relaxation stops when no coefficient moves more than this many standard errors
  bool hold_commands = false;     ///< the surfaces held over each sample interval (raw zero-order-hold data) instead of interpolated
  /// s, aileron, elevator, rudder: each surface's commands act this much later than the data has
  /// them (header, "The commands' timing"); a free delay starts here
  std::array<double, 3> command_shift_s = {0.0, 0.0, 0.0};
};

/// The measured side, one entry per sample (every vector the same length); windows are runs of
/// consecutive samples, each simulated from its first sample's measured rates.
struct RateData {
  std::vector<double> t;                                     ///< s
  std::vector<double> Va;                                    ///< m/s, sqrt(2 qbar / rho)
  std::vector<double> alpha, beta;                           ///< rad
  std::vector<double> delta_a, delta_e, delta_r;             ///< rad, the commands in force
  std::vector<double> Q_p;                                   ///< N m, the prior's propeller torque
  std::vector<double> p, q, r;                               ///< rad/s, measured
  std::vector<std::pair<std::size_t, std::size_t>> windows;  ///< [begin, end) of each window
  /// rad/rad: how much of each command the flow angles above carry, where they were reconstructed
  /// from the forces (identify.hpp): beta from the side force -C_Y_delta_a / C_Y_beta of the aileron
  /// and -C_Y_delta_r / C_Y_beta of the rudder, alpha from the lift -C_L_delta_e / C_L_alpha of the
  /// elevator. A command shifted by its delay moves that part with it (0: angles that do not).
  double beta_per_delta_a = 0.0, beta_per_delta_r = 0.0, alpha_per_delta_e = 0.0;
  std::size_t size() const { return t.size(); }
};

struct OutputErrorFit {
  RateAxes axes = RateAxes::pitch;
  std::vector<std::string> names;        ///< the free coefficients, the aircraft file's keys
  Eigen::VectorXd start, theta;          ///< the equation-error start and the output-error estimate
  Eigen::VectorXd std_error;             ///< 1 sigma, the largest of the three bounds (header)
  Eigen::VectorXd std_error_white;       ///< the Cramer-Rao bound, white residuals
  Eigen::MatrixXd residual_covariance;   ///< R, (rad/s)^2, outputs in the order p q r of the axes
  Eigen::VectorXd rms_start, rms;        ///< rad/s per output: the start's and the estimate's residuals
  Eigen::VectorXd r_squared;             ///< per output, 1 - sum v^2 / sum (z - mean z)^2
  int relaxations = 0, evaluations = 0;  ///< fits made, model simulations in all
  bool budget_spent = false;             ///< relaxation stopped by max_simulations
  std::size_t samples = 0;               ///< residual samples per output
};

/// The windows' data from the airborne samples: `alpha` and `beta` the flow angles to drive the
/// model with (identify's, from the forces), `segments` runs of consecutive samples, cut into
/// windows of `window_s` (a last piece shorter than half of it joins the window before).
RateData rate_data(const AeroSamples& a, const std::vector<double>& alpha, const std::vector<double>& beta,
                   const std::vector<std::pair<std::size_t, std::size_t>>& segments, const Aircraft& prior, double window_s);

/// The rates the model gives over every window with coefficients `aero` (header): [p q r] per
/// sample; samples outside every window are the measured rates.
std::vector<Eigen::Vector3d> simulate_rates(const RateData& d, const Aircraft& prior, const AeroCoefficients& aero, RateAxes axes);

/// Fits the coefficients named in `free` (keys of the aircraft file among C_ell_*, C_m_*, C_n_*
/// of the axes' moments; and kDelayNames' delays of the axes' surfaces, from o.command_shift_s) from
/// `start`, the others held (header).
OutputErrorFit output_error(const RateData& d, const Aircraft& prior, const AeroCoefficients& start, RateAxes axes,
                            const std::vector<std::string>& free, const OutputErrorOptions& o);

/// The member of AeroCoefficients a rotational coefficient's key names; throws std::invalid_argument.
double AeroCoefficients::*moment_coefficient(const std::string& name);

}  // namespace tern::core::sysid
