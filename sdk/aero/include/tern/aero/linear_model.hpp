// tern/aero/linear_model.hpp: `tern aero linearize` (issue 11): Beard & McLain ch. 5 state-space models about
// a trim (central differences of the uavbook nonlinear model, model.hpp) and the transfer-function
// coefficients of sec. 5.4. Plain C++ (Eigen), no host or plugin types.
//
// Errors: compute_trim's (std::runtime_error, one line) when the trim does not exist.
#pragma once

#include <map>
#include <string>

#include <Eigen/Core>

#include "tern/aircraft.hpp"
#include "tern/aero/trim.hpp"

namespace tern::aero {

/// Beard & McLain ch. 5 linear models and transfer-function coefficients.
struct LinearModel {
  sim::TrimResult trim;
  double Va = 0;  ///< m/s
  // x_lon = [u w q theta h], u_lon = [delta_e delta_t]; x_lat = [v p r phi psi], u_lat = [delta_a delta_r]
  // (SI units, rad, body axes FRD; h up)
  Eigen::Matrix<double, 5, 5> A_lon, A_lat;
  Eigen::Matrix<double, 5, 2> B_lon, B_lat;
  std::map<std::string, double> tf;  ///< a_phi1, a_phi2, a_theta1..3, a_V1..3, a_beta1, a_beta2
};

/// Trims `ac` as `req` asks and linearizes about the trim.
LinearModel linearize(const tern::Aircraft& ac, const sim::TrimRequest& req);

}  // namespace tern::aero
