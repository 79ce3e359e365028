// core/apps/sysid/sideslip_instrument.hpp: an instrument for the sideslip in the side force's
// regression (identify.hpp): the sideslip a linear lateral model gives for the flight's own aileron
// and rudder commands, frequency by frequency; and likewise alpha for the lift's, from the
// longitudinal model and the elevator and throttle.
//
// Why. The side force's regression needs beta, and beta is not measured: the flight path's
// reconstruction (flight_data.hpp) misses the lateral gusts, an error as large as what the rudder
// moves beta by, independent of the true beta's forced part. Least squares on it flattens C_Y_beta
// (to ~0.4 of the truth on the shipped bench), and every moment derivative in beta scales with it.
// An instrumental variable removes that bias when it correlates with the true sideslip and not with
// the gusts (Klein and Morelli, *Aircraft System Identification*, sec. 5.5; Soderstrom and Stoica,
// *System Identification*, ch. 8: instruments from a model's simulated output). The commands are
// set by the excitation (and the controller); the model's sideslip for them is such a signal. The
// model needs only the right shape, not the right coefficients: a wrong prior makes the instrument
// weaker (wider bounds), not the estimate biased.
//
// The model: Beard and McLain ch. 5 (sec. 5.5, eq. 5.43), x = [v p r phi psi], u = [delta_a
// delta_r], linearised about the trim at the stretch's mean airspeed by `tern aero linearize`'s
// code (tern/aero/linear_model.hpp). At frequency f: x(f) = (j 2 pi f I - A)^-1 B u(f),
// beta(f) = v(f) / Va.
//
// Units: Hz, rad; the spectra are finite Fourier transforms (regression.hpp's `fourier`).
// Errors: std::invalid_argument for spectra of lengths other than f's.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "tern/aero/linear_model.hpp"

namespace tern::core::sysid {

/// beta(f) of the lateral model `m` for the commands' spectra at the frequencies `f_hz` (header).
Eigen::VectorXcd modelled_sideslip(const tern::aero::LinearModel& m, const std::vector<double>& f_hz, const Eigen::VectorXcd& delta_a,
                                   const Eigen::VectorXcd& delta_r);

/// p(f) / Va and r(f) / Va of the same model (rad/m): times b / 2, the nondimensional rates'
/// instruments in the rolling and yawing moments (identify.hpp).
Eigen::VectorXcd modelled_roll_rate(const tern::aero::LinearModel& m, const std::vector<double>& f_hz, const Eigen::VectorXcd& delta_a,
                                    const Eigen::VectorXcd& delta_r);
Eigen::VectorXcd modelled_yaw_rate(const tern::aero::LinearModel& m, const std::vector<double>& f_hz, const Eigen::VectorXcd& delta_a,
                                   const Eigen::VectorXcd& delta_r);

/// alpha(f) of the longitudinal model (x = [u w q theta h], u = [delta_e delta_t], eq. 5.50):
/// w(f) / Va for the commands' spectra, the lift's instrument likewise.
Eigen::VectorXcd modelled_alpha(const tern::aero::LinearModel& m, const std::vector<double>& f_hz, const Eigen::VectorXcd& delta_e,
                                const Eigen::VectorXcd& delta_t);

}  // namespace tern::core::sysid
