// Land items in the path manager and follower (tern/path/landing.hpp, manager.hpp): the approach
// geometry by hand, and the kinematic aircraft (kinematic.hpp) flown onto the glide path, through
// a go-around and back, and to an abandoned landing after land_attempts approaches.
#include <doctest/doctest.h>

#include <cmath>

#include "kinematic.hpp"
#include "tern/math.hpp"
#include "tern/path/follower.hpp"
#include "tern/path/landing.hpp"
#include "tern/path/manager.hpp"

using namespace tern::path;
using doctest::Approx;

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;

MissionPoint land_item(const Vec3& td, double heading) {
  MissionPoint m;
  m.type = ItemType::land;
  m.w = td;
  m.chi_d = heading;
  m.Va_d = 15.0;
  return m;
}

MissionPoint waypoint(double n, double e, double h) {
  MissionPoint m;
  m.w = Vec3(n, e, -h);
  return m;
}

struct Flown {
  bool final_reached = false;
  double max_final_cross = 0.0, max_final_glide_err = 0.0;
  double h_at_touchdown = 1e9;
};

/// Flies the kinematic aircraft for `seconds` through manager and follower; records the final
/// approach's tracking until the aircraft passes the touchdown point.
Flown fly(PathManager& m, testkit::KinematicAircraft& ac, double seconds, double dt = 0.02) {
  Flown out;
  for (double t = 0.0; t < seconds; t += dt) {
    const PathSegment seg = m.update(ac.p(), ac.chi, t);
    const FollowerCommand c = follow(seg, {ac.p(), ac.chi, ac.psi, ac.Va, ac.Vg()}, FollowerGains{});
    if (seg.landing && m.approach()) {
      const Approach& a = *m.approach();
      const double along = along_runway(a, ac.p());
      if (along < 0.0 && along > -0.8 * a.length) {
        out.final_reached = true;
        const double cross = -std::sin(a.heading) * (ac.n - a.touchdown.x()) + std::cos(a.heading) * (ac.e - a.touchdown.y());
        out.max_final_cross = std::max(out.max_final_cross, std::fabs(cross));
        out.max_final_glide_err = std::max(out.max_final_glide_err, std::fabs(ac.h - glide_path_altitude(a, ac.p())));
      }
      if (along >= 0.0 && out.h_at_touchdown > 1e8) out.h_at_touchdown = ac.h;
      CHECK(c.landing);
      CHECK(c.h_td == Approx(-a.touchdown.z()));
      CHECK(c.h_c >= c.h_td - 1e-9);
    }
    ac.step(c.chi_c, c.phi_ff, c.h_c, c.Va_c, dt);
  }
  return out;
}

/// The kinematic aircraft at 60 m, 15 m/s, heading north at the origin.
testkit::KinematicAircraft start_at_60m() {
  testkit::KinematicAircraft ac;
  ac.h = 60.0;
  ac.Va = 15.0;
  ac.set_course(0.0);
  return ac;
}

/// Flies `ac` through manager and follower until the segment is a land item's final (or 400 s);
/// returns the last segment.
PathSegment fly_to_final(PathManager& m, testkit::KinematicAircraft& ac) {
  PathSegment seg;
  for (double t = 0.0; t < 400.0 && !seg.landing; t += 0.02) {
    seg = m.update(ac.p(), ac.chi, t);
    const FollowerCommand c = follow(seg, {ac.p(), ac.chi, ac.psi, ac.Va, ac.Vg()}, FollowerGains{});
    ac.step(c.chi_c, c.phi_ff, c.h_c, c.Va_c, 0.02);
  }
  return seg;
}
}  // namespace

TEST_CASE("landing: the approach's entry point, glide direction and glide-path altitude, hand-worked") {
  LandSpec spec;
  spec.glide_slope = std::atan(0.1);  // 1 in 10
  spec.decision_height = 10.0;
  const Approach a = plan_approach(Vec3(100, 0, 0), 0.0, spec, -60.0);  // runway heading north, entered at 60 m
  CHECK_FALSE(a.raised);
  CHECK(a.length == Approx(600.0));
  CHECK(a.entry.x() == Approx(-500.0));
  CHECK(a.entry.y() == Approx(0.0).scale(1.0));
  CHECK(a.entry.z() == Approx(-60.0));
  CHECK(a.q.x() == Approx(1.0 / std::sqrt(1.01)));
  CHECK(a.q.z() == Approx(0.1 / std::sqrt(1.01)));
  CHECK(glide_path_altitude(a, Vec3(-200, 30, -99)) == Approx(30.0));        // 300 m short: 30 m up
  CHECK(glide_path_altitude(a, Vec3(300, 0, 0)) == Approx(0.0).scale(1.0));  // beyond: the runway
  CHECK(glide_path_altitude(a, Vec3(-900, 0, 0)) == Approx(60.0));           // before the entry: its altitude
  CHECK(along_runway(a, Vec3(90, 5, 0)) == Approx(-10.0));
  // Entered too low: raised to kMinEntryHeights decision heights above the touchdown point.
  const Approach low = plan_approach(Vec3(0, 0, -2), kDeg * 90.0, spec, -10.0);
  CHECK(low.raised);
  CHECK(low.entry.z() == Approx(-2.0 - kMinEntryHeights * 10.0));
  CHECK(low.entry.y() == Approx(-200.0));  // heading east: the entry lies west
}

