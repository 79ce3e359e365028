// Path manager behaviour (every degenerate case), closed-loop flights with a kinematic
// aircraft, and the three plugins through the SDK harness.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "../src/adapters.hpp"
#include "kinematic.hpp"
#include "tern/path/follower.hpp"
#include "tern/path/manager.hpp"
#include "tern/path/mission.hpp"
#include "tern/testing/harness.hpp"
#include "tern/math.hpp"

using namespace tern;
using namespace tern::path;
using doctest::Approx;

namespace {
using tern::kPi;
const std::filesystem::path kData = TERN_PATH_TEST_DATA;

std::vector<MissionPoint> points(const std::vector<Vec3>& ws, bool use_chi = false, double chi_d = 0.0) {
  std::vector<MissionPoint> out;
  for (const auto& w : ws) out.push_back({w, chi_d, use_chi, 17.0, ItemType::waypoint, {}});
  return out;
}

std::vector<MissionPoint> hourglass(bool use_chi = false) {
  return points({{400, -250, -70}, {-400, -50, -70}, {-400, -250, -70}, {400, -50, -70}}, use_chi, 1.1518);
}

/// The manager (100 Hz) and the follower (10 Hz, as ROSplane) flying the kinematic aircraft.
struct Flight {
  explicit Flight(ManagerConfig cfg = {})
      : manager(
            cfg, [this](const std::string& s) { warnings.push_back(s); }, [this](const std::string& s) { infos.push_back(s); }) {
    aircraft.h = 70;
  }
  PathManager manager;
  testkit::KinematicAircraft aircraft;
  std::vector<std::string> warnings;
  std::vector<std::string> infos;
  bool finite = true;
  double t = 0.0;
  double worst_line_error = 0.0;   ///< |cross-track| on lines, from the second segment on
  double worst_orbit_error = 0.0;  ///< ||p - c| - rho| on orbits after settle_s
  double settle_s = 0.0;
  PathSegment seg;
  std::vector<int> targets;  ///< distinct successive targets

  void run(double seconds) {
    const double dt = 0.01;
    FollowerCommand c;
    const int steps = static_cast<int>(std::lround(seconds / dt));
    for (int k = 0; k < steps; ++k, t += dt) {
      seg = manager.update(aircraft.p(), aircraft.chi, t);
      if (targets.empty() || targets.back() != manager.target()) targets.push_back(manager.target());
      if (k % 10 == 0) {
        FollowerInput in;
        in.p = aircraft.p();
        in.chi = aircraft.chi;
        in.psi = aircraft.psi;
        in.Va = aircraft.Va;
        in.Vg = aircraft.Vg();
        c = follow(seg, in, FollowerGains{});
      }
      finite = finite && std::isfinite(c.chi_c) && std::isfinite(c.h_c) && std::isfinite(c.phi_ff) && std::isfinite(c.Va_c) &&
               seg.r.allFinite() && seg.q.allFinite() && seg.c.allFinite() && std::isfinite(seg.rho);
      aircraft.step(c.chi_c, c.phi_ff, c.h_c, c.Va_c, dt);
      if (t > settle_s) {
        if (seg.type == PathSegment::Type::line && manager.passed().size() >= 1)
          worst_line_error = std::max(worst_line_error, std::fabs(cross_track_error(seg.r, seg.q, aircraft.p())));
        if (seg.type == PathSegment::Type::orbit)
          worst_orbit_error = std::max(worst_orbit_error, std::fabs((aircraft.p() - seg.c).head<2>().norm() - seg.rho));
      }
    }
  }
  int count_warnings(const std::string& part) const {
    int n = 0;
    for (const auto& w : warnings) n += w.find(part) != std::string::npos;
    return n;
  }
};

/// Passages of the hourglass waypoints in order: 0 1 2 3 0 1 ...
bool in_cycle_order(const std::vector<int>& passed, int n) {
  for (std::size_t i = 1; i < passed.size(); ++i)
    if (passed[i] != (passed[i - 1] + 1) % n) return false;
  return true;
}
}  // namespace

TEST_CASE("manager: no waypoints -> orbit the origin at the default altitude and airspeed") {
  PathManager m;
  const PathSegment s = m.update(Vec3(10, 10, -20), 0.0, 0.0);
  CHECK(s.type == PathSegment::Type::orbit);
  CHECK(s.c == Vec3(0, 0, -50));
  CHECK(s.rho == 50.0);
  CHECK(s.lambda == 1);
  CHECK(s.Va_d == 15.0);
  CHECK(s.waypoint_index == -1);
  CHECK_THROWS_AS(m.set_config(ManagerConfig{0.0}), std::invalid_argument);
}

