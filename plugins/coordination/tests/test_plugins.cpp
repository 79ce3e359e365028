// coord_rendezvous and coord_formation through tern::testing::Harness with three vehicles, each
// with its own NED origin (as each vehicle's estimator sets it at its first GNSS fix).
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "formation_plugin.hpp"
#include "rendezvous_plugin.hpp"
#include "tern/geodesy.hpp"
#include "tern/testing/harness.hpp"

using tern::GeoOrigin;
using tern::GeoPoint;
using tern::msg::MissionEdit;
using tern::msg::State;
using tern::msg::Waypoint;

namespace {
const std::vector<double> kOrigin = {45.0, 7.0, 300.0};
const GeoOrigin kCommon(kOrigin[0], kOrigin[1], kOrigin[2]);
const std::vector<std::string> kVehicles = {"uav1", "uav2", "uav3"};

tern::testing::HarnessOptions fleet() {
  tern::testing::HarnessOptions o;
  o.instance = "coord";
  o.vehicles = kVehicles;
  return o;
}

/// Vehicle i's own origin: its take-off place, somewhere else in the common frame.
GeoPoint vehicle_origin(std::size_t i) { return kCommon.to_geodetic(Eigen::Vector3d(-800.0 * i, 300.0 * i, 0.0)); }

/// Vehicle i's estimate at `ned` (common frame) on course chi, in its own frame.
State state_at(std::size_t i, const Eigen::Vector3d& ned, double chi) {
  const GeoPoint o = vehicle_origin(i);
  const Eigen::Vector3d own = GeoOrigin(o).to_ned(kCommon.to_geodetic(ned));
  State x;
  x.valid = true;
  x.origin_valid = true;
  x.origin_lat = o.lat;
  x.origin_lon = o.lon;
  x.origin_alt = o.alt;
  x.p_n = own.x();
  x.p_e = own.y();
  x.p_d = own.z();
  x.chi = chi;
  x.Va = 17.0;
  return x;
}

/// A waypoint's position in the common frame.
Eigen::Vector3d common(const Waypoint& w) {
  REQUIRE(w.lla);
  return kCommon.to_ned(GeoPoint{w.w.x(), w.w.y(), w.w.z()});
}

std::map<std::string, double> summary_of(tern::Plugin& p) {
  std::map<std::string, double> m;
  for (const auto& [k, v] : p.summary()) m[k] = v;
  return m;
}

std::map<std::string, tern::ParamValue> rendezvous_params() {
  return {{"origin", kOrigin},
          {"point", std::vector<double>{0.0, 0.0, -100.0}},
          {"altitude_spacing", 20.0},
          {"start_phase", std::string("valid")},
          {"replan_period", 2.0}};
}

// The rendezvous geometry of the tests: all flying straight at the point, 3000, 2400, 600 m out.
const std::vector<std::pair<Eigen::Vector3d, double>> kStart = {
    {{-3000, 0, -100}, 0.0}, {{0, 2400, -100}, -M_PI / 2}, {{600, 0, -100}, M_PI}};

void feed_start(tern::testing::Harness& h) {
  for (std::size_t i = 0; i < 3; ++i) h.set_input(kVehicles[i] + "/state", state_at(i, kStart[i].first, kStart[i].second));
}
}  // namespace

