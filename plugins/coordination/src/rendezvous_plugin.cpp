// coord_rendezvous adapter; see rendezvous_plugin.hpp.
#include "rendezvous_plugin.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "tern/math.hpp"

namespace tern::coord {

void RendezvousPlugin::configure() {
  declare_fleet();
  const RendezvousConfig d;
  declare(point_, "point", std::vector<double>{0.0, 0.0, -100.0},
          ParamSpec("m", -100000.0, 100000.0, "rendezvous point [n, e, d] in the common frame (origin)").of_size(3).start_only());
  declare(altitude_spacing_, "altitude_spacing", 15.0,
          ParamSpec("m", 0.0, 500.0, "vehicle i arrives i * this above the point (vertical separation)").start_only());
  declare(Va_min_, "Va_min", d.Va_min, ParamSpec("m/s", 1.0, 100.0, "lowest airspeed commanded").start_only());
  declare(Va_max_, "Va_max", d.Va_max, ParamSpec("m/s", 1.0, 100.0, "highest airspeed commanded").start_only());
  declare(Va_nominal_, "Va_nominal", d.Va_nominal,
          ParamSpec("m/s", 1.0, 100.0, "airspeed of the vehicle farthest in time, and after a hold").start_only());
  declare(arrival_radius_, "arrival_radius", 30.0,
          ParamSpec("m", 1.0, 2000.0, "a vehicle has arrived within this horizontal distance of the point"));
  declare(replan_period_, "replan_period", 5.0, ParamSpec("s", 0.1, 600.0, "replan the vehicles in transit this often"));
  declare(turn_radius_, "turn_radius", d.turn_radius,
          ParamSpec("m", 1.0, 10000.0, "the vehicles' turn radius (their path manager's R_min): path lengths and holds").start_only());
  declare(loiter_radius_, "loiter_radius", 60.0,
          ParamSpec("m", 0.0, 10000.0, "radius of the loiter over the point after arrival (0: the path manager's)"));
  declare(time_tolerance_, "time_tolerance", d.time_tolerance,
          ParamSpec("s", 0.0, 600.0, "a predicted arrival this far off T needs no new command").start_only());
  try {
    config().validate();
  } catch (const std::invalid_argument& e) {
    throw ParamError(context().instance_name() + ": " + e.what());
  }
  flight_ = Flight{};
  flight_.v.resize(vehicle_count());
}

RendezvousConfig RendezvousPlugin::config() const {
  RendezvousConfig c;
  c.Va_min = Va_min_();
  c.Va_max = Va_max_();
  c.Va_nominal = Va_nominal_();
  c.turn_radius = turn_radius_();
  c.time_tolerance = time_tolerance_();
  return c;
}

void RendezvousPlugin::start() {
  if (flight_.v.size() != vehicle_count()) flight_.v.resize(vehicle_count());
}

void RendezvousPlugin::reset() {
  flight_ = Flight{};
  flight_.v.resize(vehicle_count());
  reset_fleet();
}

Eigen::Vector3d RendezvousPlugin::slot(std::size_t i) const {
  const auto& p = point_();
  return {p[0], p[1], p[2] - static_cast<double>(i) * altitude_spacing_()};
}

Vec2 RendezvousPlugin::point2() const { return {point_()[0], point_()[1]}; }

VehicleKinematics RendezvousPlugin::kinematics(const Observed& o) {
  VehicleKinematics k;
  k.p = o.ned.head<2>();
  k.chi = o.chi;
  k.wind = o.wind;
  return k;
}

void RendezvousPlugin::step(Nanos now) {
  const double t = to_seconds(now);
  std::vector<std::optional<Observed>> obs(vehicle_count());
  const bool starting = !flight_.T.has_value();
  for (std::size_t i = 0; i < obs.size(); ++i) obs[i] = observe(i, starting);
  if (!flight_.T) {
    if (!plan_all(t, obs) && !flight_.waiting_logged) log().info("t = {:.1f} s: waiting for every vehicle to be ready", t);
    flight_.waiting_logged = true;
  } else {
    detect_arrivals(t, obs);
    end_holds(t, obs);
    if (t - flight_.last_replan >= replan_period_() - 1e-6) replan(t, obs);  // 1 us: steps summed in floating point
  }
  send_queued(now);
}

bool RendezvousPlugin::plan_all(double t, const std::vector<std::optional<Observed>>& obs) {
  std::vector<VehicleKinematics> ks;
  for (const auto& o : obs) {
    if (!o) return false;
    ks.push_back(kinematics(*o));
  }
  flight_.T = arrival_time(t, ks, point2(), config());
  flight_.T_initial = *flight_.T;
  flight_.last_replan = t;
  log().info("t = {:.1f} s: every vehicle ready, rendezvous planned for T = {:.1f} s", t, *flight_.T);
  for (std::size_t i = 0; i < obs.size(); ++i) command(i, t, *obs[i]);
  return true;
}

void RendezvousPlugin::detect_arrivals(double t, const std::vector<std::optional<Observed>>& obs) {
  for (std::size_t i = 0; i < obs.size(); ++i) {
    Vehicle& v = flight_.v[i];
    if (v.arrived || !obs[i] || !v.commanded) continue;
    // the arrival is the passage: the least horizontal distance to the point while within
    // arrival_radius, taken when the distance grows again (or the vehicle leaves the circle)
    const double d = (obs[i]->ned.head<2>() - point2()).norm();
    if (d <= arrival_radius_() && d <= v.closest) {
      v.closest = d;
      v.closest_t = t;
      continue;
    }
    if (v.closest_t < 0.0) continue;
    v.arrived = true;
    v.arrival_t = v.closest_t;
    msg::Waypoint stay = lla_waypoint(slot(i));
    stay.type = msg::Waypoint::loiter;
    stay.loiter_radius = loiter_radius_();
    stay.Va_d = config().Va_nominal;
    queue_add(i, stay, true);
    log().info("t = {:.1f} s: {} arrived (passed {:.1f} m from the point {:+.1f} s from T), loitering over its slot", v.arrival_t,
               vehicle(i), v.closest, v.arrival_t - *flight_.T);
  }
}

/// A holding vehicle leaves its circle at the first step from which flying to the point at
/// Va_nominal arrives no earlier than T - time_tolerance: where on the circle it then is, its
/// turn onto the leg included, is what the plan's hold_time (from the circle's centre) could
/// only guess (up to half a circle, ~ pi R / Vg), so that it can still both speed up and slow down.
void RendezvousPlugin::end_holds(double t, const std::vector<std::optional<Observed>>& obs) {
  const RendezvousConfig cfg = config();
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const Vehicle& v = flight_.v[i];
    if (!obs[i] || passing(v) || !(t < v.hold_end)) continue;
    if (predicted_arrival(t, kinematics(*obs[i]), point2(), cfg.Va_nominal, cfg) >= *flight_.T - cfg.time_tolerance) command(i, t, *obs[i]);
  }
}