TEST_CASE("manager: the hourglass with fillets is flyable and its fillets are where the book puts them") {
  Flight f;
  f.manager.set_waypoints(hourglass(), true);
  // Fillet at waypoint 1 between the legs w0 -> w1 (course 166 deg) and w1 -> w2 (due west):
  // cos(varrho) = -q_in . q_out = 200 / sqrt(800^2 + 200^2), offset = R / tan(varrho / 2),
  // z1 = w1 - offset q_in, z2 = w1 + offset q_out = (-400, -50 - offset), centre R north of
  // z2 (a right turn onto a westbound leg), clockwise.
  bool checked = false;
  for (int k = 0; k < 1500 && !checked; ++k) {
    f.run(0.1);
    if (f.manager.target() == 1 && f.manager.stage() == PathManager::Stage::fillet_line) {
      const Fillet& fl = f.manager.fillet();
      const double varrho = std::acos(200.0 / std::sqrt(680000.0));
      const double offset = 50.0 / std::tan(varrho / 2);
      CHECK(fl.offset == Approx(offset));
      CHECK(offset == Approx(64.04).epsilon(1e-4));
      const Vec3 q_in = Vec3(-800, 200, 0).normalized();
      CHECK((fl.z1 - (Vec3(-400, -50, -70) - offset * q_in)).norm() < 1e-9);
      CHECK((fl.z2 - Vec3(-400, -50 - offset, -70)).norm() < 1e-9);
      CHECK((fl.c - Vec3(-350, -50 - offset, -70)).norm() < 1e-9);
      CHECK(fl.lambda == 1);
      checked = true;
    }
  }
  REQUIRE(checked);
  f.settle_s = 0.0;
  f.run(400.0);
  CHECK(f.finite);
  CHECK(f.warnings.empty());
  REQUIRE(f.manager.passed().size() >= 8);  // twice around
  CHECK(f.manager.passed().front() == 0);
  CHECK(in_cycle_order(f.manager.passed(), 4));
  CHECK(f.worst_line_error < 10.0);
  CHECK(f.worst_orbit_error < 15.0);
}

TEST_CASE("manager: the hourglass (fillets and Dubins) stays flyable in a 5 m/s wind") {
  for (bool use_chi : {false, true}) {
    CAPTURE(use_chi);
    Flight f;
    f.aircraft.w_n = 3.0;
    f.aircraft.w_e = -4.0;
    f.settle_s = 30.0;
    f.manager.set_waypoints(hourglass(use_chi), true);
    f.run(500.0);
    CHECK(f.finite);
    CHECK(f.warnings.empty());
    REQUIRE(f.manager.passed().size() >= 8);
    CHECK(in_cycle_order(f.manager.passed(), 4));
    CHECK(f.worst_line_error < 15.0);
    CHECK(f.worst_orbit_error < 25.0);
  }
}

TEST_CASE("manager: turn_bank plans each turn for the wind: the downwind fillets of the hourglass widen, the aircraft stays on them") {
  const double w_n = 3.5355339, w_e = -3.5355339;  // 5 m/s to the north-west, as the default mission
  double worst[2] = {0.0, 0.0};
  for (int planned = 0; planned < 2; ++planned) {
    CAPTURE(planned);
    ManagerConfig cfg;
    cfg.turn_bank = planned ? 30.0 * kPi / 180.0 : 0.0;
    Flight f(cfg);
    f.aircraft.w_n = w_n;
    f.aircraft.w_e = w_e;
    f.manager.set_wind(Vec3(w_n, w_e, 0.0));
    f.settle_s = 60.0;
    f.manager.set_waypoints(hourglass(), true);
    std::map<int, double> radius;  // fillet radius per waypoint
    for (int k = 0; k < 5000; ++k) {
      f.run(0.1);
      if (f.manager.stage() == PathManager::Stage::fillet_orbit) radius[f.manager.target()] = f.seg.rho;
    }
    CHECK(f.finite);
    REQUIRE(f.manager.passed().size() >= 8);
    CHECK(in_cycle_order(f.manager.passed(), 4));
    REQUIRE(radius.size() == 4);
    worst[planned] = f.worst_orbit_error;
    if (!planned) {
      for (const auto& [wp, R] : radius) CHECK(R == 50.0);
      CHECK(f.warnings.empty());
      continue;
    }
    // waypoints 2 and 3 turn through the downwind course: (17 + 5)^2 / (g tan 30 deg) = 85.5 m
    // does not fit; the 200-m legs leave 100 m / tan(52 deg) = 78.1 m (warned once each)
    // (tangent points offset R tan(turn / 2) from the waypoint, turn = pi - varrho = 104 deg)
    const double varrho = std::acos(200.0 / std::sqrt(680000.0));
    const double R_fit = 100.0 / std::tan(0.5 * (kPi - varrho));
    CHECK(radius[2] == Approx(R_fit).epsilon(1e-6));
    CHECK(radius[3] == Approx(R_fit).epsilon(1e-6));
    // information, not a warning: the manager flies the turn tighter, at 33 deg instead of 30
    auto count_infos = [&](const std::string& part) {
      return std::count_if(f.infos.begin(), f.infos.end(), [&](const std::string& i) { return i.find(part) != std::string::npos; });
    };
    CHECK(count_infos("waypoint 2: the turn needs a radius of 85.5 m") == 1);
    CHECK(count_infos("waypoint 3: the turn needs a radius of 85.5 m") == 1);
    CHECK(count_infos("m, about 32.") + count_infos("m, about 33.") == 2);
    CHECK(f.count_warnings("the turn needs") == 0);
    // waypoints 0 and 1 turn upwind: smaller radii, still above R_min
    CHECK(radius[0] > 60.0);
    CHECK(radius[0] < radius[2]);
    CHECK(radius[1] > 60.0);
    CHECK(radius[1] < radius[2]);
  }
  MESSAGE("worst orbit error after the first minute: " << worst[0] << " m with R_min 50 m, " << worst[1] << " m with turn_bank 30 deg");
  CHECK(worst[1] < 0.5 * worst[0]);
}

