// @CLASS@: a coordination plugin. Once a vehicle's estimate is valid, it sends that vehicle to
// loiter over one common point, each at its own altitude (vehicle i, in the mission's vehicles:
// order, i * altitude_spacing above the point), records when each arrives over the point and the
// closest approach of any two vehicles, and adds them to the flight's summary.json.
// A starting point for rendezvous, formations, task allocation: anything that looks at every
// vehicle and sends them mission edits.
//
// Ports, for each vehicle v of context().vehicles() (the host binds "v/T" to vehicle v's topic T):
//   in  v/state          msg::State: v's estimate in ITS OWN NED frame, whose origin is
//                        origin_lat/lon/alt (origin_valid false before its first GNSS fix)
//   out v/mission_edit   msg::MissionEdit: to v's path planner, applied at its next tick
// Frames: each estimate goes through its own origin to latitude/longitude and into the common
// frame of the `origin` parameter (tern/geodesy.hpp); the loiter goes out as lat/lon/alt
// (waypoint.lla), which each vehicle's planner converts into its own frame. Never the truth.
// Parameters: origin [lat deg, lon deg, alt m MSL], point [n, e, d] m in that frame,
// altitude_spacing (m), loiter_radius (m), Va (m/s).
// Summary: <instance>.arrival_<vehicle> (s, -1: not arrived), .vehicles_arrived,
//          .min_separation (m, estimates).
// Per-flight state (tern/plugin.hpp): everything a flight changes is in `flight_`, which
// reset() replaces wholesale.
#pragma once

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>

#include "gather.hpp"
#include "tern/geodesy.hpp"
#include "tern/plugin.hpp"

class @CLASS@ final : public tern::Plugin {
 public:
  void configure() override {
    using tern::ParamSpec;
    declare(origin_, "origin", std::vector<double>{0.0, 0.0, 0.0},
            ParamSpec("deg|m", -1000.0, 20000.0, "common frame origin [lat deg, lon deg, alt m MSL]").of_size(3).start_only());
    declare(point_, "point", std::vector<double>{0.0, 0.0, -100.0},
            ParamSpec("m", -100000.0, 100000.0, "gathering point [n, e, d] in the common frame").of_size(3).start_only());
    declare(spacing_, "altitude_spacing", 20.0, ParamSpec("m", 0.0, 500.0, "vehicle i loiters i * this above the point"));
    declare(radius_, "loiter_radius", 80.0, ParamSpec("m", 10.0, 5000.0, "loiter radius; arrived within this of the point"));
    declare(Va_, "Va", 16.0, ParamSpec("m/s", 5.0, 60.0, "airspeed to the point and on the loiter"));
    for (const std::string& v : context().vehicles()) {
      auto p = std::make_unique<Ports>();
      declare(p->state, v + "/state", "vehicle " + v + "'s estimate (its own NED frame)");
      declare(p->edit, v + "/mission_edit", "mission edits for vehicle " + v + "'s path planner");
      ports_.push_back(std::move(p));
    }
    reset();
  }

  /// Between flights: as after configure() (nobody sent anywhere yet).
  void reset() override {
    flight_ = Flight{};
    flight_.vehicles.resize(ports_.size());
  }

  void step(tern::Nanos now) override {
    const tern::GeoOrigin frame(origin_()[0], origin_()[1], origin_()[2]);
    const Eigen::Vector3d point(point_()[0], point_()[1], point_()[2]);
    std::vector<Eigen::Vector3d> where(ports_.size(), Eigen::Vector3d::Constant(NAN));
    for (std::size_t i = 0; i < ports_.size(); ++i) {
      const auto p = position(i, frame);
      if (!p) continue;
      where[i] = *p;
      Vehicle& v = flight_.vehicles[i];
      if (!v.sent) send(i, now, frame, point);
      if (v.arrival < 0.0 && tern_@NAME@::within(*p, point, radius_())) {
        v.arrival = tern::to_seconds(now);
        log().info("t = {:.1f} s: {} is over the point", v.arrival, context().vehicles()[i]);
      }
    }
    flight_.separation.add(where);
  }

  std::vector<std::pair<std::string, double>> summary() const override {
    std::vector<std::pair<std::string, double>> s;
    int arrived = 0;
    for (std::size_t i = 0; i < flight_.vehicles.size(); ++i) {
      s.emplace_back("arrival_" + context().vehicles()[i], flight_.vehicles[i].arrival);
      arrived += flight_.vehicles[i].arrival >= 0.0 ? 1 : 0;
    }
    s.emplace_back("vehicles_arrived", arrived);
    s.emplace_back("min_separation", flight_.separation.min());
    return s;
  }

 private:
  /// Vehicle i's estimated position in the common frame, if it is valid and finite.
  std::optional<Eigen::Vector3d> position(std::size_t i, const tern::GeoOrigin& frame) {
    const auto& in = ports_[i]->state;
    if (!in.has_value() || !in->valid || !in->origin_valid) return std::nullopt;
    const tern::msg::State& x = *in;
    const Eigen::Vector3d own(x.p_n, x.p_e, x.p_d);
    if (!own.allFinite() || !std::isfinite(x.origin_lat) || !std::isfinite(x.origin_lon) || !std::isfinite(x.origin_alt)) {
      if (!flight_.vehicles[i].warned) log().warn("{}/state is not finite: ignored while it lasts", context().vehicles()[i]);
      flight_.vehicles[i].warned = true;
      return std::nullopt;
    }
    return frame.to_ned(tern::GeoOrigin(x.origin_lat, x.origin_lon, x.origin_alt).to_geodetic(own));
  }

  /// A new list for vehicle i: one loiter over its slot, no time limit.
  void send(std::size_t i, tern::Nanos now, const tern::GeoOrigin& frame, const Eigen::Vector3d& point) {
    const tern::GeoPoint g = frame.to_geodetic(tern_@NAME@::slot(point, i, spacing_()));
    tern::msg::MissionEdit e;
    e.stamp = now;
    e.id = static_cast<std::uint32_t>(i + 1);
    e.op = tern::msg::MissionEdit::add;
    e.set_current_wp = true;
    e.waypoint.lla = true;
    e.waypoint.w = Eigen::Vector3d(g.lat, g.lon, g.alt);
    e.waypoint.type = tern::msg::Waypoint::loiter;
    e.waypoint.loiter_radius = radius_();
    e.waypoint.Va_d = Va_();
    ports_[i]->edit.publish(e);
    flight_.vehicles[i].sent = true;
    log().info("{} sent to loiter {:.0f} m above the point", context().vehicles()[i], static_cast<double>(i) * spacing_());
  }

  struct Ports {
    tern::Input<tern::msg::State> state;
    tern::Output<tern::msg::MissionEdit> edit;
  };
  std::vector<std::unique_ptr<Ports>> ports_;  ///< one per vehicle, in context().vehicles() order
  tern::Param<std::vector<double>> origin_, point_;
  tern::Param<double> spacing_, radius_, Va_;
  struct Vehicle {
    bool sent = false;     ///< its loiter went out
    double arrival = -1.0;  ///< s, -1: not yet
    bool warned = false;   ///< non-finite state warned
  };
  /// What a flight changes; reset() replaces it with a fresh one.
  struct Flight {
    std::vector<Vehicle> vehicles;
    tern_@NAME@::Separation separation;
  } flight_;
};
