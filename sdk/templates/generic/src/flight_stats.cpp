#include "flight_stats.hpp"

#include <algorithm>
#include <cmath>

namespace tern_@NAME@ {

bool FlightStats::add(double t, double phi, double Va, double Va_warn) {
  if (!std::isfinite(t) || !std::isfinite(phi) || !std::isfinite(Va)) return false;
  if (samples_ > 0 && below_ && t > last_t_) time_below_ += t - last_t_;
  max_abs_phi_ = std::max(max_abs_phi_, std::fabs(phi));
  min_Va_ = samples_ ? std::min(min_Va_, Va) : Va;
  sum_Va_ += Va;
  ++samples_;
  last_t_ = t;
  const bool was_below = below_;
  below_ = Va < Va_warn;
  if (below_ && !was_below) ++episodes_;
  return below_ && !was_below;
}

}  // namespace tern_@NAME@