TEST_CASE("manager: straight lines switch at the bisector half-plane (corner = line)") {
  ManagerConfig cfg;
  cfg.corner = ManagerConfig::Corner::line;
  Flight f(cfg);
  const auto wps = points({{300, 0, -70}, {300, 300, -70}, {0, 300, -70}, {0, 0, -70}});
  f.manager.set_waypoints(wps, true);
  int switches = 0;
  // run(0.01) updates the manager with the position at its start: `at` switched, `before` not.
  Vec3 before = f.aircraft.p(), at = f.aircraft.p();
  for (int k = 0; k < 30000 && switches < 6; ++k) {
    const int target = f.manager.target();
    before = at;
    at = f.aircraft.p();
    f.run(0.01);
    if (f.manager.target() != target && target >= 0) {
      // Switched this step: the aircraft crossed the bisector through the waypoint it was flying to.
      const int i = target, prev = (i + 3) % 4, next = (i + 1) % 4;
      const Vec3 q_in = (wps[i].w - wps[prev].w).normalized(), q_out = (wps[next].w - wps[i].w).normalized();
      const Vec3 n = (q_in + q_out).normalized();
      if (switches > 0) {  // the first leg starts at the aircraft, not at wps[prev]
        CHECK((at - wps[i].w).head<2>().dot(n.head<2>()) >= 0.0);
        CHECK((before - wps[i].w).head<2>().dot(n.head<2>()) < 0.0);
      }
      ++switches;
    }
  }
  CHECK(switches == 6);
  CHECK(f.finite);
}

TEST_CASE("manager: repeated waypoints are skipped with one warning each") {
  Flight f;
  f.manager.set_waypoints(points({{0, 400, -70}, {0, 400, -70}, {400, 400, -70}, {400, 0, -70}, {400, 0.5, -70}, {0, 400.2, -70}}), true);
  f.run(600.0);
  CHECK(f.finite);
  CHECK(f.count_warnings("repeats") == 3);
  CHECK(f.warnings.size() == 3);  // once per list, not once per lap
  CHECK(f.manager.active_count() == 3);
  REQUIRE(f.manager.passed().size() >= 6);
  for (int i : f.manager.passed()) CHECK((i == 0 || i == 2 || i == 3));
}

TEST_CASE("manager: a two-waypoint loop doubles back 180 degrees: fly over, turn around, no NaN") {
  Flight f;
  f.manager.set_waypoints(points({{0, 0, -70}, {500, 0, -70}}), true);
  f.run(600.0);
  CHECK(f.finite);
  CHECK(f.count_warnings("two-waypoint mission") == 1);
  CHECK(f.count_warnings("corner needs") == 2);  // the turn-around at each end
  CHECK(f.warnings.size() == 3);
  REQUIRE(f.manager.passed().size() >= 6);
  CHECK(in_cycle_order(f.manager.passed(), 2));

  ManagerConfig cfg;
  cfg.corner = ManagerConfig::Corner::line;
  Flight g(cfg);
  g.manager.set_waypoints(points({{0, 0, -70}, {500, 0, -70}}), true);
  g.run(600.0);
  CHECK(g.finite);
  CHECK(g.count_warnings("doubles back") == 2);
  REQUIRE(g.manager.passed().size() >= 6);
  CHECK(in_cycle_order(g.manager.passed(), 2));
}

TEST_CASE("manager: a list re-sent every 2 s warns once a minute; a new case warns at once") {
  Flight f;
  // coord_rendezvous re-sends a two-waypoint list of one shape every few seconds, flown at once
  for (int k = 0; k < 20; ++k) {  // 40 s
    f.manager.set_waypoints(points({{0, 0, -70}, {500.0 + 10.0 * k, 0, -70}}), true, true);
    f.run(2.0);
  }
  CHECK(f.finite);
  CHECK(f.count_warnings("two-waypoint mission") == 1);
  const std::size_t seen = f.warnings.size();
  // a list with a case not seen yet warns at once
  f.manager.set_waypoints(points({{0, 0, -70}, {0, 0, -70}, {300, 0, -70}, {0, 60, -70}}), true, true);
  f.run(30.0);
  CHECK(f.count_warnings("repeats") == 1);
  CHECK(f.warnings.size() > seen);
  // a minute after its last warning, the two-waypoint case warns again
  f.manager.set_waypoints(points({{0, 0, -70}, {700, 0, -70}}), true, true);
  f.run(2.0);
  CHECK(f.count_warnings("two-waypoint mission") == 2);
}

