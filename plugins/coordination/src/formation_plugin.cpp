// coord_formation adapter; see formation_plugin.hpp.
#include "formation_plugin.hpp"

#include <cmath>
#include <stdexcept>

#include <spdlog/spdlog.h>

namespace tern::coord {

void FormationPlugin::configure() {
  declare_fleet();
  const FormationConfig d;
  declare(leader_, "leader", "", ParamSpec("", 0, 0, "the leader's vehicle name (empty: the first vehicle)").start_only());
  declare(center_, "center", std::vector<double>{0.0, 0.0, -100.0},
          ParamSpec("m", -100000.0, 100000.0, "orbit centre [n, e, d] in the common frame (origin); d sets the leader's altitude")
              .of_size(3)
              .start_only());
  declare(radius_, "radius", d.radius, ParamSpec("m", 1.0, 10000.0, "orbit radius").start_only());
  declare(direction_, "direction", std::int64_t{1},
          ParamSpec("", -1, 1, "orbit direction: 1 clockwise, -1 counter-clockwise").start_only());
  declare(spacing_, "spacing", d.spacing,
          ParamSpec("m", 1.0, 100000.0, "arc length between consecutive vehicles on the orbit").start_only());
  declare(altitude_offset_, "altitude_offset", 15.0, ParamSpec("m", 0.0, 500.0, "follower k flies k * this above the leader").start_only());
  declare(gain_, "gain", d.gain, ParamSpec("1/s", 0.0, 10.0, "spacing gain K_s: ground-speed change per metre of arc error").start_only());
  declare(Va_min_, "Va_min", d.Va_min, ParamSpec("m/s", 1.0, 100.0, "lowest follower airspeed").start_only());
  declare(Va_nominal_, "Va_nominal", d.Va_nominal, ParamSpec("m/s", 1.0, 100.0, "the leader's airspeed").start_only());
  declare(Va_max_, "Va_max", d.Va_max, ParamSpec("m/s", 1.0, 100.0, "highest follower airspeed").start_only());
  declare(update_period_, "update_period", 2.0, ParamSpec("s", 0.1, 600.0, "recompute the followers' airspeeds this often"));
  declare(Va_tolerance_, "Va_tolerance", 0.5, ParamSpec("m/s", 0.0, 50.0, "send a follower a new airspeed only when it moved by more"));
  declare(settle_time_, "settle_time", 60.0,
          ParamSpec("s", 0.0, 100000.0, "spacing errors count in summary() from this long after the start"));
  declare(orbit_leader_, "orbit_leader", true,
          ParamSpec("", 0, 0, "send the leader the orbit too (false: it flies its own mission)").start_only());
  if (vehicle_count() == 0) return;  // describing
  const auto leader = leader_().empty() ? std::optional<std::size_t>(0) : index_of(leader_());
  if (!leader) throw ParamError(context().instance_name() + ".leader: '" + leader_() + "' is not one of the mission's vehicles");
  leader_index_ = *leader;
  try {
    config().validate(static_cast<int>(vehicle_count()) - 1);
  } catch (const std::invalid_argument& e) {
    throw ParamError(context().instance_name() + ": " + e.what());
  }
  reset();
}

FormationConfig FormationPlugin::config() const {
  FormationConfig c;
  c.center = Vec2(center_()[0], center_()[1]);
  c.radius = radius_();
  c.direction = static_cast<int>(direction_());
  c.spacing = spacing_();
  c.gain = gain_();
  c.Va_min = Va_min_();
  c.Va_nominal = Va_nominal_();
  c.Va_max = Va_max_();
  return c;
}

void FormationPlugin::reset() {
  flight_ = Flight{};
  flight_.v.resize(vehicle_count());
  reset_fleet();
}

int FormationPlugin::follower_number(std::size_t i) const {
  if (i == leader_index_) return 0;
  return static_cast<int>(i < leader_index_ ? i + 1 : i);
}

void FormationPlugin::step(Nanos now) {
  const double t = to_seconds(now);
  std::vector<std::optional<Observed>> obs(vehicle_count());
  const bool starting = !flight_.t_start.has_value();
  for (std::size_t i = 0; i < obs.size(); ++i) obs[i] = observe(i, starting);
  if (!flight_.t_start)
    start_formation(t, obs);
  else
    track(t, obs);
  send_queued(now);
}

void FormationPlugin::start_formation(double t, const std::vector<std::optional<Observed>>& obs) {
  for (const auto& o : obs)
    if (!o) {
      if (!flight_.waiting_logged) log().info("t = {:.1f} s: waiting for every vehicle to be ready", t);
      flight_.waiting_logged = true;
      return;
    }
  flight_.t_start = t;
  log().info("t = {:.1f} s: every vehicle ready, formation on the orbit starts (leader {})", t, vehicle(leader_index_));
  if (orbit_leader_()) send_orbit(leader_index_, 0, Va_nominal_());
  flight_.last_update = -std::numeric_limits<double>::infinity();
  track(t, obs);
}

void FormationPlugin::track(double t, const std::vector<std::optional<Observed>>& obs) {
  if (!obs[leader_index_]) return;
  const FormationConfig cfg = config();
  const OrbitPlace leader{orbit_angle(obs[leader_index_]->ned.head<2>(), cfg.center), obs[leader_index_]->wind};
  const bool update = t - flight_.last_update >= update_period_() - 1e-6;  // 1 us: steps summed in floating point
  const bool settled = t >= *flight_.t_start + settle_time_();
  if (update) flight_.last_update = t;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const int k = follower_number(i);
    if (k == 0 || !obs[i]) continue;
    const OrbitPlace follower{orbit_angle(obs[i]->ned.head<2>(), cfg.center), obs[i]->wind};
    const double e = spacing_error(leader.theta, follower.theta, k, cfg);
    Vehicle& v = flight_.v[i];
    if (settled) {
      v.sum_sq += e * e;
      ++v.samples;
      flight_.error_max = std::max(flight_.error_max, std::fabs(e));
    }
    const double Va = follower_airspeed(e, leader, follower, cfg);
    if (update && (v.Va_sent == 0.0 || std::fabs(Va - v.Va_sent) > Va_tolerance_())) send_orbit(i, k, Va);
  }
}

