// core/apps/sysid/pitot_scale_share.cpp: the pitot scale's share of the bounds (pitot_scale_share.hpp).
#include "sysid/pitot_scale_share.hpp"

#include <cmath>
#include <string>

namespace tern::core::sysid {

namespace {

/// How a coefficient scales with k: as k^-1 for a rate derivative (its regressor carries 1 / Va),
/// as k^-2 for the rest (flow angles, surfaces, trim terms); 0 for the drag's, whose bound has it.
int scale_power(const std::string& name) {
  if (name.rfind("C_D", 0) == 0 || name.rfind("C_", 0) != 0) return 0;
  const std::string last = name.substr(name.find_last_of('_') + 1);
  return last == "p" || last == "q" || last == "r" ? 1 : 2;
}

}  // namespace

void consider_pitot_scale(std::vector<CoefficientEstimate>& coefficients, double relative) {
  if (!(relative > 0.0)) return;
  for (CoefficientEstimate& e : coefficients)
    if (e.identified) e.std_error = std::hypot(e.std_error, scale_power(e.name) * relative * e.estimate);
}

}  // namespace tern::core::sysid