TEST_CASE("manager: a corner too sharp for the fillet radius is flown over") {
  Flight f;
  // 300 m north, then back to 60 m east of the start: a 169-degree corner at (300, 0).
  f.manager.set_waypoints(points({{0, 0, -70}, {300, 0, -70}, {0, 60, -70}}), true);
  f.run(500.0);
  CHECK(f.finite);
  CHECK(f.count_warnings("waypoint 1: the 169 deg corner needs") == 1);
  REQUIRE(f.manager.passed().size() >= 6);
  CHECK(in_cycle_order(f.manager.passed(), 3));
}

TEST_CASE("manager: one waypoint -> orbit it; two without loop -> fly both, orbit the last") {
  Flight one;
  one.manager.set_waypoints(points({{300, 300, -80}}), true);
  one.run(200.0);
  CHECK(one.finite);
  CHECK(one.count_warnings("one-waypoint mission") == 1);
  CHECK(one.seg.type == PathSegment::Type::orbit);
  CHECK(one.seg.c == Vec3(300, 300, -80));
  CHECK(std::fabs((one.aircraft.p() - one.seg.c).head<2>().norm() - 50.0) < 3.0);
  CHECK(one.aircraft.h == Approx(80.0).epsilon(0.02));

  Flight two;
  two.manager.set_waypoints(points({{300, 0, -70}, {300, 400, -70}}), false);
  two.run(200.0);
  CHECK(two.finite);
  CHECK(two.count_warnings("two-waypoint mission") == 1);
  CHECK(two.manager.passed() == std::vector<int>{0, 1});
  CHECK(two.manager.mode() == PathManager::Mode::waypoint_orbit);
  CHECK(two.seg.c == Vec3(300, 400, -70));

  ManagerConfig cfg;
  cfg.orbit_last = true;  // ROSplane's orbit_last overrides a looping list
  Flight last(cfg);
  last.manager.set_waypoints(hourglass(), true);
  last.run(400.0);
  CHECK(last.manager.passed() == std::vector<int>{0, 1, 2, 3});
  CHECK(last.seg.type == PathSegment::Type::orbit);
  CHECK(last.seg.c == Vec3(400, -50, -70));
}

TEST_CASE("manager: Dubins paths (use_chi) are flown; waypoints closer than 2R get the shortest possible type") {
  Flight f;
  f.manager.set_waypoints(hourglass(true), true);
  f.run(500.0);
  CHECK(f.finite);
  CHECK(f.warnings.empty());
  REQUIRE(f.manager.passed().size() >= 6);
  CHECK(in_cycle_order(f.manager.passed(), 4));
  CHECK(f.worst_line_error < 10.0);

  Flight close;
  close.manager.set_waypoints(points({{0, 0, -70}, {0, 60, -70}, {300, 30, -70}}, true, kPi / 2), true);
  close.run(600.0);
  CHECK(close.finite);
  CHECK(close.count_warnings("closer than 2 R_min") >= 1);
  CHECK(close.warnings.size() <= 3);
  REQUIRE(close.manager.passed().size() >= 6);
  CHECK(in_cycle_order(close.manager.passed(), 3));
}

TEST_CASE("manager: non-finite input is refused without NaN output") {
  Flight f;
  auto wps = hourglass();
  wps[2].w.x() = NAN;
  wps[1].use_chi = true;
  wps[1].chi_d = INFINITY;
  wps[3].Va_d = -1;
  f.manager.set_waypoints(wps, true);
  f.run(300.0);
  CHECK(f.finite);
  CHECK(f.count_warnings("waypoint 2 has a non-finite position") == 1);
  CHECK(f.count_warnings("waypoint 1 has a non-finite chi_d") == 1);
  const PathSegment s = f.manager.update(Vec3(NAN, 0, 0), 0.0, 0.0);
  CHECK(s.r.allFinite());
  CHECK(f.count_warnings("not finite") == 1);
  CHECK(f.manager.active_count() == 3);
}