void FormationPlugin::send_orbit(std::size_t i, int k, double Va) {
  const auto& c = center_();
  msg::Waypoint wp = lla_waypoint({c[0], c[1], c[2] - k * altitude_offset_()});
  wp.type = msg::Waypoint::loiter;
  wp.loiter_radius = radius_();
  wp.loiter_direction = static_cast<std::int8_t>(direction_() >= 0 ? 1 : -1);
  wp.Va_d = Va;
  queue_add(i, wp, true);
  flight_.v[i].Va_sent = Va;
  ++flight_.updates;
}

std::vector<std::pair<std::string, double>> FormationPlugin::summary() const {
  std::vector<std::pair<std::string, double>> s;
  s.emplace_back("formation_start", flight_.t_start.value_or(-1.0));
  double sum = 0.0;
  std::uint64_t n = 0;
  for (std::size_t i = 0; i < flight_.v.size(); ++i) {
    if (follower_number(i) == 0) continue;
    const Vehicle& v = flight_.v[i];
    s.emplace_back("spacing_rms_" + vehicle(i), v.samples ? std::sqrt(v.sum_sq / static_cast<double>(v.samples)) : 0.0);
    sum += v.sum_sq;
    n += v.samples;
  }
  s.emplace_back("spacing_rms", n ? std::sqrt(sum / static_cast<double>(n)) : 0.0);
  s.emplace_back("spacing_error_max", flight_.error_max);
  s.emplace_back("spacing_samples", static_cast<double>(n));
  s.emplace_back("orbit_updates", static_cast<double>(flight_.updates));
  s.emplace_back("mission_edits", static_cast<double>(edits_sent()));
  return s;
}

}  // namespace tern::coord