TEST_CASE("rendezvous plugin: waits for a vehicle without origin, then sends each its slot and airspeed") {
  tern::testing::Harness h(std::make_unique<tern::coord::RendezvousPlugin>(), rendezvous_params(), fleet());
  feed_start(h);
  State late = state_at(1, kStart[1].first, kStart[1].second);
  late.origin_valid = false;  // no GNSS fix yet
  h.set_input("uav2/state", late);
  for (int s = 1; s <= 5; ++s) h.step(tern::from_seconds(0.1 * s));
  for (const auto& v : kVehicles) CHECK(h.published(v + "/mission_edit") == 0);

  feed_start(h);
  h.step(tern::from_seconds(1.0));
  const double T = summary_of(h.plugin()).at("rendezvous_T");
  CHECK(T == doctest::Approx(1.0 + 3000.0 / 17.0).epsilon(1e-3));
  // first edits: a new list each (set_current)
  const MissionEdit& e1 = h.output<MissionEdit>("uav1/mission_edit");
  CHECK(e1.set_current_wp);
  CHECK(e1.waypoint.type == Waypoint::waypoint);
  CHECK(e1.waypoint.Va_d == doctest::Approx(17.0).epsilon(1e-3));
  CHECK((common(e1.waypoint) - Eigen::Vector3d(0, 0, -100)).norm() < 0.01);
  const MissionEdit& e2 = h.output<MissionEdit>("uav2/mission_edit");
  CHECK(e2.waypoint.Va_d == doctest::Approx(2400.0 / (T - 1.0)).epsilon(1e-3));
  CHECK((common(e2.waypoint) - Eigen::Vector3d(0, 0, -120)).norm() < 0.01);  // 20 m above uav1
  const MissionEdit& e3 = h.output<MissionEdit>("uav3/mission_edit");
  CHECK(e3.set_current_wp);
  CHECK(e3.waypoint.type == Waypoint::loiter);  // the near one holds first
  CHECK(e3.waypoint.loiter_time > 100.0);
  CHECK(common(e3.waypoint).z() == doctest::Approx(-140.0).epsilon(1e-4));
  // the rest of each list follows, one edit per step: uav3's waypoint at its slot, then its loiter
  h.step(tern::from_seconds(1.1));
  CHECK_FALSE(h.output<MissionEdit>("uav3/mission_edit").set_current_wp);
  CHECK(h.output<MissionEdit>("uav3/mission_edit").waypoint.type == Waypoint::waypoint);
  CHECK(h.output<MissionEdit>("uav3/mission_edit").waypoint.Va_d == doctest::Approx(17.0));
  // uav1's leg goes on 400 m beyond the point (straight through it: no fillet cut there)
  CHECK(h.output<MissionEdit>("uav1/mission_edit").waypoint.type == Waypoint::waypoint);
  CHECK(common(h.output<MissionEdit>("uav1/mission_edit").waypoint).head<2>().norm() == doctest::Approx(400.0).epsilon(1e-3));
  h.step(tern::from_seconds(1.2));
  CHECK(h.output<MissionEdit>("uav3/mission_edit").waypoint.type == Waypoint::waypoint);
  CHECK(h.published("uav1/mission_edit") == 2);
  CHECK(h.published("uav3/mission_edit") == 3);
}

TEST_CASE("rendezvous plugin: start_phase cruise waits for every vehicle's cruise") {
  auto params = rendezvous_params();
  params["start_phase"] = std::string("cruise");
  tern::testing::Harness h(std::make_unique<tern::coord::RendezvousPlugin>(), params, fleet());
  feed_start(h);
  tern::msg::FlightPhase ph;
  ph.phase = tern::msg::Phase::cruise;
  h.set_input("uav1/flight_phase", ph);
  h.set_input("uav2/flight_phase", ph);
  ph.phase = tern::msg::Phase::climb;
  h.set_input("uav3/flight_phase", ph);
  h.step(tern::from_seconds(1.0));
  CHECK(summary_of(h.plugin()).at("rendezvous_T") == -1.0);
  ph.phase = tern::msg::Phase::cruise;
  h.set_input("uav3/flight_phase", ph);
  h.step(tern::from_seconds(2.0));
  CHECK(summary_of(h.plugin()).at("rendezvous_T") > 100.0);
  // the phase gates the start only: uav1 out of cruise still arrives
  ph.phase = tern::msg::Phase::loiter;
  h.set_input("uav1/flight_phase", ph);
  h.set_input("uav1/state", state_at(0, {-10, 0, -100}, 0.0));
  h.step(tern::from_seconds(3.0));
  CHECK(summary_of(h.plugin()).at("arrival_uav1") == -1.0);  // in the circle: the passage not over yet
  h.set_input("uav1/state", state_at(0, {15, 0, -100}, 0.0));
  h.step(tern::from_seconds(3.5));
  CHECK(summary_of(h.plugin()).at("arrival_uav1") == 3.0);  // the least distance
}