TEST_CASE("manager: edits take effect at the next waypoint decision; extensions at once") {
  Flight f;
  f.manager.set_waypoints(hourglass(), true);
  while (f.manager.target() != 1) f.run(0.1);
  // A different list (the mission restarted at the old waypoint 3): waypoint 1 is still flown.
  auto rotated = hourglass();
  std::rotate(rotated.begin(), rotated.begin() + 3, rotated.end());
  f.manager.set_waypoints(rotated, true);
  f.run(0.1);
  CHECK(f.manager.target() == 1);
  const std::size_t passed_before = f.manager.passed().size();
  while (f.manager.passed().size() == passed_before) f.run(0.1);
  // Decision at the old waypoint 1: the new list starts, its waypoint 0 is the old waypoint 3.
  CHECK(f.manager.target() == 0);
  CHECK(f.seg.type == PathSegment::Type::line);
  CHECK(f.seg.q.x() > 0.99);  // heading north from (-400, -50) to (400, -50)
  // An extension keeps the current segment and target.
  auto longer = rotated;
  longer.push_back({Vec3(0, 300, -70), 0.0, false, 17.0, ItemType::waypoint, {}});
  f.manager.set_waypoints(longer, true);
  f.run(0.1);
  CHECK(f.manager.target() == 0);
  f.run(600.0);
  CHECK(f.finite);
  CHECK(f.manager.passed().back() >= 0);
  bool flew_new = false;
  for (int i : f.manager.passed()) flew_new = flew_new || i == 4;
  CHECK(flew_new);
  // The same list again changes nothing.
  const int target_now = f.manager.target();
  f.manager.set_waypoints(longer, true);
  f.run(0.01);
  CHECK(f.manager.target() == target_now);
  // An empty list: orbit the origin at once.
  f.manager.set_waypoints({}, true);
  CHECK(f.manager.update(f.aircraft.p(), f.aircraft.chi, f.t).c == Vec3(0, 0, -50));
}

// ---- the plugins through the SDK harness -------------------------------------------------------

namespace {
msg::State state_of(const testkit::KinematicAircraft& a, bool origin = true) {
  msg::State s;
  s.p_n = a.n;
  s.p_e = a.e;
  s.p_d = -a.h;
  s.chi = a.chi;
  s.psi = a.psi;
  s.Va = a.Va;
  s.Vg = a.Vg();
  s.valid = true;
  s.origin_valid = origin;
  s.origin_lat = 40.2455;
  s.origin_lon = -111.6480;
  s.origin_alt = 1450.0;
  return s;
}

tern::testing::HarnessOptions options(const std::string& name, YAML::Node mission = {}) {
  tern::testing::HarnessOptions o;
  o.instance = name;
  o.config_dir = kData;
  o.mission = mission;
  return o;
}
}  // namespace

namespace {
MissionPoint loiter_at(const Vec3& c, double radius, int direction, double time, double turns) {
  MissionPoint p{c, 0.0, false, 17.0, ItemType::loiter, {}};
  p.loiter = {radius, direction, time, turns};
  return p;
}

// The flight time at which the manager's target first became `index` (-1: never).
double time_target_became(Flight& f, int index, double seconds) {
  const double dt = 0.05;
  for (double t = 0.0; t < seconds; t += dt) {
    f.run(dt);
    if (f.manager.target() == index) return f.t;
  }
  return -1.0;
}
}  // namespace

TEST_CASE("manager: a loiter item is orbited (its radius and direction) for its turns, then the mission goes on") {
  Flight f;
  std::vector<MissionPoint> list = points({{300, 0, -70}});
  list.push_back(loiter_at({300, 400, -70}, 80.0, -1, 0.0, 2.0));
  list.push_back({{0, 400, -70}, 0.0, false, 17.0, ItemType::waypoint, {}});
  f.manager.set_waypoints(list, false);
  REQUIRE(time_target_became(f, 1, 200.0) > 0.0);
  CHECK(f.manager.stage() == PathManager::Stage::loiter);
  f.run(1.0);
  CHECK(f.seg.type == PathSegment::Type::orbit);
  CHECK(f.seg.c == Vec3(300, 400, -70));
  CHECK(f.seg.rho == 80.0);
  CHECK(f.seg.lambda == -1);
  f.settle_s = f.t + 60.0;  // onto the orbit
  f.worst_orbit_error = 0.0;
  double turns_at_exit = 0.0;
  for (int k = 0; k < 4000 && f.manager.target() == 1; ++k) {
    turns_at_exit = f.manager.loiter_turns_flown();
    f.run(0.05);
  }
  CHECK(f.manager.target() == 2);
  CHECK(turns_at_exit == Approx(2.0).epsilon(0.02));
  CHECK(f.worst_orbit_error < 5.0);
  CHECK(f.finite);
  CHECK(f.warnings.empty());
}

