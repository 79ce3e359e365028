// When a takeoff is aborted. See takeoff_checks.hpp.
#include "safety/takeoff_checks.hpp"

#include <cmath>

#include <fmt/format.h>

#include "tern/math.hpp"

namespace tern::core {

std::string takeoff_abort(const msg::State& s, double run, double height, const TakeoffLimits& l) {
  if (run >= l.run_length && s.Va < l.min_airspeed && height < l.safe_height)
    return fmt::format("airspeed {:.1f} m/s < {:.1f} m/s after {:.0f} m of runway", s.Va, l.min_airspeed, run);
  if (height >= l.safe_height) return "";
  if (std::fabs(s.phi) > l.max_roll)
    return fmt::format("roll {:.0f} deg beyond {:.0f} deg at {:.1f} m", s.phi * kDegPerRad, l.max_roll * kDegPerRad, height);
  if (s.theta > l.max_pitch)
    return fmt::format("pitch {:.0f} deg above {:.0f} deg at {:.1f} m", s.theta * kDegPerRad, l.max_pitch * kDegPerRad, height);
  if (s.theta < l.min_pitch)
    return fmt::format("pitch {:.0f} deg below {:.0f} deg at {:.1f} m", s.theta * kDegPerRad, l.min_pitch * kDegPerRad, height);
  return "";
}

}  // namespace tern::core