namespace {
/// Flies the three vehicles kinematically along their commands: straight through the point at
/// the commanded airspeed (no wind; the leg goes on beyond it), holding in place while a hold
/// lasts, for `seconds`. Returns the summary.
std::map<std::string, double> fly_rendezvous(tern::testing::Harness& h, double seconds, bool nan_uav2 = false) {
  std::vector<Eigen::Vector3d> p;
  std::vector<double> chi, Va(3, 0.0), hold_until(3, 0.0);
  std::vector<Eigen::Vector2d> leg(3, Eigen::Vector2d::Zero());  // the direction of each one's leg
  for (const auto& s : kStart) {
    p.push_back(s.first);
    chi.push_back(s.second);
  }
  const double dt = 0.1;
  for (int s = 1; s <= static_cast<int>(seconds / dt); ++s) {
    const double t = s * dt;
    for (std::size_t i = 0; i < 3; ++i) {
      State x = state_at(i, p[i], chi[i]);
      if (nan_uav2 && i == 1 && t > 60.0 && t < 70.0) x.p_n = NAN;
      h.set_input(kVehicles[i] + "/state", x);
    }
    h.step(tern::from_seconds(t));
    for (std::size_t i = 0; i < 3; ++i) {
      const std::string port = kVehicles[i] + "/mission_edit";
      if (h.published(port) == 0) continue;
      const MissionEdit& e = h.output<MissionEdit>(port);
      REQUIRE(std::isfinite(e.waypoint.w.x()));
      if (e.set_current_wp) hold_until[i] = e.waypoint.type == Waypoint::loiter ? t + e.waypoint.loiter_time : 0.0;
      if (e.waypoint.type == Waypoint::waypoint) Va[i] = e.waypoint.Va_d;
      if (leg[i].isZero()) leg[i] = -p[i].head<2>().normalized();
      if (t < hold_until[i]) continue;
      p[i].head<2>() += leg[i] * Va[i] * dt;
    }
  }
  h.stop();
  return summary_of(h.plugin());
}
}  // namespace

TEST_CASE("rendezvous plugin: flown along its commands, the vehicles arrive together at T") {
  tern::testing::Harness h(std::make_unique<tern::coord::RendezvousPlugin>(), rendezvous_params(), fleet());
  const auto s = fly_rendezvous(h, 220.0);
  CHECK(s.at("vehicles_arrived") == 3.0);
  const double T = s.at("rendezvous_T");
  CHECK(T == s.at("rendezvous_T_initial"));
  // arrival: the passage (the least distance to the point), at T to a step (0.1 s)
  for (const auto& v : kVehicles) CHECK(s.at("arrival_" + v) == doctest::Approx(T).epsilon(0.15 / T));
  CHECK(s.at("arrival_spread") < 1.0);
  // the plan held: one list each and no thrashing (2 + 2 + 3 edits), the holding vehicle's end
  // of hold (a list of 2, end_holds), then each its loiter over its slot on arriving (3)
  CHECK(s.at("replans") == 4.0);
  CHECK(s.at("mission_edits") == 12.0);
}

