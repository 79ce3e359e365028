// core/apps/sysid/equation_error.hpp: the equation-error fits of the identification (identify.hpp):
// a model's terms in the excitation's band, a bias from the trim windows, a trim fit on the
// windows' means; which terms were excited, which the data determined, and what is recorded of
// each. Context is what every axis's step (identify_*.hpp) works on.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sysid/identify.hpp"
#include "sysid/regression.hpp"
#include "sysid/spectra.hpp"
#include "tern/math.hpp"

namespace tern::core::sysid {

using Member = double AeroCoefficients::*;
using M = AeroCoefficients;

/// When a regressor counts as excited: `peak` of |signal| (rates) or the standard deviation of
/// signal less its trim-window means (angles, surfaces) above `threshold`; `what` words the
/// failure ("pitch rate never above 5 deg/s").
struct Excitation {
  const Col* signal = nullptr;
  bool peak = false;
  double threshold = 0.0;
  std::string what;
};

/// One term of a model: coefficient * regressor.
struct Term {
  std::string name;
  Member member = nullptr;
  const Col* x = nullptr;
  Excitation excitation;
  const Col* instrument = nullptr;  ///< the same quantity measured with an independent error (or none)
};

struct Context {
  const AeroSamples& a;
  const Layout& L;
  const SysidOptions& o;
  Spectra spectra;
  AeroCoefficients& coef;  ///< the identified model so far
  const AeroCoefficients& prior;
  SysidResult& result;
};

/// The prior of a term kept at it is taken as uncertain by this fraction of its value (a model
/// from XFLR5 or the book's sister aircraft: x0.6 .. x1.5); its effect on the estimates fitted
/// beside it is added to their bounds (a consider covariance).
constexpr double kPriorUncertainty = 0.5;

/// rad, RMS about its trim: a flow angle or a surface that moved less excites nothing.
inline constexpr double kMinAngleMotion = 0.3 * kRadPerDeg;

/// The excitation tests (identify.hpp), worded for the log.
struct Signals {
  Excitation alpha, beta, p, q, r, delta_a, delta_e, delta_r;
};

Signals signals(const AeroSamples& a, const Col& alpha, const Col& beta);

/// The start of the note a band fit gives a term excited and not collinear whose bound exceeds
/// max_relative_error of its estimate (band_fit): the output error tries such a term again (refine).
inline constexpr const char* kPoorlyDetermined = "poorly determined";

/// Term t's estimate as it stands in c.coef, recorded in the result by `method`; returns the record.
CoefficientEstimate& record(Context& c, const Term& t, const std::string& method);

/// z = sum of terms, in the frequency domain over the band. Terms not excited keep the prior (moved
/// to the left side); of those collinear or poorly determined after a fit, the least determined
/// (least_determined) keeps its prior and the others are fitted again. What the
/// kept priors' uncertainty (kPriorUncertainty) moves the fitted terms by is added to their bounds.
/// Each fit is made twice, the second with the rows weighted by the inverse of the first's residual
/// power about their frequency (band_weights.hpp: the residual's power differs across the band, the
/// gusts the flight path misses at its low end); what the two disagree by is added to the bounds (an
/// instrument that shares some of the noise biases them differently). Collinearity is judged on the
/// rows unweighted.
void band_fit(Context& c, const std::string& axis, const Col& z, const std::vector<Term>& terms);

/// Of the terms `failed` after a band fit, the one to keep at its prior first (band_fit): the
/// largest standard error against the size its prior expects, |prior| (|estimate| where the prior
/// is 0). A weak instrument can throw an estimate far from any value (C_Y_beta +1.9 +- 2.2 against
/// a prior of -0.59): measured against itself it would look better determined than a small term
/// (C_Y_delta_a -1.4 +- 1.1 against 0.045) that costs the fit little to hold. failed.size() when
/// none failed. Errors: std::invalid_argument when the four differ in length.
std::size_t least_determined(const Eigen::VectorXd& estimate, const Eigen::VectorXd& std_error, const std::vector<double>& prior,
                             const std::vector<bool>& failed);

/// A bias term from the trim windows: mean of z less the model's other terms.
void bias_fit(Context& c, const std::string& name, Member member, const Col& z, const std::vector<Term>& terms);

/// Time-domain least squares on the trim windows' means: z = X theta, with `instruments` (one per
/// column, or empty: ordinary least squares) the instrumental-variable estimate; the bounds never
/// below the delete-one-batch jackknife's (trim_jackknife). Returns it.
LsEstimate trim_fit(Context& c, const Col& z, const std::vector<const Col*>& columns, const std::vector<const Col*>& instruments = {});

/// The band's estimate of `name`, taken out of the result (reported, not adopted); nullopt if the
/// band did not identify it.
std::optional<CoefficientEstimate> take_out(Context& c, const std::string& name);
/// The estimate of the coefficient `name` in r.coefficients; null when it has none.
CoefficientEstimate* find_estimate(SysidResult& r, const std::string& name);
const CoefficientEstimate* find_estimate(const SysidResult& r, const std::string& name);

}  // namespace tern::core::sysid
