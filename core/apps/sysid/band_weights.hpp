// core/apps/sysid/band_weights.hpp: the weights of a frequency-domain regression whose residual
// power differs across the band (identify.hpp, the band fits).
//
// Why. The equation error's residual is not white: in the side force it is C_Y_beta times the
// lateral gusts the flight path's sideslip misses, whose power falls as 1/f^2 above a few tenths
// of a Hz (the Dryden spectrum), on top of the accelerometer's flat noise. Measured on the bench's
// realistic seed 4 (true prior): the side force's residual power 590 at 0.1-0.2 Hz, 55 at 0.5-0.7
// Hz, 45 at 1-2 Hz (arbitrary units). Unweighted, the noisiest rows count as much as the
// cleanest. Weighting each row by the inverse of the residual power at its frequency is the
// frequency-domain maximum-likelihood (generalised least squares) estimate for residuals
// independent from frequency to frequency with a power that varies (Pintelon and Schoukens,
// *System Identification: A Frequency Domain Approach*, 2nd ed., 2012, on weighted least squares;
// Klein and Morelli, *Aircraft System Identification*, 2006, sec. 5.2.1 on coloured residuals).
// The power is estimated from a first, unweighted fit's residual (a two-stage estimate), smoothed
// over the `neighbours` rows nearest in frequency across all segments.
//
// Units: Hz; the weights none (relative, mean square 1). Errors: std::invalid_argument when
// residual's length is not row_hz's.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace tern::core::sysid {

/// Rows whose neighbours give a row's residual power: 31 rows, some 0.05 Hz at the band's low end
/// on a 600-s flight (five 120-s pieces), enough for the mean of |v|^2 to be within 20 %.
constexpr std::size_t kWeightNeighbours = 31;

/// The smallest residual power a row's weight assumes, as a share of the band's mean: where a fit
/// is near exact (a simulated flight without noise), the residual's dips are the model's small
/// errors, not a cleaner measurement, and unbounded weights would fit those rows alone.
constexpr double kMinPowerShare = 0.01;

/// The square roots of the weights 1 / sigma^2(f) of each row (multiply the rows of X, Z and z by
/// them), sigma^2 the mean of |residual|^2 over the `neighbours` rows nearest in frequency;
/// `row_hz` the rows' frequencies (Spectra::row_frequencies), `residual` the first fit's |v|.
/// Empty when the residual is zero everywhere (an exact fit: nothing to weight).
Eigen::VectorXd residual_power_weights(const std::vector<double>& row_hz, const Eigen::VectorXd& residual,
                                       std::size_t neighbours = kWeightNeighbours);

}  // namespace tern::core::sysid