TEST_CASE("rendezvous plugin: a vehicle that falls behind is replanned faster") {
  tern::testing::Harness h(std::make_unique<tern::coord::RendezvousPlugin>(), rendezvous_params(), fleet());
  feed_start(h);
  h.step(tern::from_seconds(0.1));
  const double T = summary_of(h.plugin()).at("rendezvous_T");
  const double Va0 = h.output<MissionEdit>("uav2/mission_edit").waypoint.Va_d;
  // the vehicles do not move: at the first replan (2.1 s) none is late by more than 2 s yet; at
  // the second (4.1 s) every one is, and gets the airspeed for what is left
  double Va = Va0, t_replan = 0.0;
  for (int s = 2; s <= 50; ++s) {
    feed_start(h);
    h.step(tern::from_seconds(0.1 * s));
    const MissionEdit& e = h.output<MissionEdit>("uav2/mission_edit");
    if (e.set_current_wp && e.waypoint.Va_d != Va) {
      Va = e.waypoint.Va_d;
      t_replan = 0.1 * s;
    }
  }
  CHECK(t_replan == doctest::Approx(4.1));
  CHECK(Va == doctest::Approx(2400.0 / (T - t_replan)).epsilon(1e-3));
  CHECK(Va > Va0 + 0.2);
  CHECK(summary_of(h.plugin()).at("rendezvous_T") == T);  // uav1 still makes T at Va_max
}

TEST_CASE("rendezvous plugin: NaN in a state is skipped, the flight goes on") {
  tern::testing::Harness h(std::make_unique<tern::coord::RendezvousPlugin>(), rendezvous_params(), fleet());
  const auto s = fly_rendezvous(h, 220.0, true);
  CHECK(s.at("vehicles_arrived") == 3.0);
  CHECK(s.at("arrival_spread") < 1.0);
  for (const auto& [k, v] : s) CHECK_MESSAGE(std::isfinite(v), k);
}

TEST_CASE("rendezvous plugin: after reset() a flight is the first one again") {
  tern::testing::Harness h(std::make_unique<tern::coord::RendezvousPlugin>(), rendezvous_params(), fleet());
  const auto first = fly_rendezvous(h, 120.0);
  CHECK(first.at("vehicles_arrived") == 0.0);  // T is ~177 s
  CHECK(first.at("mission_edits") == 7.0);
  h.reset();
  CHECK(fly_rendezvous(h, 120.0) == first);
  h.reset();
  const auto full = fly_rendezvous(h, 220.0);
  CHECK(full.at("vehicles_arrived") == 3.0);
}

TEST_CASE("rendezvous plugin: bad parameters and a one-vehicle mission are refused") {
  auto p = rendezvous_params();
  p["Va_nominal"] = 30.0;  // above Va_max
  CHECK_THROWS_AS(tern::testing::Harness(std::make_unique<tern::coord::RendezvousPlugin>(), p, fleet()), tern::ParamError);
  p = rendezvous_params();
  p["origin"] = std::vector<double>{95.0, 7.0, 300.0};
  CHECK_THROWS_AS(tern::testing::Harness(std::make_unique<tern::coord::RendezvousPlugin>(), p, fleet()), tern::ParamError);
  CHECK_THROWS_AS(tern::testing::Harness(std::make_unique<tern::coord::RendezvousPlugin>(), rendezvous_params()), tern::ParamError);
}

namespace {
std::map<std::string, tern::ParamValue> formation_params() {
  return {{"origin", kOrigin},
          {"leader", std::string("uav2")},
          {"center", std::vector<double>{200.0, -100.0, -120.0}},
          {"radius", 150.0},
          {"spacing", 100.0},
          {"start_phase", std::string("valid")},
          {"settle_time", 0.0},
          {"update_period", 1.0}};
}

/// Vehicle i on the orbit (clockwise) at angle theta about the formation's centre.
State on_orbit(std::size_t i, double theta) {
  const Eigen::Vector3d c(200.0, -100.0, -120.0);
  return state_at(i, c + 150.0 * Eigen::Vector3d(std::cos(theta), std::sin(theta), 0.0), theta + M_PI / 2);
}
}  // namespace

TEST_CASE("formation plugin: an unknown leader is refused, naming it") {
  auto p = formation_params();
  p["leader"] = std::string("uav9");
  try {
    tern::testing::Harness h(std::make_unique<tern::coord::FormationPlugin>(), p, fleet());
    FAIL("no error");
  } catch (const tern::ParamError& e) {
    CHECK(std::string(e.what()).find("uav9") != std::string::npos);
  }
}

