// core/apps/sysid/pitot_scale_share.cpp: the pitot scale's share of the bounds (pitot_scale_share.hpp).
#include "sysid/pitot_scale_share.hpp"

#include <cmath>
#include <string>

namespace tern::core::sysid {

namespace {

/// How a coefficient scales with k: as k^-1 for a rate derivative (C_*_p, C_*_q, C_*_r: its
/// regressor carries 1 / Va), as k^-2 for the rest (flow angles, surfaces such as C_n_delta_r, trim
/// terms); 0 for the drag's, whose bound has it.
int scale_power(const std::string& name) {
  if (name.rfind("C_D", 0) == 0 || name.rfind("C_", 0) != 0) return 0;
  const std::size_t cut = name.find_last_of('_');
  const std::string last = name.substr(cut + 1), before = name.substr(0, cut);
  const bool surface = before.size() >= 6 && before.compare(before.size() - 6, 6, "_delta") == 0;
  return !surface && (last == "p" || last == "q" || last == "r") ? 1 : 2;
}

}  // namespace

void consider_pitot_scale(std::vector<CoefficientEstimate>& coefficients, double relative) {
  if (!(relative > 0.0)) return;
  for (CoefficientEstimate& e : coefficients)
    if (e.identified) e.std_error = std::hypot(e.std_error, scale_power(e.name) * relative * e.estimate);
}

}  // namespace tern::core::sysid
