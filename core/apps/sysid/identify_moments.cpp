// core/apps/sysid/identify_moments.cpp: the pitching moment, output error, the gyros' coupling (identify_moments.hpp).
#include "sysid/identify_moments.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

#include <fmt/format.h>

namespace tern::core::sysid {

void pitching_moment(Context& c, const Col& alpha, bool accel) {
  const AeroSamples& a = c.a;
  const Signals x = signals(a, alpha, a.beta);
  const std::vector<Term> pitch = {{"C_m_alpha", &M::C_m_alpha, &alpha, x.alpha, accel ? &a.alpha : nullptr},
                                   {"C_m_q", &M::C_m_q, &a.q_hat, x.q},
                                   {"C_m_delta_e", &M::C_m_delta_e, &a.delta_e, x.delta_e}};
  band_fit(c, "pitch", a.C_m, pitch);
  bias_fit(c, "C_m_0", &M::C_m_0, a.C_m, pitch);
}

namespace {

/// s, the elevator delays the pitch rate's timing fit is profiled over (timing_fit): a 20-ms grid
/// from commands stamped late to a slow servo bus
constexpr std::array<double, 7> kPitchDelayGrid = {-0.04, -0.02, 0.0, 0.02, 0.04, 0.06, 0.08};

/// The timing fits' cost (they run beside the refinement): the profile's fits stop after this many
/// simulations, and the joint fit after two relaxations (its delays settle in the first)
constexpr int kProfileEvaluations = 80;
constexpr int kTimingRelaxations = 2;

/// The least share of a measured rate's variance the output error's simulated rates must explain
/// for its estimates to be used. tern's flights reach 0.87-0.98 (pitch, roll, yaw), logs rewritten
/// to other rates 0.78-0.95; a log without a pitot 0.37 in pitch: its simulation, on the
/// estimator's gust-free airspeed, settled on C_m_q -105 where the equation error had -36.0 +- 8.7
/// (truth -38.2), and their mean was adopted 85 % off.
constexpr double kMinOutputErrorRSquared = 0.5;

/// Whether surface s (aileron, elevator, rudder) moved: the equation error's test of a command
/// (signals(), its RMS about the trim windows' means above kMinAngleMotion).
bool surface_moved(const Context& c, std::size_t s) {
  const Col& delta = s == 0 ? c.a.delta_a : s == 1 ? c.a.delta_e : c.a.delta_r;
  return rms(detrended(delta, c.L)) > kMinAngleMotion;
}

/// The timing fit's parameters (SysidOptions::estimate_delays): the delays and the derivatives a
/// shifted command trades against (the damping and control derivatives, the rate cross
/// derivatives C_ell_r and C_n_p, the static stability beside them); the other coefficients held
/// at the equation error's values. Held, the cross derivatives kept the equation error's answer for
/// the timing as loaded and pulled the delay toward it: on the Anaconda's foreign log (seed 2, true
/// prior) the aileron's delay from a start at 0 ms 2.1 ms, from 4 ms 3.1; free, 2.6 and 3.4 (the
/// truth 3.7-4). A surface that never moved brings neither its delay nor its control derivative
/// (they would leave the fit singular); its delay_shift says why.
void add_timing(Context& c, RateAxes axes, std::vector<std::string>& free) {
  static constexpr std::array<const char*, 3> kControl = {"C_ell_delta_a", "C_m_delta_e", "C_n_delta_r"};
  const std::vector<std::string> extra =
      axes == RateAxes::pitch ? std::vector<std::string>{"C_m_0", "C_m_alpha", "C_m_q", "C_m_delta_e", kDelayNames[1]}
                              : std::vector<std::string>{"C_ell_beta", "C_ell_p", "C_ell_r",     "C_ell_delta_a", "C_n_beta",
                                                         "C_n_p",      "C_n_r",   "C_n_delta_r", kDelayNames[0],  kDelayNames[2]};
  std::array<bool, 3> still{};
  for (std::size_t s = 0; s < 3; ++s)
    if (std::find(extra.begin(), extra.end(), kDelayNames[s]) != extra.end() && !surface_moved(c, s))
      still[s] = true, c.result.delay_shift[s] = {0.0, 0.0, false,
                                                  fmt::format("the {} never moved more than {:g} deg about its trim", kSurfaceNames[s],
                                                              kMinAngleMotion / kRadPerDeg)};
  for (const auto& name : extra) {
    bool skip = false;
    for (std::size_t s = 0; s < 3; ++s) skip = skip || (still[s] && (name == kDelayNames[s] || name == kControl[s]));
    if (!skip && std::find(free.begin(), free.end(), name) == free.end()) free.push_back(name);
  }
}

/// The delays of a timing pass's fit into the result (identify.hpp, delay_shift).
void take_delays(Context& c, const OutputErrorFit& f) {
  for (std::size_t j = 0; j < f.names.size(); ++j)
    for (std::size_t s = 0; s < kDelayNames.size(); ++s)
      if (f.names[j] == kDelayNames[s]) {
        const auto J = static_cast<Eigen::Index>(j);
        c.result.delay_shift[s] = {f.theta[J], f.std_error[J], true, ""};
      }
}

/// The timing pass's fit of one group of axes. The pitch rate's is first profiled over a grid of
/// elevator delays (the coefficients fitted at each): its output error's basin is narrow (a pitch
/// attitude hold's gains are high) and from a poor equation-error start the joint fit can run off
/// to commands half a second early. The lateral axes' fit starts from the delays given.
OutputErrorFit timing_fit(Context& c, const RateData& d, RateAxes axes, const std::vector<std::string>& free) {
  OutputErrorOptions o = c.o.output_error;
  AeroCoefficients start = c.coef;
  if (axes == RateAxes::pitch) {
    std::vector<std::string> coefficients = free;
    coefficients.erase(std::remove(coefficients.begin(), coefficients.end(), kDelayNames[1]), coefficients.end());
    OutputErrorOptions profile = o;
    profile.max_relaxations = 1, profile.max_evaluations = kProfileEvaluations;
    double best = std::numeric_limits<double>::infinity();
    for (const double tau : kPitchDelayGrid) {
      profile.command_shift_s[1] = o.command_shift_s[1] + tau;
      const OutputErrorFit f = output_error(d, c.result.aircraft, c.coef, axes, coefficients, profile);
      if (f.rms[0] < best) {
        best = f.rms[0];
        o.command_shift_s[1] = profile.command_shift_s[1];
        start = c.coef;
        for (std::size_t j = 0; j < coefficients.size(); ++j)
          start.*moment_coefficient(coefficients[j]) = f.theta[static_cast<Eigen::Index>(j)];
      }
    }
  }
  o.max_relaxations = std::min(o.max_relaxations, kTimingRelaxations);
  return output_error(d, c.result.aircraft, start, axes, free, o);
}

/// A retried term the output error left undetermined: the prior kept, the note saying what it found.
void note_undetermined(CoefficientEstimate& e, double theta, double se) {
  e.note += fmt::format("; output error {:.3g} +- {:.2g}", theta, se);
}

/// The retried terms (free[from...]) the output error fit f leaves undetermined: back to the prior
/// with a note, out of `free`. Returns whether any went (the rest are then fitted again).
bool drop_undetermined(Context& c, std::vector<std::string>& free, std::size_t from, const OutputErrorFit& f) {
  std::vector<std::string> kept(free.begin(), free.begin() + static_cast<std::ptrdiff_t>(from));
  for (std::size_t j = from; j < free.size(); ++j) {
    const auto J = static_cast<Eigen::Index>(j);
    CoefficientEstimate* e = find_estimate(c.result, free[j]);
    if (retry_determined(c.o.max_relative_error, *e, f.theta[J], f.std_error[J]))
      kept.push_back(free[j]);
    else
      note_undetermined(*e, f.theta[J], f.std_error[J]);
  }
  const bool dropped = kept.size() < free.size();
  free = std::move(kept);
  return dropped;
}

/// A retried term the output error determined: adopted, with a note saying so.
void adopt_retried(Context& c, CoefficientEstimate& e, double theta, double se) {
  c.result.notes.push_back(fmt::format("{}: the band left it {}; the output error's {:.4g} +- {:.2g} adopted", e.name, e.note, theta, se));
  e.identified = true, e.note.clear(), e.estimate = theta, e.std_error = se, e.method = "output error";
  c.coef.*moment_coefficient(e.name) = theta;
}

}  // namespace

bool retried_by_output_error(const CoefficientEstimate& e) {
  return !e.identified && e.method == "band" && e.note.rfind(kPoorlyDetermined, 0) == 0 &&
         std::find(kDominant.begin(), kDominant.end(), e.name) != kDominant.end();
}

bool retry_determined(double max_relative_error, const CoefficientEstimate& e, double theta, double se) {
  const double size = std::min(std::abs(theta), e.prior != 0.0 ? std::abs(e.prior) : std::abs(theta));
  return se <= max_relative_error * size;
}

void refine(Context& c, const RateData& d, RateAxes axes) {
  std::vector<std::string> free, retried;
  for (const auto& e : c.result.coefficients) {
    const bool pitch = e.name.rfind("C_m_", 0) == 0, lateral = e.name.rfind("C_ell_", 0) == 0 || e.name.rfind("C_n_", 0) == 0;
    if (!(axes == RateAxes::pitch ? pitch : lateral)) continue;
    if (e.identified) free.push_back(e.name);
    if (retried_by_output_error(e)) retried.push_back(e.name);
  }
  if (c.o.estimate_delays) {
    std::vector<std::string> timed;
    add_timing(c, axes, timed);
    take_delays(c, timing_fit(c, d, axes, timed));
  }
  if (free.empty()) return;
  const std::size_t identified = free.size();
  free.insert(free.end(), retried.begin(), retried.end());
  OutputErrorFit f = output_error(d, c.result.aircraft, c.coef, axes, free, c.o.output_error);
  if (drop_undetermined(c, free, identified, f)) f = output_error(d, c.result.aircraft, c.coef, axes, free, c.o.output_error);
  const std::vector<std::string> outputs =
      axes == RateAxes::pitch ? std::vector<std::string>{"pitch rate"} : std::vector<std::string>{"roll rate", "yaw rate"};
  std::string rms;
  for (std::size_t a = 0; a < outputs.size(); ++a) {
    const auto A = static_cast<Eigen::Index>(a);
    c.result.fits.push_back({outputs[a], "output error", f.r_squared[A], f.rms[A], f.samples, f.r_squared[A]});
    rms += fmt::format("{}{} {:.4f} -> {:.4f} rad/s", a ? ", " : "", outputs[a], f.rms_start[A], f.rms[A]);
  }
  c.result.notes.push_back(
      fmt::format("output error ({}): {} coefficients, residual rms {}; {} relaxations, {} simulations{}",
                  axes == RateAxes::pitch ? "pitch" : "roll and yaw", free.size(), rms, f.relaxations, f.evaluations,
                  f.budget_spent ? fmt::format(" (its budget of {} spent: not converged)", c.o.output_error.max_simulations) : ""));
  if (const double worst = f.r_squared.minCoeff(); !(worst >= kMinOutputErrorRSquared)) {
    c.result.notes.push_back(
        fmt::format("output error ({}): its simulated rates explain R^2 {:.2f} of the measured, under {:g}: a model "
                    "that does not follow the flight; the equation error's estimates kept",
                    axes == RateAxes::pitch ? "pitch" : "roll and yaw", worst, kMinOutputErrorRSquared));
    return;
  }
  for (std::size_t j = 0; j < free.size(); ++j) {
    const auto J = static_cast<Eigen::Index>(j);
    CoefficientEstimate* e = find_estimate(c.result, free[j]);
    double se = f.std_error[J];
    if (j >= identified) {
      if (retry_determined(c.o.max_relative_error, *e, f.theta[J], se))
        adopt_retried(c, *e, f.theta[J], se);
      else
        note_undetermined(*e, f.theta[J], se);
      continue;
    }
    if (se > c.o.max_relative_error * std::abs(f.theta[J])) {
      c.result.notes.push_back(fmt::format("{}: output error poorly determined ({:.4g} +- {:.2g}); the equation error's {:.4g} kept",
                                           e->name, f.theta[J], se, e->estimate));
      continue;
    }
    // the output error further from the equation error than its own bound: one of them is biased
    // (the equation error by its flow angles' errors; the output error by the turbulence it does not
    // model, process noise, and by the noise in the flow angles it is driven by: Klein and Morelli
    // ch. 6), and which is not known. The estimate is then their mean, its bound the larger of
    // theirs and half the gap (the truth between them lies inside it).
    double theta = f.theta[J];
    std::string method = "output error";
    const double apart = std::abs(f.theta[J] - e->estimate);
    if (apart > se) {
      se = std::max({se, e->std_error, 0.5 * apart});
      theta = 0.5 * (f.theta[J] + e->estimate);
      method = "mean of equation and output error";
    }
    e->estimate = theta, e->std_error = se, e->method = method;
    c.coef.*moment_coefficient(e->name) = theta;
  }
}

void consider_gyro_coupling(Context& c) {
  const AeroCoefficients& m = c.coef;
  const Aircraft& ac = c.result.aircraft;
  const std::array<std::tuple<const char*, double, const char*, double>, 5> pairs = {
      {{"C_ell_beta", m.C_ell_beta, "C_n_beta", m.C_n_beta},
       {"C_ell_p", m.C_ell_p, "C_n_p", m.C_n_p},
       {"C_ell_r", m.C_ell_r, "C_n_r", m.C_n_r},
       {"C_ell_delta_a", m.C_ell_delta_a, "C_n_delta_a", m.C_n_delta_a},
       {"C_ell_delta_r", m.C_ell_delta_r, "C_n_delta_r", m.C_n_delta_r}}};
  const double k = c.o.gyro_cross_axis;
  // the rate regressors' share: each damping or cross derivative takes kappa times its axis's other rate term
  const std::array<std::pair<const char*, double>, 4> regressors = {
      {{"C_ell_r", m.C_ell_p}, {"C_ell_p", m.C_ell_r}, {"C_n_r", m.C_n_p}, {"C_n_p", m.C_n_r}}};
  for (CoefficientEstimate& e : c.result.coefficients) {
    if (!e.identified) continue;
    for (const auto& [roll, C_ell, yaw, C_n] : pairs) {
      if (e.name == yaw) e.std_error = std::hypot(e.std_error, k * (ac.Jz / ac.Jx) * C_ell);
      if (e.name == roll) e.std_error = std::hypot(e.std_error, k * (ac.Jx / ac.Jz) * C_n);
    }
    for (const auto& [name, other] : regressors)
      if (e.name == name) e.std_error = std::hypot(e.std_error, k * other);
  }
}

}  // namespace tern::core::sysid