TEST_CASE("manager: a loiter with a time leaves after that long on the orbit; a bare loiter stays") {
  Flight f;
  f.manager.set_waypoints(
      {loiter_at({0, 200, -70}, 0.0, 1, 40.0, 0.0), MissionPoint{{-300, 200, -70}, 0.0, false, 17.0, ItemType::waypoint, {}}}, false);
  f.run(0.01);
  REQUIRE(f.manager.target() == 0);
  CHECK(f.seg.rho == 50.0);  // radius 0: R_min
  double on_orbit_at = -1.0;
  for (int k = 0; k < 6000 && f.manager.target() == 0; ++k) {
    f.run(0.05);
    if (on_orbit_at < 0.0 && f.manager.on_loiter_orbit()) on_orbit_at = f.t;
  }
  REQUIRE(on_orbit_at > 0.0);
  CHECK(f.manager.target() == 1);
  CHECK(f.t - on_orbit_at == Approx(40.0).epsilon(0.01));
  Flight stay;
  stay.manager.set_waypoints(
      {loiter_at({0, 200, -70}, 60.0, 1, 0.0, 0.0), MissionPoint{{-300, 200, -70}, 0.0, false, 17.0, ItemType::waypoint, {}}}, false);
  stay.run(600.0);
  CHECK(stay.manager.target() == 0);
  CHECK(stay.manager.loiter_turns_flown() > 5.0);
}

TEST_CASE("manager: a loiter to an altitude climbs on the orbit and goes on once within altitude_band of it") {
  Flight f;
  MissionPoint climb = loiter_at({300, 0, -150}, 100.0, -1, 0.0, 0.0);
  climb.loiter.to_altitude = true;
  f.manager.set_waypoints({climb, MissionPoint{{-300, 0, -150}, 0.0, false, 17.0, ItemType::waypoint, {}}}, false);
  f.run(0.01);
  REQUIRE(f.manager.target() == 0);
  double left_at_h = -1.0;
  for (int k = 0; k < 20000 && f.manager.target() == 0; ++k) {
    f.run(0.05);
    left_at_h = f.aircraft.h;
  }
  CHECK(f.manager.target() == 1);
  CHECK(left_at_h >= 150.0 - ManagerConfig{}.altitude_band);  // from 70 m: it climbed before it left
  CHECK(f.finite);
}

TEST_CASE("manager: Vg_min raises the airspeed into the wind (wind triangle), never below Va_d or on a land item") {
  Flight f;
  f.manager.set_wind(Vec3(-8.0, 0.0, 0.0));  // 8 m/s from the north
  MissionPoint north{{600, 0, -70}, 0.0, false, 15.0, ItemType::waypoint, {}};
  north.Vg_min = 12.0;
  MissionPoint south{{-600, 0, -70}, 0.0, false, 15.0, ItemType::waypoint, {}};
  south.Vg_min = 12.0;
  f.manager.set_waypoints({north, south}, false);
  f.run(0.01);
  REQUIRE(f.seg.type == PathSegment::Type::line);
  CHECK(f.seg.Va_d == Approx(20.0));  // |12 north - (-8 north)|: 20 m/s of air for 12 over the ground
  f.run(120.0);
  REQUIRE(f.manager.target() == 1);
  if (f.seg.type == PathSegment::Type::line) CHECK(f.seg.Va_d == Approx(15.0));  // downwind: Va_d already gives 23 m/s
  MissionPoint loiter = loiter_at({0, 0, -70}, 100.0, 1, 0.0, 0.0);
  loiter.Vg_min = 12.0;
  f.manager.set_waypoints({loiter}, false, true);
  f.run(0.01);
  CHECK(f.seg.Va_d == Approx(20.0));  // an orbit meets the headwind: Vg_min + |wind|
  MissionPoint land{{0, 0, 0}, 0.0, false, 15.0, ItemType::land, {}};
  land.Vg_min = 12.0;
  CHECK(f.manager.airspeed(land) == 15.0);
}

TEST_CASE("manager: an immediate return_home replaces the route at once and orbits home at its altitude for good") {
  Flight f;
  f.manager.set_waypoints(hourglass(), true);
  f.run(30.0);
  REQUIRE(f.manager.mode() == PathManager::Mode::route);
  MissionPoint home{{500, -500, -90}, 0.0, false, 17.0, ItemType::return_home, {}};  // return_home: n and e are ignored
  home.loiter.radius = 70.0;
  f.manager.set_waypoints({home}, false, true);
  f.run(0.01);
  CHECK(f.seg.type == PathSegment::Type::orbit);
  CHECK(f.seg.c == Vec3(0, 0, -90));
  CHECK(f.seg.rho == 70.0);
  f.settle_s = f.t + 90.0;
  f.worst_orbit_error = 0.0;
  f.run(400.0);
  CHECK(f.manager.target() == 0);
  CHECK(f.manager.loiter_turns_flown() > 3.0);
  CHECK(f.worst_orbit_error < 5.0);
  CHECK(f.count_warnings("one-waypoint") == 0);
}

