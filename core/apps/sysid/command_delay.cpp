// core/apps/sysid/command_delay.cpp: the commands' delays from the flight (command_delay.hpp).
#include "sysid/command_delay.hpp"

#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "sysid/prior_update.hpp"
#include "sysid/verdicts.hpp"

namespace tern::core::sysid {

namespace {

constexpr std::array<const char*, 3> kRates = {"the roll and yaw rates", "the pitch rate", "the roll and yaw rates"};

/// Whether the timing pass's estimate for one surface is adopted; `why` says why not.
bool adopted(const NuisanceEstimate& shift, double start, const DelayOptions& d, std::string& why) {
  if (!shift.identified) {
    why = shift.note.empty() ? "its axis had no output-error fit" : shift.note;
    return false;
  }
  if (!(shift.std_error <= d.max_std_error_s)) {
    why = fmt::format("its standard error {:.1f} ms exceeds {:g} ms", 1e3 * shift.std_error, 1e3 * d.max_std_error_s);
    return false;
  }
  if (!(std::abs(start + shift.estimate) <= d.max_delay_s)) {
    why = fmt::format("{:.0f} ms is beyond {:g} ms of a stamp", 1e3 * (start + shift.estimate), 1e3 * d.max_delay_s);
    return false;
  }
  return true;
}

/// The delay the adopted surfaces share: their delays' mean weighted by 1 / SE^2, and its standard
/// error; nullopt when none was adopted. One output loop (a mixer cycle, a servo bus) drives every
/// surface, so a surface whose own delay the flight leaves undetermined takes the others' timing.
std::optional<NuisanceEstimate> shared_delay(const std::array<double, 3>& delays, const std::array<NuisanceEstimate, 3>& shift,
                                             const std::array<bool, 3>& taken) {
  double weights = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < 3; ++i)
    if (taken[i]) {
      const double w = 1.0 / std::max(shift[i].std_error * shift[i].std_error, 1e-12);
      weights += w, sum += w * delays[i];
    }
  if (weights == 0.0) return std::nullopt;
  NuisanceEstimate e;
  e.estimate = sum / weights, e.std_error = std::sqrt(1.0 / weights), e.identified = true;
  return e;
}

/// Whether a surface left undetermined takes the shared delay: its own fit, where it has one,
/// within `sigmas` of its standard error (and the shared one's) of it; `why` says why not.
bool takes_shared(const NuisanceEstimate& own, double own_delay, const NuisanceEstimate& shared, double sigmas, std::string& why) {
  if (!own.identified) return true;
  const double spread = std::hypot(own.std_error, shared.std_error);
  if (std::abs(own_delay - shared.estimate) <= sigmas * spread) return true;
  why = fmt::format("{:.1f} ms, its own fit, is {:.1f} standard errors from the other surfaces' {:.1f} ms", 1e3 * own_delay,
                    std::abs(own_delay - shared.estimate) / spread, 1e3 * shared.estimate);
  return false;
}

/// The prior with the held terms moved (prior_update.hpp) after `pass`'s verdicts; the given one
/// when o.scale_held_priors is off.
ScaledPrior held_moved(const SysidResult& pass, const Aircraft& prior, const SysidOptions& o) {
  if (!o.scale_held_priors) return {prior, {}};
  SysidResult judged = pass;
  apply_verdicts(judged, prior, o);
  return scaled_prior(judged, prior);
}

}  // namespace

DelayChoice choose_delays(const std::array<double, 3>& start_s, std::array<NuisanceEstimate, 3> shift, const DelayOptions& d) {
  DelayChoice c{start_s, {}, {}, false};
  std::array<bool, 3> taken = {false, false, false};
  std::array<std::string, 3> why;
  for (std::size_t i = 0; i < 3; ++i) {
    taken[i] = d.estimate[i] && adopted(shift[i], start_s[i], d, why[i]);
    if (taken[i]) c.delays[i] = start_s[i] + shift[i].estimate, c.moved = c.moved || shift[i].estimate != 0.0;
  }
  const std::optional<NuisanceEstimate> shared = shared_delay(c.delays, shift, taken);
  for (std::size_t i = 0; i < 3; ++i) {
    if (taken[i]) continue;
    if (!d.estimate[i]) {
      c.lines.push_back(fmt::format("command delay ({}): {:g} ms, given", kSurfaceNames[i], 1e3 * start_s[i]));
      shift[i].identified = false, shift[i].note = "given";
      continue;
    }
    const double own_delay = start_s[i] + shift[i].estimate;
    const std::string own =
        shift[i].identified ? fmt::format("{:.1f} +- {:.1f} ms, {}", 1e3 * own_delay, 1e3 * shift[i].std_error, why[i]) : why[i];
    std::string refused;
    if (shared && takes_shared(shift[i], own_delay, *shared, d.shared_sigmas, refused)) {
      c.delays[i] = shared->estimate, c.moved = c.moved || c.delays[i] != start_s[i];
      c.lines.push_back(
          fmt::format("command delay ({}): not estimated alone ({}); {:.1f} +- {:.1f} ms taken, the other surfaces' "
                      "(one output loop drives every servo)",
                      kSurfaceNames[i], own, 1e3 * shared->estimate, 1e3 * shared->std_error));
      shift[i].identified = false, shift[i].note = why[i] + "; the other surfaces' delay taken";
      continue;
    }
    c.lines.push_back(fmt::format("command delay ({}): not estimated ({}{}); {:g} ms taken (the prior's servos.delay_{})", kSurfaceNames[i],
                                  own, refused.empty() ? "" : "; " + refused, 1e3 * start_s[i], "aer"[i]));
    // sysid.json's command_delay_estimate: identified means adopted; a fit it refused says why
    shift[i].identified = false, shift[i].note = why[i];
  }
  for (std::size_t i = 0; i < 3; ++i)
    if (taken[i])
      c.lines.push_back(fmt::format("command delay ({}): {:.1f} +- {:.1f} ms after its stamp, from the output error of {}",
                                    kSurfaceNames[i], 1e3 * c.delays[i], 1e3 * shift[i].std_error, kRates[i]));
  if (!c.moved) c.delays = start_s;
  c.shift = shift;
  return c;
}

SysidResult identify_timed(const SeriesLoader& load, const std::array<double, 3>& start_s, const Aircraft& prior, const SysidOptions& o,
                           const DelayOptions& d) {
  const FlightSeries first = load(start_s);
  const bool any = d.estimate[0] || d.estimate[1] || d.estimate[2];
  if (!any || !o.output_error.enabled) {
    SysidResult r = identify(first, prior, o);
    if (const ScaledPrior s = held_moved(r, prior, o); !s.scaled.empty()) {
      r = identify(first, s.prior, o);
      r.held_scaled = s.scaled;
    }
    r.command_delay_s = start_s;
    if (any) r.notes.push_back("command delays: not estimated (the output error is off); the prior's servos.delay_* taken");
    return r;
  }
  SysidOptions timing = o;
  timing.estimate_delays = true;
  SysidResult pass = identify(first, prior, timing);
  const DelayChoice c = choose_delays(start_s, pass.delay_shift, d);
  const ScaledPrior s = held_moved(pass, prior, o);
  SysidResult r = c.moved || !s.scaled.empty() ? identify(c.moved ? load(c.delays) : first, s.prior, o) : std::move(pass);
  r.held_scaled = s.scaled;
  r.command_delay_s = c.delays;
  r.delay_shift = c.shift;
  r.notes.insert(r.notes.begin(), c.lines.begin(), c.lines.end());
  return r;
}

}  // namespace tern::core::sysid
