// core/apps/sysid/airborne.cpp: where a flight series is in the air (airborne.hpp).
#include "sysid/airborne.hpp"

#include <algorithm>
#include <limits>
#include <cmath>

#include <fmt/format.h>

namespace tern::core::sysid {

namespace {

double ground_speed(const FlightSeries& s, std::size_t k) { return std::sqrt(s.u[k] * s.u[k] + s.v[k] * s.v[k] + s.w[k] * s.w[k]); }

AirborneMask declared(const FlightSeries& s, const DeclaredAirborne& w) {
  AirborneMask m{std::vector<unsigned char>(s.size(), 0),
                 fmt::format("the log's airborne: [{:g}, {:g}] s ({})", w.start_s, w.end_s, w.source)};
  for (std::size_t k = 0; k < s.size(); ++k) m.up[k] = s.valid[k] && s.t[k] >= w.start_s && s.t[k] <= w.end_s ? 1 : 0;
  return m;
}

/// m: how far below its lowest sample put_ground_at_zero puts the ground of a log that never stood still
constexpr double kClearBelow = 1000.0;

}  // namespace

double seconds_where(const FlightSeries& s, const std::vector<unsigned char>& flag) {
  double total = 0.0;
  for (std::size_t k = 0; k + 1 < s.size(); ++k)
    if (flag[k]) total += s.t[k + 1] - s.t[k];
  return total;
}

std::optional<double> ground_height(const FlightSeries& s, const AirborneRule& rule) {
  std::vector<unsigned char> still(s.size(), 0);
  std::vector<double> heights;
  for (std::size_t k = 0; k < s.size(); ++k)
    if (s.valid[k] && std::isfinite(s.p_d[k]) && ground_speed(s, k) < rule.still_speed) still[k] = 1, heights.push_back(-s.p_d[k]);
  if (heights.empty() || seconds_where(s, still) < rule.min_still_s) return std::nullopt;
  std::nth_element(heights.begin(), heights.begin() + static_cast<std::ptrdiff_t>(heights.size() / 2), heights.end());
  return heights[heights.size() / 2];
}

void put_ground_at_zero(FlightSeries& s, const AirborneRule& rule) {
  double ground = 0.0;
  if (const auto h = ground_height(s, rule)) {
    ground = *h;
  } else {  // never on the ground in the log: the ground far below its lowest sample
    double lowest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < s.size(); ++k)
      if (s.valid[k] && std::isfinite(s.p_d[k])) lowest = std::min(lowest, -s.p_d[k]);
    ground = std::isfinite(lowest) ? lowest - kClearBelow : 0.0;
  }
  for (double& d : s.p_d) d += ground;
}

AirborneMask airborne_mask(const FlightSeries& s, const AirborneRule& rule) {
  if (s.declared_airborne) return declared(s, *s.declared_airborne);
  AirborneMask m{std::vector<unsigned char>(s.size(), 0), ""};
  const std::optional<double> ground_found = ground_height(s, rule);
  if (!ground_found) {
    for (std::size_t k = 0; k < s.size(); ++k) m.up[k] = s.valid[k];
    m.rule = fmt::format(
        "estimate valid (the aircraft never stood still: ground speed never below {:g} m/s for {:g} s, so no ground "
        "in the log)",
        rule.still_speed, rule.min_still_s);
    return m;
  }
  const double ground = *ground_found;
  for (std::size_t k = 0; k < s.size(); ++k) m.up[k] = s.valid[k] && -s.p_d[k] > ground + rule.min_height ? 1 : 0;
  m.rule = fmt::format(
      "estimate valid, more than {:g} m above the ground where the aircraft stood still ({:.1f} m from the estimator's "
      "origin; ground speed below {:g} m/s)",
      rule.min_height, std::abs(ground) < 0.05 ? 0.0 : ground, rule.still_speed);  // never "-0.0 m"
  return m;
}

}  // namespace tern::core::sysid