TEST_CASE("plugins: defaults are ROSplane's Anaconda values") {
  tern::testing::Harness m(std::make_unique<ManagerPlugin>(), {}, options("manager"));
  CHECK(std::get<double>(m.plugin().find_param("R_min")->value()) == 50.0);
  CHECK(std::get<bool>(m.plugin().find_param("orbit_last")->value()) == false);
  CHECK(std::get<double>(m.plugin().find_param("default_altitude")->value()) == 50.0);
  CHECK(std::get<double>(m.plugin().find_param("default_airspeed")->value()) == 15.0);
  tern::testing::Harness f(std::make_unique<FollowerPlugin>(), {}, options("follower"));
  CHECK(std::get<double>(f.plugin().find_param("chi_infty")->value()) == 1.2);
  CHECK(std::get<double>(f.plugin().find_param("k_path")->value()) == 0.0175);
  CHECK(std::get<double>(f.plugin().find_param("k_orbit")->value()) == 0.5);
  CHECK_THROWS_AS(tern::testing::Harness(std::make_unique<ManagerPlugin>(), {{"R_min", 0.0}}, options("manager")), ParamError);
  CHECK_THROWS_AS(tern::testing::Harness(std::make_unique<ManagerPlugin>(), {{"corner", std::string("round")}}, options("manager")),
                  ParamError);
}

TEST_CASE("plugins: a bad mission section fails configure with one clear line") {
  CHECK_THROWS_WITH_AS(tern::testing::Harness(std::make_unique<PlannerPlugin>(), {}, options("planner", YAML::Load("waypoints: [[1, 2]]"))),
                       "mission config (mission:):1: waypoints[0]: expected a list of 3 numbers", MissionError);
}

TEST_CASE("plugins: a mission longer than a WaypointList holds is refused at configure") {
  std::string yaml = "waypoints:\n";
  for (int i = 0; i < 65; ++i) yaml += "  - [" + std::to_string(10 * i) + ", 0, -50]\n";
  CHECK_THROWS_WITH_AS(tern::testing::Harness(std::make_unique<PlannerPlugin>(), {}, options("planner", YAML::Load(yaml))),
                       "mission config (mission:): 65 waypoints, more than the 64 a WaypointList holds", MissionError);
}

TEST_CASE("plugins: LLA waypoints wait for the origin, then publish the GeographicLib NED") {
  tern::testing::Harness p(std::make_unique<PlannerPlugin>(), {},
                           options("planner", YAML::Load("waypoints:\n  - [100, 0, -60]\n  - {lla: [40.2466, -111.6470, 1480.5]}")));
  testkit::KinematicAircraft a;
  p.set_input("state", state_of(a, false));
  p.step(0);
  p.step(10'000'000);
  CHECK(p.published("waypoints") == 0);
  p.set_input("state", state_of(a, true));
  p.step(20'000'000);
  REQUIRE(p.published("waypoints") == 1);
  const auto& list = p.output<msg::WaypointList>("waypoints");
  CHECK(list.count == 2);
  CHECK(list.items[0].w == Vec3(100, 0, -60));
  const Vec3 expect = lla_to_ned(Vec3(40.2466, -111.6470, 1480.5), GeoPoint{40.2455, -111.6480, 1450.0});
  CHECK(list.items[1].w == expect);
  CHECK_FALSE(list.items[1].lla);
  p.step(30'000'000);
  CHECK(p.published("waypoints") == 1);  // published on change only
}

TEST_CASE("plugins: planner edits (add, publish_now, set_current, clear, load_file)") {
  tern::testing::Harness p(std::make_unique<PlannerPlugin>(), {{"mission_file", std::string("fixedwing_mission.yaml")}},
                           options("planner"));
  Nanos t = 0;
  p.step(t += 10'000'000);
  REQUIRE(p.published("waypoints") == 1);
  CHECK(p.output<msg::WaypointList>("waypoints").count == 4);
  msg::MissionEdit e;
  e.id = 1;
  e.op = msg::MissionEdit::add;
  e.waypoint.w = Vec3(0, 0, -80);
  e.waypoint.Va_d = 16;
  e.publish_now = false;
  p.set_input("mission_edit", e);
  p.step(t += 10'000'000);
  CHECK(p.published("waypoints") == 1);  // held
  e.id = 2;
  e.publish_now = true;
  p.set_input("mission_edit", e);
  p.step(t += 10'000'000);
  CHECK(p.published("waypoints") == 2);
  CHECK(p.output<msg::WaypointList>("waypoints").count == 6);
  CHECK(p.output<msg::WaypointList>("waypoints").revision == 2);
  e = {};
  e.id = 3;
  e.op = msg::MissionEdit::set_current;
  e.index = 2;
  p.set_input("mission_edit", e);
  p.step(t += 10'000'000);
  CHECK(p.output<msg::WaypointList>("waypoints").items[0].w == Vec3(-400, -250, -70));
  CHECK(p.output<msg::WaypointList>("waypoints").count == 6);
  e.id = 4;
  e.index = 99;  // refused, logged
  p.set_input("mission_edit", e);
  p.step(t += 10'000'000);
  CHECK(p.published("waypoints") == 3);
  e = {};
  e.id = 5;
  e.op = msg::MissionEdit::clear;
  p.set_input("mission_edit", e);
  p.step(t += 10'000'000);
  CHECK(p.output<msg::WaypointList>("waypoints").count == 0);
  e = {};
  e.id = 6;
  e.op = msg::MissionEdit::load_file;
  const std::string file = (kData / "fixedwing_mission.yaml").string();
  std::memcpy(e.file.data(), file.c_str(), file.size() + 1);
  p.set_input("mission_edit", e);
  p.step(t += 10'000'000);
  CHECK(p.output<msg::WaypointList>("waypoints").count == 4);
  e.id = 7;
  std::strcpy(e.file.data(), "/nonexistent/mission.yaml");  // refused, mission unchanged
  p.set_input("mission_edit", e);
  p.step(t += 10'000'000);
  CHECK(p.output<msg::WaypointList>("waypoints").count == 4);
  CHECK(p.published("waypoints") == 5);
}

