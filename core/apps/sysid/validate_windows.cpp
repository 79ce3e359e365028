// core/apps/sysid/validate_windows.cpp: where a flight series is airborne, cut into the windows
// `tern validate` re-initialises the simulation at (validate.hpp).
#include <cmath>

#include <fmt/format.h>

#include "config/error.hpp"
#include "sysid/airborne.hpp"
#include "sysid/validate.hpp"

namespace tern::core::sysid {

namespace {

/// Every estimated channel the model's state, wind and the scored channels read, finite at k.
bool estimate_finite(const FlightSeries& s, std::size_t k) {
  for (const auto* c : {&s.Va, &s.alpha, &s.beta, &s.phi, &s.theta, &s.psi, &s.p_n, &s.p_e,     &s.p_d,     &s.u,       &s.v,
                        &s.w,  &s.w_n,   &s.w_e,  &s.w_d, &s.p,     &s.q,   &s.r,   &s.delta_a, &s.delta_e, &s.delta_r, &s.delta_t})
    if (!std::isfinite((*c)[k])) return false;
  return true;
}

}  // namespace

std::vector<unsigned char> airborne(const FlightSeries& s, const ValidateOptions& o) {
  std::vector<unsigned char> up = airborne_mask(s, o.ground).up;
  for (std::size_t k = 0; k < s.size(); ++k) up[k] = up[k] && estimate_finite(s, k) && s.Va[k] > o.min_Va ? 1 : 0;
  return up;
}

std::vector<Window> airborne_windows(const FlightSeries& s, const ValidateOptions& o, const std::string& log) {
  bool ever_valid = false;
  for (unsigned char v : s.valid) ever_valid = ever_valid || v;
  if (!ever_valid)
    throw ConfigError(fmt::format("{}: the estimate never became valid (state.csv's valid is 0 throughout): nothing to score", log));
  const std::vector<unsigned char> up = airborne(s, o);
  std::vector<Window> windows;
  std::size_t k = 0;
  while (k < s.size()) {
    if (!up[k]) {
      ++k;
      continue;
    }
    std::size_t end = k + 1;  // the window [k, end) grows while airborne and shorter than window_s
    while (end < s.size() && up[end] && s.t[end] - s.t[k] < o.window_s) ++end;
    if (end < s.size() && up[end]) {  // closed by an airborne sample window_s after its first
      windows.push_back({k, end});
      k = end;
    } else {
      k = end + 1;  // too short: the stretch ended (or the series did) before a whole window
    }
  }
  if (windows.empty())
    throw ConfigError(
        fmt::format("{}: no {:g}-s window airborne ({}; Va > {:g} m/s): {:.1f} s airborne in all, in stretches shorter than a window", log,
                    o.window_s, airborne_mask(s, o.ground).rule, o.min_Va, seconds_where(s, up)));
  return windows;
}

}  // namespace tern::core::sysid
