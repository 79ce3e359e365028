// path_manager adapter. See adapters.hpp and tern/path/manager.hpp.
#include <algorithm>
#include <cmath>

#include <spdlog/spdlog.h>

#include "adapters.hpp"

namespace tern::path {

void ManagerPlugin::configure() {
  declare(state_, "state", "vehicle state (position, course)");
  declare(waypoints_, "waypoints", "the mission from the path planner, NED");
  declare(phase_, "flight_phase", "flight phase: home's altitude at rest before the takeoff, go-arounds of a land item", Need::optional);
  declare(range_, "range", "downward range finder: the runway's altitude on a land item's final (absent: home's)", Need::optional);
  declare(path_, "current_path", "the segment to follow now (line or orbit)");
  // Defaults: ROSplane's Anaconda parameters (rosplane/params/anaconda_autopilot_params.yaml).
  declare(R_min_, "R_min", 50.0, ParamSpec("m", 1.0, 10000.0, "minimum turn radius: fillets, Dubins paths and orbits"));
  declare(orbit_last_, "orbit_last", false, ParamSpec("", 0, 0, "orbit the last waypoint instead of looping the mission"));
  declare(default_altitude_, "default_altitude", 50.0,
          ParamSpec("m", -1000.0, 20000.0, "altitude above the origin of the origin orbit (no waypoints)"));
  declare(default_airspeed_, "default_airspeed", 15.0,
          ParamSpec("m/s", 1.0, 200.0, "airspeed of waypoints with Va_d = 0 and of the origin orbit"));
  declare(corner_, "corner", "fillet",
          ParamSpec("", 0, 0, "corners of waypoints without use_chi: fillet (Alg. 6) or line (Alg. 5)").one_of({"fillet", "line"}));
  declare(min_separation_, "min_separation", 1.0,
          ParamSpec("m", 0.01, 1000.0, "waypoints closer than this (horizontally) count as repeats"));
  declare(turn_bank_, "turn_bank", 0.0,
          ParamSpec("rad", 0.0, 1.4, "bank angle turns are planned for in the estimated wind (radius >= R_min); 0: every turn R_min"));
  declare(wind_tau_, "wind_tau", 30.0,
          ParamSpec("s", 0.0, 3600.0, "time constant of the low-pass on the state's wind used for turn_bank radii"));
  declare(land_attempts_, "land_attempts", std::int64_t{3},
          ParamSpec("", 1, 20, "approaches to a land item before the landing is abandoned (orbit above the touchdown point)"));
  declare(flare_time_, "flare_time", ManagerConfig{}.flare_time,
          ParamSpec("s", 0.0, 30.0,
                    "a land item's glide path is aimed ground speed x flare_time - flare_height / tan(glide_slope) before its "
                    "touchdown point (the flare's float in the wind, as ArduPlane's LAND_FLARE_SEC); 0: at the touchdown point"));
  land_attempts_.on_change([this](const std::int64_t&) { rebuild(); });
  declare(altitude_band_, "altitude_band", ManagerConfig{}.altitude_band,
          ParamSpec("m", 0.1, 1000.0, "a loiter to an altitude (MAVLink NAV_LOITER_TO_ALT) goes on within this of its altitude"));
  altitude_band_.on_change([this](const double&) { rebuild(); });
  flare_time_.on_change([this](const double&) { rebuild(); });
  turn_bank_.on_change([this](const double&) { rebuild(); });
  R_min_.on_change([this](const double&) { rebuild(); });
  orbit_last_.on_change([this](const bool&) { rebuild(); });
  default_altitude_.on_change([this](const double&) { rebuild(); });
  default_airspeed_.on_change([this](const double&) { rebuild(); });
  corner_.on_change([this](const std::string&) { rebuild(); });
  min_separation_.on_change([this](const double&) { rebuild(); });
  if (context().describing()) return;
  auto logger = context().logger();
  manager_ = std::make_unique<PathManager>(
      config(), [logger](const std::string& s) { logger->warn("{}", s); }, [logger](const std::string& s) { logger->info("{}", s); });
}

ManagerConfig ManagerPlugin::config() const {
  ManagerConfig c;
  c.R_min = R_min_();
  c.orbit_last = orbit_last_();
  c.default_altitude = default_altitude_();
  c.default_airspeed = default_airspeed_();
  c.corner = corner_() == "line" ? ManagerConfig::Corner::line : ManagerConfig::Corner::fillet;
  c.min_separation = min_separation_();
  c.turn_bank = turn_bank_();
  c.land_attempts = static_cast<int>(land_attempts_());
  c.flare_time = flare_time_();
  c.altitude_band = altitude_band_();
  return c;
}

void ManagerPlugin::rebuild() {
  if (manager_) manager_->set_config(config());
}

void ManagerPlugin::start() { f_.revision.reset(); }

void ManagerPlugin::reset() {
  auto logger = context().logger();
  manager_ = std::make_unique<PathManager>(
      config(), [logger](const std::string& s) { logger->warn("{}", s); }, [logger](const std::string& s) { logger->info("{}", s); });
  f_ = Flight{};
}

void ManagerPlugin::step(Nanos now) {
  if (waypoints_.has_value() && (!f_.revision || *f_.revision != waypoints_->revision)) {
    const auto& list = *waypoints_;
    f_.revision = list.revision;
    const std::size_t n = std::min<std::size_t>(list.count, msg::WaypointList::kCapacity);
    if (list.count > msg::WaypointList::kCapacity)
      log().warn("waypoints revision {}: count {} exceeds the capacity {}: the rest is ignored", list.revision, list.count,
                 msg::WaypointList::kCapacity);
    std::vector<MissionPoint> wps(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& w = list.items[i];
      if (w.lla) log().warn("waypoint {} is still lat/lon (the planner converts those): skipped", i);
      wps[i].w = w.lla ? Vec3::Constant(std::nan("")) : w.w;
      wps[i].chi_d = w.chi_d;
      wps[i].use_chi = w.use_chi;
      wps[i].Va_d = w.Va_d;
      wps[i].type = item_type_of(w.type);
      wps[i].Vg_min = w.Vg_min;
      wps[i].loiter = {w.loiter_radius, w.loiter_direction >= 0 ? 1 : -1, w.loiter_time, w.loiter_turns, w.loiter_to_altitude};
      wps[i].land = {w.land_glide_slope, w.land_flare_height, w.land_decision_height};
    }
    manager_->set_waypoints(wps, list.loop, list.immediate, static_cast<int>(std::min<std::uint32_t>(list.loops, 100000)));
  }
  if (!state_.has_value()) return;
  const auto& s = *state_;
  const Vec3 p(s.p_n, s.p_e, s.p_d);
  if (s.valid && std::isfinite(s.w_n) && std::isfinite(s.w_e)) {
    const Vec3 w(s.w_n, s.w_e, 0.0);
    if (!f_.wind_stamp) {
      f_.wind = w;
    } else {
      const double dt = to_seconds(now - *f_.wind_stamp);
      const double tau = wind_tau_();
      const double k = tau > 0.0 ? 1.0 - std::exp(-std::max(dt, 0.0) / tau) : 1.0;
      f_.wind += k * (w - f_.wind);
    }
    f_.wind_stamp = now;
    manager_->set_wind(f_.wind);
  }
  follow_phase(s, now);
  follow_runway(s, now);
  const PathSegment seg = manager_->update(p, s.chi, to_seconds(now));
  if (seg.type == PathSegment::Type::line && !manager_->passed().empty() && p.allFinite()) {
    const double e = std::fabs(cross_track_error(seg.r, seg.q, p));
    f_.xt_sq += e * e;
    f_.xt_max = std::max(f_.xt_max, e);
    ++f_.xt_n;
  }
  msg::CurrentPath out;
  out.stamp = now;
  out.path_type = seg.type == PathSegment::Type::line ? msg::CurrentPath::line : msg::CurrentPath::orbit;
  out.Va_d = seg.Va_d;
  out.r = seg.r;
  out.q = seg.q;
  out.c = seg.c;
  out.rho = seg.rho;
  out.lambda = static_cast<std::int8_t>(seg.lambda >= 0 ? 1 : -1);
  out.waypoint_index = seg.waypoint_index;
  out.landing = seg.landing;
  out.flare_height = seg.flare_height;
  out.decision_height = seg.decision_height;
  out.attempt = static_cast<std::uint8_t>(std::clamp(seg.attempt, 0, 255));
  path_.publish(out);
}

namespace {
// y <- x low-passed over 2 s (first order; the first sample taken as it is), stamped at now.
void low_pass(std::optional<double>& y, Nanos& stamp, double x, Nanos now) {
  const double dt = y ? std::max(to_seconds(now - stamp), 0.0) : 0.0;
  y = y ? *y + (1.0 - std::exp(-dt / 2.0)) * (x - *y) : x;
  stamp = now;
}
}  // namespace

// Home's ground: the estimate's altitude while the aircraft rests before the takeoff (preflight,
// or takeoff not yet rolling), low-passed over 2 s; land items' touchdown altitudes count from it.
void ManagerPlugin::follow_phase(const msg::State& s, Nanos now) {
  if (!phase_.has_value()) return;
  const msg::FlightPhase& ph = *phase_;
  const bool at_rest = ph.phase == msg::Phase::preflight || (ph.phase == msg::Phase::takeoff && std::isfinite(s.Vg) && s.Vg < 1.0);
  if (at_rest && s.valid && std::isfinite(s.p_d) && ph.phase != msg::Phase::climb && manager_->approaches() == 0) {
    low_pass(f_.home_h, f_.home_stamp, -s.p_d, now);
    manager_->set_home_altitude(*f_.home_h);
  }
  // A go-around: the phase left the approach (or flare) for anything but the landing's next
  // phases. Seen from the last phase this plugin saw: the phase machine may pass through climb
  // to cruise within one of this plugin's periods.
  const bool go_around = msg::on_final(f_.last_phase) && !msg::landing_phase(ph.phase);
  f_.last_phase = ph.phase;
  if (go_around) manager_->go_around(Vec3(s.p_n, s.p_e, s.p_d));
}

// The runway under the final approach as the range finder measures it (a measurement at most
// Range::kFresh old, in the approach or the flare): the estimate's p_d plus the height, low-passed
// over 2 s; the glide path's touchdown point takes it (PathManager::set_runway_down).
void ManagerPlugin::follow_runway(const msg::State& s, Nanos now) {
  if (!phase_.has_value() || !range_.has_value() || !s.valid) return;
  const msg::Phase ph = phase_->phase;
  if (!msg::on_final(ph)) return;
  const double d = s.p_d + range_->height_at(now, s.phi, s.theta);
  if (!std::isfinite(d)) return;
  low_pass(f_.runway_d, f_.runway_stamp, d, now);
  manager_->set_runway_down(*f_.runway_d);
}

std::vector<std::pair<std::string, double>> ManagerPlugin::summary() const {
  if (!manager_) return {};
  const double rms = f_.xt_n > 0 ? std::sqrt(f_.xt_sq / static_cast<double>(f_.xt_n)) : 0.0;
  std::vector<std::pair<std::string, double>> out{{"waypoints_passed", static_cast<double>(manager_->passed().size())},
                                                  {"line_cross_track_rms_m", rms},
                                                  {"line_cross_track_max_m", f_.xt_max},
                                                  {"land_approaches", static_cast<double>(manager_->approaches())},
                                                  {"land_abandoned", manager_->landing_abandoned() ? 1.0 : 0.0},
                                                  {"home_altitude_m", f_.home_h.value_or(0.0)}};
  if (f_.runway_d) out.emplace_back("runway_altitude_m", -*f_.runway_d);  // the range finder's runway, m above the origin
  if (manager_->approach()) out.emplace_back("land_aim_offset_m", manager_->approach()->aim_offset);  // the last final's
  return out;
}

}  // namespace tern::path
