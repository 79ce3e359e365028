// core/apps/sysid/jackknife.hpp: the scatter bound of the identification's fits (identify.hpp):
// the delete-one-batch jackknife over the flight's pieces (spectra.hpp), in the band and on the
// trim windows.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "sysid/spectra.hpp"

namespace tern::core::sysid {

/// The jackknife's standard errors of the delete-one-batch estimates `thetas` (p each): sqrt((G - 1) /
/// G sum (theta_(i) - mean)^2). Zero with fewer than three.
Eigen::VectorXd jackknife_se(const std::vector<Eigen::VectorXd>& thetas, Eigen::Index p);

/// The scatter bound: the delete-one-batch jackknife over the segments (batches of at most
/// kMaxSegment): the regression refitted without each batch in turn, the variance
/// (G - 1) / G sum (theta_(i) - mean)^2 (Efron and Tibshirani, *An Introduction to the Bootstrap*,
/// ch. 11): what the flight's pieces disagree by, which no residual model of one fit sees. Unlike a
/// fit of each batch alone it stays defined when a batch holds no excitation of its own (the take-off's,
/// an instrument weak there). Zero when fewer than three batches hold rows.
Eigen::VectorXd batch_scatter(const Spectra& spectra, const Eigen::MatrixXcd& X, const Eigen::VectorXcd& z, const Eigen::MatrixXcd& Z,
                              bool iv);

/// s: the trim jackknife's blocks of consecutive windows span at least this: several times the
/// gusts' correlation time (Dryden's longitudinal scale, 200 m at low altitude, at 25 m/s: 8 s;
/// uavbook sec. 4.4), so that the blocks' errors are nearly independent, and enough blocks (nine in
/// 300 s) that the bound is not one of three pieces' scatter (2 degrees of freedom).
constexpr double kTrimBlock = 30.0;

/// The delete-one-block jackknife of a trim fit (Kunsch 1989; Efron and Tibshirani ch. 11): the
/// fit without each block of consecutive trim windows (window_s each, kTrimBlock together) in
/// turn. Zero with fewer than three blocks.
Eigen::VectorXd trim_jackknife(const Layout& L, double window_s, const Eigen::MatrixXd& X, const Eigen::VectorXd& z,
                               const Eigen::MatrixXd* Z);

}  // namespace tern::core::sysid
