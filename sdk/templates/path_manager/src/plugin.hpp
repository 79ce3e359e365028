// @CLASS@: the tern adapter of LineManager (line_manager.hpp).
//
// Ports:  in  state         msg::State (p_n, p_e, p_d); nothing published while !valid
//         in  waypoints     msg::WaypointList (NED) from the path planner; a new revision
//                           restarts the mission at its first segment
//         out current_path  msg::CurrentPath: a line w_{i-1} -> w_i, or the loiter orbit
// Parameters: default_airspeed (for waypoints without Va_d), orbit_radius, loiter_altitude.
// Per-flight state (tern/plugin.hpp): everything a flight changes is in `flight_`, which
// reset() replaces wholesale; a new mission state or counter goes there.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "line_manager.hpp"
#include "tern/plugin.hpp"

class @CLASS@ final : public tern::Plugin {
 public:
  void configure() override {
    using tern::ParamSpec;
    declare(state_, "state", "vehicle state (position)");
    declare(waypoints_, "waypoints", "the mission, NED, from the path planner");
    declare(path_, "current_path", "the segment to follow now (line or orbit)");
    declare(default_airspeed_, "default_airspeed", 17.0, ParamSpec("m/s", 5.0, 60.0, "airspeed for waypoints without Va_d"));
    declare(orbit_radius_, "orbit_radius", 50.0, ParamSpec("m", 10.0, 5000.0, "radius of the loiter orbit"));
    declare(loiter_altitude_, "loiter_altitude", 100.0, ParamSpec("m", 0.0, 10000.0, "orbit altitude above the origin without waypoints"));
  }

  /// Between flights: as after configure() (no mission until the waypoints come).
  void reset() override { flight_ = Flight{}; }

  void step(tern::Nanos now) override {
    tern_@NAME@::LineManager& manager = flight_.manager;
    const tern::msg::WaypointList& list = *waypoints_;
    if (waypoints_.has_value() && flight_.revision != list.revision) {
      std::vector<Eigen::Vector3d> w;
      flight_.Va_d.clear();
      for (std::uint32_t k = 0; k < list.count && k < list.items.size(); ++k) {
        w.push_back(list.items[k].w);
        flight_.Va_d.push_back(list.items[k].Va_d);
      }
      manager.set_waypoints(std::move(w), list.loop);
      flight_.revision = list.revision;
    }
    const tern::msg::State& x = *state_;
    if (!x.valid) return;
    manager.orbit_radius = orbit_radius_();
    manager.loiter_altitude = loiter_altitude_();
    const tern_@NAME@::Segment s = manager.update({x.p_n, x.p_e, x.p_d});

    tern::msg::CurrentPath path;
    path.stamp = now;
    path.path_type = s.type == tern_@NAME@::Segment::orbit ? tern::msg::CurrentPath::orbit : tern::msg::CurrentPath::line;
    path.r = s.r;
    path.q = s.q;
    path.c = s.c;
    path.rho = s.rho;
    path.lambda = static_cast<std::int8_t>(s.lambda);
    path.waypoint_index = s.index;
    const std::vector<double>& Va_d = flight_.Va_d;
    const bool has_Va = s.index >= 0 && static_cast<std::size_t>(s.index) < Va_d.size() && Va_d[s.index] > 0.0;
    path.Va_d = has_Va ? Va_d[s.index] : default_airspeed_();
    path_.publish(path);
  }

 private:
  tern::Input<tern::msg::State> state_;
  tern::Input<tern::msg::WaypointList> waypoints_;
  tern::Output<tern::msg::CurrentPath> path_;
  tern::Param<double> default_airspeed_, orbit_radius_, loiter_altitude_;
  /// What a flight changes; reset() replaces it with a fresh one.
  struct Flight {
    tern_@NAME@::LineManager manager;      ///< the mission and the segment flown (step() gives it the parameters first)
    std::vector<double> Va_d;              ///< airspeed of each waypoint, m/s (<= 0: default_airspeed)
    std::optional<std::uint32_t> revision;  ///< of the waypoint list flown; none before the first
  } flight_;
};