/// Arrived, or inside the arrival circle on its passage: no longer planned for.
bool RendezvousPlugin::passing(const Vehicle& v) { return v.arrived || v.closest_t >= 0.0; }

void RendezvousPlugin::replan(double t, const std::vector<std::optional<Observed>>& obs) {
  flight_.last_replan = t;
  const RendezvousConfig cfg = config();
  std::vector<VehicleKinematics> transit;
  for (std::size_t i = 0; i < obs.size(); ++i)
    if (obs[i] && !passing(flight_.v[i]) && t >= flight_.v[i].hold_end) transit.push_back(kinematics(*obs[i]));
  const double T = arrival_time_slip(t, *flight_.T, transit, point2(), cfg);
  const bool slipped = T > *flight_.T + cfg.time_tolerance;
  if (slipped) {
    log().info("t = {:.1f} s: T moves from {:.1f} s to {:.1f} s (a vehicle cannot make it at Va_max)", t, *flight_.T, T);
    flight_.T = T;
  }
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const Vehicle& v = flight_.v[i];
    if (!obs[i] || passing(v)) continue;
    if (slipped) {
      command(i, t, *obs[i]);
      continue;
    }
    if (t < v.hold_end) continue;  // holding: its list already goes on at Va_nominal
    const double eta = predicted_arrival(t, kinematics(*obs[i]), point2(), v.Va_sent, cfg);
    if (std::fabs(eta - *flight_.T) > cfg.time_tolerance) command(i, t, *obs[i]);
  }
}