TEST_CASE("landing: the aim point moved for the wind, hand-worked") {
  LandSpec spec;
  spec.glide_slope = std::atan(0.1);
  spec.flare_height = 3.0;  // reached 30 m before the aim point
  // Ground speed along the runway (heading north): a 5 m/s headwind, a 5 m/s crosswind crabbed into.
  CHECK(runway_ground_speed(15.0, Vec3(-5, 0, 0), 0.0) == Approx(10.0));
  CHECK(runway_ground_speed(15.0, Vec3(0, 5, 0), 0.0) == Approx(std::sqrt(200.0)));
  CHECK(runway_ground_speed(15.0, Vec3(0, -20, 0), 0.0) == Approx(0.0).scale(1.0));  // crosswind above Va: no progress
  CHECK(runway_ground_speed(15.0, Vec3(0, 5, 0), kDeg * 90.0) == Approx(20.0));      // heading east: a tailwind
  // The flare takes 3 s: 45 m at 15 m/s, of which 30 m are the glide path's own: aimed 15 m short.
  CHECK(aim_offset(15.0, 3.0, spec) == Approx(15.0));
  CHECK(aim_offset(9.0, 3.0, spec) == Approx(-3.0));  // into 6 m/s of headwind: 3 m beyond
  CHECK(aim_offset(15.0, 0.0, spec) == Approx(0.0).scale(1.0));
  const Approach a = plan_approach(Vec3(100, 0, 0), 0.0, spec, -60.0, 15.0);
  CHECK(a.aim.x() == Approx(85.0));
  CHECK(a.aim_offset == Approx(15.0));
  CHECK(a.entry.x() == Approx(-515.0));  // the whole glide path moved back
  CHECK(glide_path_altitude(a, Vec3(85, 0, 0)) == Approx(0.0).scale(1.0));
  CHECK(glide_path_altitude(a, Vec3(55, 0, 0)) == Approx(3.0));  // the flare height, 45 m before the touchdown point
  CHECK(along_runway(a, Vec3(90, 0, 0)) == Approx(-10.0));       // still counted from the touchdown point
  // Limited to half the glide path's length (600 m) either way.
  CHECK(plan_approach(Vec3(100, 0, 0), 0.0, spec, -60.0, 1000.0).aim_offset == Approx(300.0));
  CHECK(plan_approach(Vec3(100, 0, 0), 0.0, spec, -60.0, -1000.0).aim_offset == Approx(-300.0));
}

TEST_CASE("landing: the path manager aims the glide path for the wind it was given; flare_time 0 aims at the touchdown point") {
  for (const double flare_time : {0.0, 3.0}) {
    CAPTURE(flare_time);
    ManagerConfig cfg;
    cfg.R_min = 60.0;
    cfg.flare_time = flare_time;
    PathManager m(cfg);
    m.set_wind(Vec3(-4, 0, 0));  // 4 m/s of headwind on a runway heading north
    m.set_waypoints({waypoint(300, 300, 60), land_item(Vec3(0, 0, 0), 0.0)}, true);
    testkit::KinematicAircraft ac = start_at_60m();
    const PathSegment seg = fly_to_final(m, ac);
    REQUIRE(seg.landing);
    const LandSpec spec;  // the item's defaults
    const double expected = flare_time > 0.0 ? 11.0 * 3.0 - spec.flare_height / std::tan(spec.glide_slope) : 0.0;
    CHECK(m.approach()->aim_offset == Approx(expected));
    CHECK(seg.r.x() == Approx(-expected));  // the line the follower flies meets the runway there
  }
  ManagerConfig bad;
  bad.flare_time = -1.0;
  CHECK_THROWS_WITH(PathManager{bad}, doctest::Contains("flare_time"));
}

TEST_CASE("landing: the kinematic aircraft flies a Dubins path onto the runway heading and down the glide path") {
  for (const double heading : {0.0, 100.0 * kDeg, -150.0 * kDeg}) {
    CAPTURE(heading);
    ManagerConfig cfg;
    cfg.R_min = 60.0;
    PathManager m(cfg);
    m.set_home_altitude(0.5);  // the estimate put the parked aircraft 0.5 m up
    m.set_waypoints({waypoint(300, 300, 60), land_item(Vec3(0, 0, 0), heading)}, true);
    testkit::KinematicAircraft ac;
    ac.h = 60.0;
    ac.Va = 15.0;
    ac.tau_h = 1.0;  // a glide path's 1.3 m/s of sink: 1.3 m of lag
    ac.set_course(0.0);
    const Flown f = fly(m, ac, 400.0);
    CHECK(f.final_reached);
    CHECK(m.approaches() == 1);
    CHECK(m.stage() == PathManager::Stage::land_final);
    CHECK(f.max_final_cross < 3.0);
    CHECK(f.max_final_glide_err < 2.0);
    CHECK(std::fabs(f.h_at_touchdown - 0.5) < 2.0);  // over the touchdown point: near home's altitude (the lag above it)
    REQUIRE(m.approach());
    CHECK(m.approach()->touchdown.z() == Approx(-0.5));
  }
}

