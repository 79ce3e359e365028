// core/apps/sysid/command_delay.cpp: the commands' delays from the flight (command_delay.hpp).
#include "sysid/command_delay.hpp"

#include <cmath>

#include <fmt/format.h>

namespace tern::core::sysid {

namespace {

constexpr std::array<const char*, 3> kSurfaces = {"aileron", "elevator", "rudder"};
constexpr std::array<const char*, 3> kRates = {"the roll and yaw rates", "the pitch rate", "the roll and yaw rates"};

/// Whether the timing pass's estimate for one surface is adopted; `why` says why not.
bool adopted(const NuisanceEstimate& shift, double start, const DelayOptions& d, std::string& why) {
  if (!shift.identified) {
    why = "its axis had no output-error fit";
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

}  // namespace

SysidResult identify_timed(const SeriesLoader& load, const std::array<double, 3>& start_s, const Aircraft& prior, const SysidOptions& o,
                           const DelayOptions& d) {
  const FlightSeries first = load(start_s);
  const bool any = d.estimate[0] || d.estimate[1] || d.estimate[2];
  if (!any || !o.output_error.enabled) {
    SysidResult r = identify(first, prior, o);
    r.command_delay_s = start_s;
    if (any) r.notes.push_back("command delays: not estimated (the output error is off); the prior's servos.delay_* taken");
    return r;
  }
  SysidOptions timing = o;
  timing.estimate_delays = true;
  SysidResult pass = identify(first, prior, timing);
  std::array<NuisanceEstimate, 3> shift = pass.delay_shift;  // identified: adopted (below)
  std::array<double, 3> delays = start_s;
  std::array<bool, 3> taken = {false, false, false};
  bool moved = false;
  std::vector<std::string> lines;
  for (std::size_t i = 0; i < 3; ++i) {
    std::string why;
    taken[i] = d.estimate[i] && adopted(shift[i], start_s[i], d, why);
    if (taken[i]) delays[i] = start_s[i] + shift[i].estimate, moved = moved || std::abs(shift[i].estimate) > d.min_shift_s;
    const bool fitted = shift[i].identified;
    if (!d.estimate[i])
      lines.push_back(fmt::format("command delay ({}): {:g} ms, given", kSurfaces[i], 1e3 * start_s[i]));
    else if (!taken[i])
      lines.push_back(fmt::format(
          "command delay ({}): not estimated ({}); {:g} ms taken (the prior's servos.delay_{})", kSurfaces[i],
          fitted ? fmt::format("{:.1f} +- {:.1f} ms, {}", 1e3 * (start_s[i] + shift[i].estimate), 1e3 * shift[i].std_error, why) : why,
          1e3 * start_s[i], "aer"[i]));
    // sysid.json's command_delay_estimate: identified means adopted; a fit it refused says why
    if (!taken[i]) shift[i].identified = false, shift[i].note = d.estimate[i] ? why : "given";
  }
  for (std::size_t i = 0; i < 3; ++i)
    if (taken[i])
      lines.push_back(fmt::format(
          "command delay ({}): {:.1f} +- {:.1f} ms after its stamp, from the output error of {}{}", kSurfaces[i], 1e3 * delays[i],
          1e3 * shift[i].std_error, kRates[i],
          moved ? ""
                : fmt::format(" (within {:g} ms of the {:g} ms it started from, which stays)", 1e3 * d.min_shift_s, 1e3 * start_s[i])));
  SysidResult r = moved ? identify(load(delays), prior, o) : std::move(pass);
  r.command_delay_s = moved ? delays : start_s;
  r.delay_shift = shift;
  r.notes.insert(r.notes.begin(), lines.begin(), lines.end());
  return r;
}

}  // namespace tern::core::sysid