/// m: how far past the point the commanded leg goes on (longer than a replan period's flight).
constexpr double kBeyond = 400.0;

void RendezvousPlugin::command(std::size_t i, double t, const Observed& o) {
  const RendezvousConfig cfg = config();
  const VehicleCommand c = command_for(t, *flight_.T, kinematics(o), point2(), cfg);
  Vehicle& v = flight_.v[i];
  msg::Waypoint target = lla_waypoint(slot(i));
  target.Va_d = c.Va_d;
  // A waypoint beyond the point on the line from where the leg starts: the path manager's fillet
  // at the point is then straight (the vehicle passes through it, not inside a corner's cut);
  // after its arrival the vehicle is sent to loiter over its slot.
  const Vec2 from = c.hold_time > 0.0 ? c.hold_center : Vec2(o.ned.head<2>());
  const Vec2 ahead = direction_to(from, point2(), o.chi);
  msg::Waypoint stay = lla_waypoint(slot(i) + Eigen::Vector3d(ahead.x(), ahead.y(), 0.0) * kBeyond);
  stay.Va_d = c.Va_d;
  if (c.hold_time > 0.0) {
    msg::Waypoint hold = lla_waypoint({c.hold_center.x(), c.hold_center.y(), slot(i).z()});
    hold.type = msg::Waypoint::loiter;
    hold.loiter_radius = cfg.turn_radius;
    hold.loiter_direction = 1;
    // end_holds() ends it; the path manager leaves on its own only a circle later (a fleet
    // without its coordination still reaches the point)
    const double circle_time = 2.0 * kPi * cfg.turn_radius / cfg.Va_min;
    hold.loiter_time = c.hold_time + circle_time;
    hold.Va_d = cfg.Va_min;
    queue_add(i, hold, true);
    queue_add(i, target, false);
    v.hold_end = t + hold.loiter_time;
  } else {
    queue_add(i, target, true);
    v.hold_end = -std::numeric_limits<double>::infinity();
  }
  queue_add(i, stay, false);
  v.Va_sent = c.Va_d;
  v.commanded = true;
  ++flight_.replans;
  log().info("t = {:.1f} s: {} -> Va_d {:.1f} m/s over {:.0f} m{}, arrival {:.1f} s", t, vehicle(i), c.Va_d, c.path_length,
             c.hold_time > 0.0 ? fmt::format(" after a {:.0f}-s hold", c.hold_time) : std::string(), c.eta);
}

std::vector<std::pair<std::string, double>> RendezvousPlugin::summary() const {
  std::vector<std::pair<std::string, double>> s;
  const double T = flight_.T.value_or(-1.0);
  s.emplace_back("rendezvous_T", T);
  s.emplace_back("rendezvous_T_initial", flight_.T_initial);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, err = 0.0;
  int arrived = 0;
  for (std::size_t i = 0; i < flight_.v.size(); ++i) {
    const Vehicle& v = flight_.v[i];
    s.emplace_back("arrival_" + vehicle(i), v.arrival_t);
    if (!v.arrived) continue;
    ++arrived;
    lo = std::min(lo, v.arrival_t);
    hi = std::max(hi, v.arrival_t);
    err = std::max(err, std::fabs(v.arrival_t - T));
  }
  s.emplace_back("arrival_spread", arrived > 0 ? hi - lo : 0.0);
  s.emplace_back("arrival_error_max", err);
  s.emplace_back("vehicles_arrived", arrived);
  s.emplace_back("replans", static_cast<double>(flight_.replans));
  s.emplace_back("mission_edits", static_cast<double>(edits_sent()));
  return s;
}

}  // namespace tern::coord