TEST_CASE("landing: the runway a range finder measures moves the glide path's touchdown point; home's altitude before it") {
  ManagerConfig cfg;
  cfg.R_min = 60.0;
  PathManager m(cfg);
  m.set_home_altitude(0.5);
  m.set_waypoints({waypoint(300, 300, 60), land_item(Vec3(0, 0, 0), 0.0)}, true);
  testkit::KinematicAircraft ac = start_at_60m();
  PathSegment seg = fly_to_final(m, ac);
  REQUIRE(seg.landing);
  CHECK(seg.r.z() == Approx(-0.5));  // home's
  m.set_runway_down(-3.2);           // the estimate's altitude 2.7 m off: the runway at 3.2 m
  seg = m.update(ac.p(), ac.chi, 400.0);
  CHECK(seg.r.z() == Approx(-3.2));
  CHECK(seg.q.isApprox(m.approach()->q));  // the same slope, moved
  m.set_runway_down(std::nan(""));         // ignored
  CHECK(m.update(ac.p(), ac.chi, 400.02).r.z() == Approx(-3.2));
}

TEST_CASE("landing: a go-around climbs out along the runway, comes round, and after land_attempts the landing is abandoned") {
  ManagerConfig cfg;
  cfg.R_min = 50.0;
  cfg.land_attempts = 2;
  PathManager m(cfg);
  m.set_waypoints({waypoint(-400, 0, 50), land_item(Vec3(0, 0, 0), 0.0)}, false);
  testkit::KinematicAircraft ac;
  ac.h = 50.0;
  ac.Va = 15.0;
  ac.set_course(kDeg * 180.0);
  ac.n = -300.0;
  double t = 0.0;
  auto run_until = [&](auto done, double limit) {
    for (; t < limit && !done(); t += 0.02) {
      const PathSegment seg = m.update(ac.p(), ac.chi, t);
      const FollowerCommand c = follow(seg, {ac.p(), ac.chi, ac.psi, ac.Va, ac.Vg()}, FollowerGains{});
      ac.step(c.chi_c, c.phi_ff, c.h_c, c.Va_c, 0.02);
    }
    return done();
  };
  const auto low_on_final = [&] { return m.stage() == PathManager::Stage::land_final && ac.h < 8.0; };
  REQUIRE(run_until(low_on_final, 600.0));
  CHECK(m.approaches() == 1);
  m.go_around(ac.p());
  CHECK(m.stage() == PathManager::Stage::go_around);
  const PathSegment climb_out = m.update(ac.p(), ac.chi, t);
  CHECK_FALSE(climb_out.landing);
  CHECK(climb_out.type == PathSegment::Type::line);
  CHECK(climb_out.q.x() == Approx(1.0));    // along the runway heading
  CHECK(climb_out.r.z() == Approx(-50.0));  // at the approach altitude
  REQUIRE(run_until(low_on_final, t + 600.0));
  CHECK(m.approaches() == 2);
  CHECK(ac.n < 0.0);  // back before the touchdown point, on the glide path again
  m.go_around(ac.p());
  CHECK(m.landing_abandoned());
  const PathSegment orbit = m.update(ac.p(), ac.chi, t);
  CHECK(orbit.type == PathSegment::Type::orbit);
  CHECK_FALSE(orbit.landing);
  CHECK(orbit.c.x() == Approx(0.0).scale(1.0));
  CHECK(orbit.c.z() == Approx(-50.0));  // above the touchdown point at the approach altitude
  // a new mission starts afresh
  m.set_waypoints({waypoint(-400, 0, 50), land_item(Vec3(0, 0, 0), 0.0)}, true, true);
  m.update(ac.p(), ac.chi, t);
  CHECK(m.approaches() == 0);
  CHECK_FALSE(m.landing_abandoned());
}

TEST_CASE("landing: loops > 0 flies the route that many times, then the land item; loop without loops never lands") {
  for (const int loops : {0, 1, 2}) {
    CAPTURE(loops);
    ManagerConfig cfg;
    cfg.R_min = 40.0;
    PathManager m(cfg);
    m.set_waypoints({waypoint(300, 0, 50), waypoint(300, 300, 50), waypoint(0, 300, 50), land_item(Vec3(0, 0, 0), -kDeg * 90.0)}, true,
                    false, loops);
    testkit::KinematicAircraft ac;
    ac.h = 50.0;
    ac.Va = 15.0;
    const Flown f = fly(m, ac, 1500.0);
    CHECK(f.final_reached == (loops > 0));
    CHECK(m.loops_done() == (loops > 0 ? loops - 1 : m.loops_done()));
    if (loops == 0) CHECK(m.loops_done() >= 3);  // still looping after 1500 s
  }
}