TEST_CASE("formation plugin: the orbit for everyone, a follower behind is sent faster, one ahead slower") {
  tern::testing::Harness h(std::make_unique<tern::coord::FormationPlugin>(), formation_params(), fleet());
  const double want = 100.0 / 150.0;
  // leader uav2 at 0; uav1 (follower 1) 0.2 rad too far behind, uav3 (follower 2) 0.1 rad ahead of its place
  h.set_input("uav2/state", on_orbit(1, 0.0));
  h.set_input("uav1/state", on_orbit(0, -want - 0.2));
  h.set_input("uav3/state", on_orbit(2, -2 * want + 0.1));
  h.step(tern::from_seconds(1.0));
  const Waypoint& lead = h.output<MissionEdit>("uav2/mission_edit").waypoint;
  CHECK(lead.type == Waypoint::loiter);
  CHECK(lead.Va_d == 17.0);
  CHECK(lead.loiter_radius == 150.0);
  CHECK((common(lead) - Eigen::Vector3d(200, -100, -120)).norm() < 0.01);
  const Waypoint& f1 = h.output<MissionEdit>("uav1/mission_edit").waypoint;
  CHECK(f1.Va_d == doctest::Approx(17.0 + 0.05 * 30.0));
  CHECK(common(f1).z() == doctest::Approx(-135.0).epsilon(1e-4));
  const Waypoint& f2 = h.output<MissionEdit>("uav3/mission_edit").waypoint;
  CHECK(f2.Va_d == doctest::Approx(17.0 - 0.05 * 15.0));
  CHECK(common(f2).z() == doctest::Approx(-150.0).epsilon(1e-4));
  // same places a second later: no new edits (the airspeeds did not move)
  h.step(tern::from_seconds(2.5));
  CHECK(h.published("uav1/mission_edit") == 1);
  const auto s = summary_of(h.plugin());
  CHECK(s.at("spacing_rms_uav1") == doctest::Approx(30.0));
  CHECK(s.at("spacing_rms") == doctest::Approx(std::sqrt((30.0 * 30.0 + 15.0 * 15.0) / 2.0)));
}

namespace {
/// Flies the formation kinematically on the orbit at the commanded airspeeds for `seconds`.
std::map<std::string, double> fly_formation(tern::testing::Harness& h, double seconds) {
  std::vector<double> th = {2.0, 0.0, -2.5}, Va(3, 17.0);
  const double dt = 0.1;
  for (int s = 1; s <= static_cast<int>(seconds / dt); ++s) {
    for (std::size_t i = 0; i < 3; ++i) h.set_input(kVehicles[i] + "/state", on_orbit(i, th[i]));
    h.step(tern::from_seconds(s * dt));
    for (std::size_t i = 0; i < 3; ++i) {
      if (h.published(kVehicles[i] + "/mission_edit") > 0) Va[i] = h.output<MissionEdit>(kVehicles[i] + "/mission_edit").waypoint.Va_d;
      th[i] += Va[i] / 150.0 * dt;
    }
  }
  h.stop();
  return summary_of(h.plugin());
}
}  // namespace

TEST_CASE("formation plugin: flown on the orbit the spacing converges; reset() starts afresh") {
  auto p = formation_params();
  p["settle_time"] = 200.0;
  tern::testing::Harness h(std::make_unique<tern::coord::FormationPlugin>(), p, fleet());
  const auto first = fly_formation(h, 300.0);
  CHECK(first.at("formation_start") == doctest::Approx(0.1));
  CHECK(first.at("spacing_samples") > 1000.0);
  // the airspeed moves in steps of Va_tolerance (0.5 m/s = 10 m of error at K_s 0.05)
  CHECK(first.at("spacing_error_max") < 12.0);
  h.reset();
  CHECK(fly_formation(h, 300.0) == first);
}
