#include "safety/preflight.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "tern/math.hpp"

namespace tern::core {
namespace {

/// "imu, baro": the sensors set in a State.degraded_sensors bit field.
std::string sensor_names(std::uint8_t bits) {
  namespace b = msg::sensor_bit;
  const std::pair<std::uint8_t, const char*> names[] = {
      {b::imu, "imu"}, {b::gnss, "gnss"}, {b::baro, "baro"}, {b::diff_pressure, "pitot"}, {b::mag, "mag"}};
  std::string out;
  for (const auto& [bit, name] : names)
    if ((bits & bit) != 0) out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

void check_covariance(const msg::State& s, const PreflightLimits& l, std::vector<std::string>& out) {
  const auto& P = s.P_diag;
  if (std::all_of(P.begin(), P.end(), [](double v) { return v == 0.0; })) return;  // no covariance given
  constexpr std::size_t att = msg::State::P_attitude, pos_n = msg::State::P_position, bg = msg::State::P_gyro_bias;
  const double tilt = std::sqrt(std::max(P[att], P[att + 1])), yaw = std::sqrt(P[att + 2]);
  const double bias = std::sqrt(std::max({P[bg], P[bg + 1], P[bg + 2]}));
  const double pos = std::sqrt(std::max(P[pos_n], P[pos_n + 1]));
  if (!(tilt <= l.max_tilt_sigma))
    out.push_back(
        fmt::format("estimator not aligned: tilt sigma {:.2f} deg > {:.2f} deg", tilt * kDegPerRad, l.max_tilt_sigma * kDegPerRad));
  if (!(yaw <= l.max_yaw_sigma))
    out.push_back(fmt::format("estimator not aligned: yaw sigma {:.1f} deg > {:.1f} deg", yaw * kDegPerRad, l.max_yaw_sigma * kDegPerRad));
  if (!(bias <= l.max_gyro_bias_sigma))
    out.push_back(fmt::format("estimator gyro bias not converged: sigma {:.2f} deg/s > {:.2f} deg/s", bias * kDegPerRad,
                              l.max_gyro_bias_sigma * kDegPerRad));
  if (!(pos <= l.max_position_sigma)) out.push_back(fmt::format("estimator position sigma {:.1f} m > {:.1f} m", pos, l.max_position_sigma));
}

void check_estimator(const msg::State& s, const PreflightLimits& l, std::vector<std::string>& out) {
  if (!s.valid || s.status != msg::StateStatus::ok) {
    const std::string sensors = sensor_names(s.degraded_sensors);
    out.push_back(fmt::format("estimator not ready (status {}{})", s.valid ? "degraded" : "invalid",
                              sensors.empty() ? "" : ": no usable " + sensors + " (silent, non-finite or rejected)"));
    return;
  }
  check_covariance(s, l, out);
}

void check_innovations(const msg::Innovations& i, std::vector<std::string>& out) {
  const std::pair<const char*, double> ratios[] = {
      {"gnss position", i.gnss_pos}, {"gnss velocity", i.gnss_vel},   {"baro", i.baro}, {"pitot", i.diff_pressure}, {"mag", i.mag},
      {"sideslip", i.sideslip},      {"normal force", i.normal_force}};
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

std::optional<std::string> fcu_not_ready(const msg::FcuStatus& fcu) {
  if (!fcu.armed) return fmt::format("FCU disarmed (error code 0x{:02x}; the FCU link says what is missing)", fcu.error_code);
  if (fcu.error_code != 0) return fmt::format("FCU error code 0x{:02x} (the FCU link says which)", fcu.error_code);
  return std::nullopt;
}

std::vector<std::string> preflight_failures(const PreflightInputs& in, const PreflightLimits& limits) {
  std::vector<std::string> out;
  if (in.fcu != nullptr)
    if (auto f = fcu_not_ready(*in.fcu)) out.push_back(*f);
  if (limits.require_rc && !(in.rc_age && *in.rc_age <= limits.max_rc_age))
    out.push_back(
        in.rc_age ? fmt::format("RC silent for {:.1f} s > {:.1f} s (the config requires the transmitter)", *in.rc_age, limits.max_rc_age)
                  : "no RC frame yet (the config requires the transmitter: preflight_require_rc)");
  if (in.state == nullptr) {
    out.emplace_back("no state yet (estimator silent)");
  } else {
    const msg::State& s = *in.state;
    check_estimator(s, limits, out);
    const double speed = std::sqrt(s.v_n * s.v_n + s.v_e * s.v_e + s.v_d * s.v_d);
    if (!(speed <= limits.max_ground_speed))
      out.push_back(fmt::format("aircraft moving: ground speed {:.2f} m/s > {:.2f} m/s", speed, limits.max_ground_speed));
    // the wind an estimator sees at rest (one with a covariance: a truth or test source's state
    // says nothing about the air at the aircraft)
    const bool estimated = std::any_of(s.P_diag.begin(), s.P_diag.end(), [](double v) { return v != 0.0; });
    const double wind = std::max(std::isfinite(s.Va) ? s.Va : 0.0, std::hypot(s.w_n, s.w_e));
    if (!(wind <= limits.max_wind) && s.valid && estimated)
      out.push_back(
          fmt::format("wind at rest {:.1f} m/s > {:.1f} m/s (airspeed {:.1f} m/s, estimated wind {:.1f} m/s): beyond the "
                      "takeoff limit preflight_max_wind",
                      wind, limits.max_wind, s.Va, std::hypot(s.w_n, s.w_e)));
  }
  if (in.innovations != nullptr) check_innovations(*in.innovations, out);
  if (in.gnss != nullptr) check_gnss(*in.gnss, limits, out);
  return out;
}

}  // namespace tern::core
