// core/apps/sysid/regression.hpp: linear regression for the equation-error method (Klein and
// Morelli, *Aircraft System Identification*, 2006: ch. 5 least squares, sec. 5.2.1 the
// parameter covariance with coloured residuals; ch. 7 the frequency-domain equation error),
// plain Eigen, no host types.
//
// The model is z = X theta + v: z (n) the measured coefficient, X (n x p) the regressors.
//  * least_squares: theta = (X^T X)^-1 X^T z in the time domain. Its covariance is computed two
//    ways: the textbook s^2 (X^T X)^-1, which assumes white residuals, and Morelli and Klein's
//    (J. Guidance 20(1), 1997, "Accuracy of aircraft parameter estimates from flight data";
//    K&M eq. 5.81) (X^T X)^-1 [sum_i sum_j x_i R_vv(i-j) x_j^T] (X^T X)^-1 with R_vv the
//    residual autocorrelation estimated up to max_lag samples: the bound that stays honest when
//    the residuals are coloured (turbulence, model error), as flight residuals always are.
//  * least_squares_frequency: the same regression on the finite Fourier transforms of z and X
//    at chosen frequencies (K&M sec. 7.2.2): theta = Re(X~^H X~)^-1 Re(X~^H z~), covariance
//    s^2 Re(X~^H X~)^-1 with s^2 the residual power, and (coloured residuals: a residual power
//    that differs across the band) the sandwich D Re(X~^H diag|v|^2 X~) D, D = Re(X~^H X~)^-1;
//    optionally with instrumental variables (below). Only the band the excitation filled enters,
//    so bias terms and slow drifts (the trim, the estimator's wind) fall out, and noise above
//    the band does not enter.
// Errors: std::invalid_argument for mismatched shapes or fewer rows than parameters.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace tern::core::sysid {

struct LsEstimate {
  Eigen::VectorXd theta;            ///< the estimate, one per regressor column
  Eigen::VectorXd std_error;        ///< standard errors: the coloured-residual bound (never below the white one)
  Eigen::VectorXd std_error_white;  ///< standard errors assuming white residuals, s^2 (X^T X)^-1
  Eigen::VectorXd residual;         ///< z - X theta (time domain; magnitudes in the frequency domain)
  double s2 = 0.0;                  ///< residual variance, z units^2
  double r_squared = 0.0;           ///< 1 - |v|^2 / |z - mean(z)|^2 (frequency domain: |z~|^2)
  /// With instruments, Pesaran and Smith's generalized R^2 (Econometrica 62(3), 1994, "A
  /// generalized R^2 criterion for regression models estimated by the instrumental variables
  /// method"): 1 - |z - X^ theta|^2 / |z - mean(z)|^2, X^ = P_Z X the regressors the instruments
  /// predict. An instrumented regressor's own error (the gust in a reconstructed alpha) is in v
  /// and can make r_squared negative for a model that holds; it is not in z - X^ theta. Without
  /// instruments: r_squared.
  double r_squared_generalized = 0.0;
  std::size_t rows = 0;
};

/// Time-domain least squares with the coloured-residual covariance (header). max_lag in samples.
/// With `instruments` Z (the shape of X), the instrumental-variable estimate theta = (Z^T X)^-1
/// Z^T z (K&M sec. 5.5), covariance D [sum_i sum_j z_i R_vv(i-j) z_j^T] D^T, D = (Z^T X)^-1:
/// consistent when a regressor carries an error that Z's columns do not correlate with;
/// r_squared_generalized then judges the fit.
LsEstimate least_squares(const Eigen::MatrixXd& X, const Eigen::VectorXd& z, std::size_t max_lag,
                         const Eigen::MatrixXd* instruments = nullptr);

/// Frequency-domain least squares on complex rows (header). With `instruments` Z (the shape of
/// X), the instrumental-variable estimate theta = Re(Z~^H X~)^-1 Re(Z~^H z~) (K&M sec. 5.5; Ljung,
/// *System Identification*, sec. 7.6): consistent when a regressor carries an error, so long as
/// the instrument's column measures the same quantity with an independent error; covariance
/// D Re(Z~^H diag|v|^2 Z~) D^T, D = Re(Z~^H X~)^-1.
LsEstimate least_squares_frequency(const Eigen::MatrixXcd& X, const Eigen::VectorXcd& z, const Eigen::MatrixXcd* instruments = nullptr);

/// Finite Fourier transform of `x` sampled at times t (s, uniform dt) at each frequency of f (Hz):
/// X(f) = sum_k x_k exp(-j 2 pi f t_k) dt (K&M eq. 7.8, the Euler approximation, exact for a
/// band-limited signal well inside the Nyquist frequency). Rows follow f.
Eigen::VectorXcd fourier(const std::vector<double>& x, const std::vector<double>& t, const std::vector<double>& f_hz);

/// Pairwise correlation coefficients of the columns of X (p x p), for the collinearity test.
Eigen::MatrixXd column_correlation(const Eigen::MatrixXd& X);
/// The same for complex columns (the real part of the normalised inner products).
Eigen::MatrixXd column_correlation(const Eigen::MatrixXcd& X);

}  // namespace tern::core::sysid