TEST_CASE("plugins: planner -> manager -> follower fly the ROSplane hourglass; a set_current edit waits for the next decision") {
  tern::testing::Harness planner(std::make_unique<PlannerPlugin>(), {}, options("planner", YAML::Load("file: fixedwing_mission.yaml")));
  tern::testing::Harness manager(std::make_unique<ManagerPlugin>(), {}, options("manager"));
  tern::testing::Harness follower(std::make_unique<FollowerPlugin>(), {}, options("follower"));
  testkit::KinematicAircraft a;
  a.h = 70;
  std::uint64_t seen = 0;
  std::vector<int> order;  // successive waypoint indices of current_path
  bool finite = true, edited = false;
  double worst = 0.0;
  int index_after_edit = -2;
  Vec3 q_after_edit = Vec3::Zero();
  const Nanos dt = 10'000'000;  // 100 Hz; follower at 10 Hz
  for (int k = 0; k < 60000; ++k) {
    const Nanos t = k * dt;
    const msg::State s = state_of(a);
    planner.set_input("state", s);
    planner.step(t);
    if (planner.published("waypoints") != seen) {
      seen = planner.published("waypoints");
      manager.set_input("waypoints", planner.output<msg::WaypointList>("waypoints"));
    }
    manager.set_input("state", s);
    manager.step(t);
    const auto& path = manager.output<msg::CurrentPath>("current_path");
    if (order.empty() || order.back() != path.waypoint_index) order.push_back(path.waypoint_index);
    if (k % 10 == 0) {
      follower.set_input("state", s);
      follower.set_input("current_path", path);
      follower.step(t);
    }
    const auto& c = follower.output<msg::ControllerCommand>("controller_command");
    finite = finite && std::isfinite(c.chi_c) && std::isfinite(c.h_c) && std::isfinite(c.phi_ff);
    a.step(c.chi_c, c.phi_ff, c.h_c, c.Va_c, 0.01);
    // (After the edit the new first leg starts with a 90-degree turn: not counted.)
    if (path.path_type == msg::CurrentPath::line && order.size() > 2 && !edited)
      worst = std::max(worst, std::fabs(cross_track_error(path.r, path.q, a.p())));
    // Second lap, flying to waypoint 1: make waypoint 3 the next one.
    if (!edited && order.size() == 6 && path.waypoint_index == 1) {
      msg::MissionEdit e;
      e.id = 1;
      e.op = msg::MissionEdit::set_current;
      e.index = 3;
      planner.set_input("mission_edit", e);
      edited = true;
      order.push_back(-100);  // marker
    }
    if (edited && index_after_edit == -2 && order.back() != 1 && order.back() != -100) {
      index_after_edit = path.waypoint_index;
      q_after_edit = path.q;
    }
  }
  CHECK(finite);
  CHECK(follower.published("controller_command") > 0);
  const std::vector<int> first_lap(order.begin(), order.begin() + 6);
  CHECK(first_lap == std::vector<int>{0, 1, 2, 3, 0, 1});
  REQUIRE(edited);
  // After the edit the aircraft still went to waypoint 1, then to the renumbered list's
  // waypoint 0, which is the old waypoint 3 at (400, -50): due north of waypoint 1.
  CHECK(order[7] == 1);
  CHECK(index_after_edit == 0);
  CHECK(q_after_edit.x() > 0.99);
  CHECK(worst < 10.0);
  const auto summary = manager.plugin().summary();
  REQUIRE(summary.size() == 6);
  CHECK(summary[3].first == "land_approaches");
  CHECK(summary[3].second == 0.0);  // the hourglass has no land item
  CHECK(summary[0].first == "waypoints_passed");
  CHECK(summary[0].second >= 8);
  CHECK(summary[1].first == "line_cross_track_rms_m");
  CHECK(summary[1].second > 0.0);
  CHECK(summary[1].second <= summary[2].second);
  CHECK(summary[2].second < 40.0);  // includes the turn onto the first leg after the edit
  CHECK(planner.output<msg::WaypointList>("waypoints").items[0].w == Vec3(400, -50, -70));
}
