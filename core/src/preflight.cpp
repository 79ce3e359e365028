#include "preflight.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace tern::core {
namespace {
constexpr double kDeg = 180.0 / 3.14159265358979323846;

void check_estimator(const msg::State& s, const PreflightLimits& l, std::vector<std::string>& out) {
  if (!s.valid || s.status != msg::StateStatus::ok) {
    out.push_back(fmt::format("estimator not ready (status {}{})", s.valid ? "degraded" : "invalid",
                              s.degraded_sensors != 0 ? fmt::format(", sensor bits 0x{:02x}", s.degraded_sensors) : ""));
    return;
  }
  const auto& P = s.P_diag;
  if (std::all_of(P.begin(), P.end(), [](double v) { return v == 0.0; })) return;  // no covariance given
  constexpr std::size_t att = msg::State::P_attitude, pos_n = msg::State::P_position;
  const double tilt = std::sqrt(std::max(P[att], P[att + 1])), yaw = std::sqrt(P[att + 2]);
  const double pos = std::sqrt(std::max(P[pos_n], P[pos_n + 1]));
  if (!(tilt <= l.max_tilt_sigma))
    out.push_back(fmt::format("estimator not aligned: tilt sigma {:.2f} deg > {:.2f} deg", tilt * kDeg, l.max_tilt_sigma * kDeg));
  if (!(yaw <= l.max_yaw_sigma))
    out.push_back(fmt::format("estimator not aligned: yaw sigma {:.1f} deg > {:.1f} deg", yaw * kDeg, l.max_yaw_sigma * kDeg));
  if (!(pos <= l.max_position_sigma))
    out.push_back(fmt::format("estimator position sigma {:.1f} m > {:.1f} m", pos, l.max_position_sigma));
}

void check_innovations(const msg::Innovations& i, std::vector<std::string>& out) {
  const std::pair<const char*, double> ratios[] = {{"gnss position", i.gnss_pos}, {"gnss velocity", i.gnss_vel},
                                                   {"baro", i.baro},               {"pitot", i.diff_pressure},
                                                   {"mag", i.mag},                 {"sideslip", i.sideslip}};
  for (const auto& [name, r] : ratios)
    if (!(r < 1.0) && r != msg::Innovations::none)
      out.push_back(fmt::format("{} innovation test ratio {:.2f} >= 1 (the estimator disagrees with the sensor)", name, r));
}

void check_gnss(const msg::Gnss& g, const PreflightLimits& l, std::vector<std::string>& out) {
  if (g.fix_type != msg::FixType::fix_3d) {
    out.push_back(fmt::format("GNSS fix type {} (3-D fix required)", static_cast<int>(g.fix_type)));
    return;
  }
  if (!(g.h_acc <= l.max_h_acc)) out.push_back(fmt::format("GNSS h_acc {:.1f} m > {:.1f} m", g.h_acc, l.max_h_acc));
  if (!(g.v_acc <= l.max_v_acc)) out.push_back(fmt::format("GNSS v_acc {:.1f} m > {:.1f} m", g.v_acc, l.max_v_acc));
  if (g.num_sats < l.min_sats) out.push_back(fmt::format("GNSS {} satellites < {}", g.num_sats, l.min_sats));
}
}  // namespace

std::vector<std::string> preflight_failures(const msg::State* state, const msg::Innovations* innovations,
                                            const msg::Gnss* gnss, const PreflightLimits& limits) {
  std::vector<std::string> out;
  if (state == nullptr) {
    out.emplace_back("no state yet (estimator silent)");
  } else {
    check_estimator(*state, limits, out);
    const double speed = std::sqrt(state->v_n * state->v_n + state->v_e * state->v_e + state->v_d * state->v_d);
    if (!(speed <= limits.max_ground_speed))
      out.push_back(fmt::format("aircraft moving: ground speed {:.2f} m/s > {:.2f} m/s", speed, limits.max_ground_speed));
  }
  if (innovations != nullptr) check_innovations(*innovations, out);
  if (gnss != nullptr) check_gnss(*gnss, limits, out);
  return out;
}

}  // namespace tern::core
