// Geometry and vector-field tests against hand-worked numbers (Beard & McLain ch. 10-11).
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "kinematic.hpp"
#include "tern/path/follower.hpp"
#include "tern/path/geometry.hpp"
#include "tern/math.hpp"

using namespace tern::path;
using doctest::Approx;

namespace {
using tern::kPi;

void check_vec(const Vec3& a, const Vec3& b, double eps = 1e-9) {
  CHECK(a.x() == Approx(b.x()).epsilon(eps).scale(1.0));
  CHECK(a.y() == Approx(b.y()).epsilon(eps).scale(1.0));
  CHECK(a.z() == Approx(b.z()).epsilon(eps).scale(1.0));
}

/// Direction of travel at x on the circle (c, lambda): clockwise is increasing atan2(e, n).
Vec3 circle_direction(const Vec3& x, const Vec3& c, int lambda) {
  Vec3 r = x - c;
  r.z() = 0;
  return lambda * Vec3(-r.y(), r.x(), 0.0).normalized();
}
}  // namespace

TEST_CASE("line switching: half-plane at the bisector of the corner (Alg. 5)") {
  const Vec3 q_in(1, 0, 0), q_out(0, 1, 0);
  const Vec3 n = line_switch_normal(q_in, q_out);
  check_vec(n, Vec3(std::sqrt(0.5), std::sqrt(0.5), 0));
  const Vec3 w(100, 0, -50);
  CHECK(in_half_plane(Vec3(90, 10, -50), w, n));  // on the boundary: switches
  CHECK_FALSE(in_half_plane(Vec3(90, 9.9, -50), w, n));
  CHECK(in_half_plane(Vec3(100, 0, 0), w, n));  // altitude does not matter
  // Doubling back: the normal is the incoming direction (switch when passing w).
  check_vec(line_switch_normal(q_in, -q_in), q_in);
}

TEST_CASE("fillet: entry, exit, centre and direction (Alg. 6), hand-worked") {
  // Right turn of 90 degrees at (100, 0), R = 20: varrho = pi/2, offset R / tan(pi/4) = 20.
  const Fillet f = compute_fillet(Vec3(0, 0, -50), Vec3(100, 0, -50), Vec3(100, 100, -50), 20.0);
  REQUIRE(f.kind == Fillet::Kind::fillet);
  CHECK(f.varrho == Approx(kPi / 2));
  CHECK(f.offset == Approx(20.0));
  check_vec(f.z1, Vec3(80, 0, -50));
  check_vec(f.z2, Vec3(100, 20, -50));
  check_vec(f.c, Vec3(80, 20, -50));
  CHECK(f.lambda == 1);
  // The same corner turning left: mirrored centre, counter-clockwise.
  const Fillet g = compute_fillet(Vec3(0, 0, 0), Vec3(100, 0, 0), Vec3(100, -100, 0), 20.0);
  REQUIRE(g.kind == Fillet::Kind::fillet);
  check_vec(g.c, Vec3(80, -20, 0));
  CHECK(g.lambda == -1);
  // A 120-degree turn: varrho = 60 deg, offset = R / tan(30 deg) = 34.641, centre at
  // R / sin(30 deg) = 40 m from w along the inner bisector.
  const Vec3 w(0, 0, 0);
  const Fillet h = compute_fillet(Vec3(-200, 0, 0), w, Vec3(200 * std::cos(2 * kPi / 3), 200 * std::sin(2 * kPi / 3), 0), 20.0);
  REQUIRE(h.kind == Fillet::Kind::fillet);
  CHECK(h.offset == Approx(20.0 / std::tan(kPi / 6)));
  CHECK((h.c - w).norm() == Approx(40.0));
  CHECK((h.z1 - h.c).norm() == Approx(20.0));
  CHECK((h.z2 - h.c).norm() == Approx(20.0));
  check_vec(circle_direction(h.z1, h.c, h.lambda), h.q_in, 1e-9);
  check_vec(circle_direction(h.z2, h.c, h.lambda), h.q_out, 1e-9);
}

TEST_CASE("fillet: degenerate corners fall back to line switching without NaN") {
  // Straight through: no orbit.
  const Fillet s = compute_fillet(Vec3(0, 0, 0), Vec3(100, 0, 0), Vec3(200, 0.01, 0), 50.0);
  CHECK(s.kind == Fillet::Kind::straight);
  CHECK(s.c.allFinite());
  // 180 degrees doubling back.
  const Fillet b = compute_fillet(Vec3(0, 0, 0), Vec3(100, 0, 0), Vec3(0, 0, 0), 50.0);
  CHECK(b.kind == Fillet::Kind::too_sharp);
  CHECK(b.c.allFinite());
  CHECK(b.z1.allFinite());
  // A 150-degree turn on 100 m legs with R = 50: offset = 50 / tan(15 deg) = 186.6 m > 100 m.
  const double a = kPi - 5 * kPi / 6;  // leaving at 30 deg from the reverse direction
  const Fillet t = compute_fillet(Vec3(-100, 0, 0), Vec3(0, 0, 0), Vec3(-100 * std::cos(a), 100 * std::sin(a), 0), 50.0);
  CHECK(t.kind == Fillet::Kind::too_sharp);
  CHECK(t.offset == Approx(50.0 / std::tan(kPi / 12)));
  CHECK_THROWS_AS(compute_fillet(Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), 50.0), std::invalid_argument);
  CHECK_THROWS_AS(compute_fillet(Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(10, 10, 0), 0.0), std::invalid_argument);
}

TEST_CASE("Dubins: type, length and tangent points, hand-worked (Alg. 7)") {
  const double R = 50.0;
  SUBCASE("RSR: U-turn 400 m to the east") {
    // North at (0,0) to south at (0,400): quarter right, 300 m east, quarter right.
    const DubinsPath P = dubins_path(Vec3(0, 0, -50), 0.0, Vec3(0, 400, -50), kPi, R);
    CHECK(P.type == DubinsType::RSR);
    CHECK(P.length == Approx(300.0 + R * kPi));
    CHECK(P.lengths[3] == Approx(500.0 + 3 * R * kPi));  // LSL: three-quarter circles each end
    CHECK(P.lengths[1] == Approx(P.lengths[2]));         // RSL and LSR mirror each other here
    CHECK(P.lengths[1] == Approx(R * (kPi / 2 + std::asin(0.25)) + std::sqrt(150000.0) + R * (2 * kPi - (kPi / 2 - std::asin(0.25)))));
    check_vec(P.cs, Vec3(0, 50, -50));
    check_vec(P.ce, Vec3(0, 350, -50));
    check_vec(P.z1, Vec3(50, 50, -50));
    check_vec(P.z2, Vec3(50, 350, -50));
    check_vec(P.q1, Vec3(0, 1, 0));
    CHECK(P.lambda_s == 1);
    CHECK(P.lambda_e == 1);
    CHECK(P.arc_s == Approx(kPi / 2));
    CHECK(P.arc_e == Approx(kPi / 2));
  }
  SUBCASE("LSL: the mirror image") {
    const DubinsPath P = dubins_path(Vec3(0, 0, 0), 0.0, Vec3(0, -400, 0), kPi, R);
    CHECK(P.type == DubinsType::LSL);
    CHECK(P.length == Approx(300.0 + R * kPi));
    check_vec(P.z1, Vec3(50, -50, 0));
    CHECK(P.lambda_s == -1);
  }
  SUBCASE("RSL: north to north, 400 m to the east") {
    // cs = (0, 50), ce = (0, 350) (left of the end), l = 300: psi = pi/2 + asin(1/3),
    // L = 2 R psi + sqrt(300^2 - 100^2) = 473.907 m; z1 = cs + R (cos(asin(1/3)), 1/3).
    const DubinsPath P = dubins_path(Vec3(0, 0, 0), 0.0, Vec3(0, 400, 0), 0.0, R);
    CHECK(P.type == DubinsType::RSL);
    const double psi = kPi / 2 + std::asin(1.0 / 3.0);
    CHECK(P.length == Approx(2 * R * psi + std::sqrt(80000.0)));
    CHECK(P.length == Approx(473.907).epsilon(1e-5));
    CHECK(P.lengths[0] == Approx(400.0 + 2 * R * kPi));                                                   // RSR
    CHECK(P.lengths[3] == Approx(400.0 + 2 * R * kPi));                                                   // LSL
    CHECK(P.lengths[2] == Approx(2 * R * (2 * kPi - (kPi / 2 - std::asin(0.2))) + std::sqrt(240000.0)));  // LSR
    check_vec(P.z1, Vec3(50 * std::sqrt(8.0 / 9.0), 50 + 50.0 / 3.0, 0), 1e-9);
    check_vec(P.ce, Vec3(0, 350, 0));
    CHECK(P.lambda_s == 1);
    CHECK(P.lambda_e == -1);
  }
  SUBCASE("LSR: the mirror image of RSL") {
    const DubinsPath P = dubins_path(Vec3(0, 0, 0), 0.0, Vec3(0, -400, 0), 0.0, R);
    CHECK(P.type == DubinsType::LSR);
    CHECK(P.length == Approx(2 * R * (kPi / 2 + std::asin(1.0 / 3.0)) + std::sqrt(80000.0)));
  }
  SUBCASE("straight ahead: zero arcs, no spurious full circle") {
    const DubinsPath P = dubins_path(Vec3(0, 0, 0), 0.3, Vec3(300 * std::cos(0.3), 300 * std::sin(0.3), 0), 0.3, R);
    CHECK(P.length == Approx(300.0));
    CHECK(P.arc_s == Approx(0.0).scale(1.0));
    CHECK(P.arc_e == Approx(0.0).scale(1.0));
  }
}

TEST_CASE("Dubins: closer than 2R and coincident ends give finite, flyable paths") {
  const double R = 50.0;
  const DubinsPath P = dubins_path(Vec3(0, 0, 0), 0.0, Vec3(0, 30, 0), kPi, R);
  CHECK(P.close);
  CHECK(std::isinf(P.lengths[1]));  // RSL impossible: centres 30 m apart < 2R
  CHECK(std::isinf(P.lengths[2]));  // LSR impossible
  CHECK(std::isfinite(P.length));
  CHECK(P.z1.allFinite());
  CHECK(P.z2.allFinite());
  CHECK(P.q1.allFinite());
  // Same configuration: an empty path (no spurious circle); same point, new course: a loop.
  const DubinsPath Z = dubins_path(Vec3(10, 10, 0), 0.5, Vec3(10, 10, 0), 0.5, R);
  CHECK(Z.length == Approx(0.0).scale(1.0));
  CHECK(Z.q1.allFinite());
  const DubinsPath Q = dubins_path(Vec3(10, 10, 0), 0.0, Vec3(10, 10, 0), kPi / 2, R);
  CHECK(std::isfinite(Q.length));
  CHECK(Q.length > 2 * R);
  CHECK(Q.z1.allFinite());
  CHECK_THROWS_AS(dubins_path(Vec3(0, 0, 0), 0.0, Vec3(1, 0, 0), 0.0, -1.0), std::invalid_argument);
  CHECK_THROWS_AS(dubins_path(Vec3(0, 0, NAN), 0.0, Vec3(1, 0, 0), 0.0, 1.0), std::invalid_argument);
}

TEST_CASE("Dubins: every path is tangent-continuous and its length adds up (random configurations)") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(-500, 500), ang(-kPi, kPi), rad(10, 100);
  for (int k = 0; k < 500; ++k) {
    const Vec3 ps(pos(rng), pos(rng), -50), pe(pos(rng), pos(rng), -80);
    const double cs = ang(rng), ce = ang(rng), R = rad(rng);
    const DubinsPath P = dubins_path(ps, cs, pe, ce, R);
    REQUIRE(std::isfinite(P.length));
    for (double L : P.lengths) CHECK(P.length <= L);
    CHECK((P.z1 - P.cs).head<2>().norm() == Approx(R));
    CHECK((P.z2 - P.ce).head<2>().norm() == Approx(R));
    CHECK((circle_direction(ps, P.cs, P.lambda_s) - course_vector(cs)).norm() < 1e-9);
    CHECK((circle_direction(pe, P.ce, P.lambda_e) - course_vector(ce)).norm() < 1e-9);
    CHECK((circle_direction(P.z1, P.cs, P.lambda_s) - P.q1).norm() < 1e-6);
    CHECK((circle_direction(P.z2, P.ce, P.lambda_e) - P.q1).norm() < 1e-6);
    const Vec3 s = (P.z2 - P.z1);
    CHECK(s.head<2>().dot(P.q1.head<2>()) >= -1e-6);  // the straight runs forwards
    CHECK(std::fabs(s.x() * P.q1.y() - s.y() * P.q1.x()) < 1e-6);
    CHECK(P.length == Approx(R * P.arc_s + s.head<2>().norm() + R * P.arc_e));
  }
}

TEST_CASE("follower, line: course and altitude commands (eq. 10.5, 10.8)") {
  PathSegment line;
  line.type = PathSegment::Type::line;
  line.Va_d = 17;
  line.r = Vec3(0, 0, -100);
  line.q = Vec3(1, 0, 0);
  FollowerGains g;  // ROSplane's Anaconda values
  FollowerInput in;
  in.chi = 0.0;
  in.p = Vec3(50, 0, -100);
  FollowerCommand c = follow(line, in, g);
  CHECK(c.chi_c == Approx(0.0).scale(1.0));
  CHECK(c.h_c == Approx(100.0));
  CHECK(c.Va_c == 17.0);
  CHECK(c.phi_ff == 0.0);
  // 100 m right (east) of a northbound line: turn left towards it,
  // chi_c = -chi_inf 2/pi atan(k_path 100).
  in.p = Vec3(0, 100, -100);
  c = follow(line, in, g);
  CHECK(cross_track_error(line.r, line.q, in.p) == Approx(100.0));
  CHECK(c.chi_c == Approx(-1.2 * 2 / kPi * std::atan(0.0175 * 100)));
  // Far away the approach angle tends to chi_inf.
  in.p = Vec3(0, -1e6, -100);
  CHECK(follow(line, in, g).chi_c == Approx(1.2).epsilon(1e-4));
  // Climbing line: 10 m up per 100 m along it.
  line.q = Vec3(100, 0, -10).normalized();
  in.p = Vec3(50, 20, -100);
  CHECK(follow(line, in, g).h_c == Approx(105.0));
  // Course unwrapped near chi: flying at chi = 3 rad a line of course -3 rad needs a small turn.
  line.q = course_vector(-3.0);
  in.p = line.r;
  in.chi = 3.0;
  CHECK(follow(line, in, g).chi_c == Approx(-3.0 + 2 * kPi));
  // No horizontal direction: hold the course, no NaN.
  line.q = Vec3(0, 0, 1);
  c = follow(line, in, g);
  CHECK(c.chi_c == Approx(3.0));
  CHECK(std::isfinite(c.h_c));
}

TEST_CASE("follower, orbit: course, altitude, direction and roll feed-forward (eq. 10.13)") {
  PathSegment orbit;
  orbit.type = PathSegment::Type::orbit;
  orbit.Va_d = 17;
  orbit.c = Vec3(0, 0, -60);
  orbit.rho = 50;
  orbit.lambda = 1;
  FollowerGains g;
  FollowerInput in;
  in.Va = 17;
  in.Vg = 17;
  in.p = Vec3(50, 0, -60);  // north of the centre, clockwise: fly east
  in.chi = kPi / 2;
  in.psi = kPi / 2;
  FollowerCommand c = follow(orbit, in, g);
  CHECK(c.chi_c == Approx(kPi / 2));
  CHECK(c.h_c == Approx(60.0));
  CHECK(c.phi_ff == Approx(std::atan(17.0 * 17.0 / (9.81 * 50))));
  // With wind: ground speed and crab angle enter (phi_ff = atan(Vg^2 / (g rho cos(chi - psi)))).
  in.Vg = 20;
  in.psi = kPi / 2 - 0.3;
  CHECK(follow(orbit, in, g).phi_ff == Approx(std::atan(400.0 / (9.81 * 50 * std::cos(0.3)))));
  in.psi = kPi / 2 - 1.4;  // an implausible crab angle is limited (cos >= 0.5)
  CHECK(follow(orbit, in, g).phi_ff == Approx(std::atan(400.0 / (9.81 * 50 * 0.5))));
  in.Vg = 0;  // ground speed unknown: airspeed
  in.psi = kPi / 2;
  CHECK(follow(orbit, in, g).phi_ff == Approx(std::atan(17.0 * 17.0 / (9.81 * 50))));
  in.Vg = 17;
  orbit.lambda = -1;  // counter-clockwise: fly west, roll left
  in.chi = -kPi / 2;
  in.psi = -kPi / 2;
  c = follow(orbit, in, g);
  CHECK(c.chi_c == Approx(-kPi / 2));
  CHECK(c.phi_ff == Approx(-std::atan(17.0 * 17.0 / (9.81 * 50))));
  // Far outside: head for the centre; no feed-forward.
  in.p = Vec3(5000, 0, -60);
  in.chi = 0;
  c = follow(orbit, in, g);
  // Counter-clockwise, north of the centre (varphi = 0): chi_c = -(pi/2 + atan(0.5 * 99)) = -pi + 0.0202.
  CHECK(tern::wrap_pi(c.chi_c - kPi) == Approx(0.0202).epsilon(1e-2));
  CHECK(c.phi_ff == 0.0);
  // At the centre: finite.
  in.p = orbit.c;
  c = follow(orbit, in, g);
  CHECK(std::isfinite(c.chi_c));
}

TEST_CASE("follower: from 100 m cross-track the kinematic aircraft converges without crossing the line by 5 m") {
  PathSegment line;
  line.type = PathSegment::Type::line;
  line.Va_d = 17;
  line.r = Vec3(0, 0, -70);
  line.q = Vec3(1, 0, 0);
  const FollowerGains g;
  for (double side : {100.0, -100.0}) {
    for (double heading : {0.0, -side / 100.0 * kPi / 2, kPi}) {  // along, straight at the line, reversed
      CAPTURE(side);
      CAPTURE(heading);
      testkit::KinematicAircraft a;
      a.e = side;
      a.h = 70;
      a.set_course(heading);
      double worst_overshoot = 0.0, last = 0.0;
      const double dt = 0.01;
      FollowerCommand c;
      for (int k = 0; k < 20000; ++k) {  // 200 s; follower at 10 Hz as ROSplane's
        if (k % 10 == 0) {
          FollowerInput in;
          in.p = a.p();
          in.chi = a.chi;
          in.psi = a.chi;
          in.Va = in.Vg = a.Va;
          c = follow(line, in, g);
          REQUIRE(std::isfinite(c.chi_c));
        }
        a.step(c.chi_c, c.phi_ff, c.h_c, c.Va_c, dt);
        last = cross_track_error(line.r, line.q, a.p());
        worst_overshoot = std::max(worst_overshoot, -last * (side > 0 ? 1.0 : -1.0));
      }
      CHECK(worst_overshoot < 5.0);
      CHECK(std::fabs(last) < 1.0);
    }
  }
}

TEST_CASE("wind_turn_radius: the radius at which a ground circle needs at most the given bank") {
  const double g = 9.81, phi = 30.0 * kPi / 180.0, Va = 17.0;
  // no wind: Va^2 / (g tan phi) for any turn
  const double R0 = Va * Va / (g * std::tan(phi));
  CHECK(wind_turn_radius(Va, Vec3::Zero(), 0.3, 1.0, phi) == Approx(R0));
  CHECK(wind_turn_radius(Va, Vec3::Zero(), 0.3, -2.0 * kPi, phi) == Approx(R0));
  // 5 m/s blowing to the north-west (course -45 deg): a full circle is limited downwind, where
  // the crab angle is 0 and Vg = Va + 5
  const Vec3 w(3.5355339, -3.5355339, 0.0);
  const double R_down = 22.0 * 22.0 / (g * std::tan(phi));
  CHECK(wind_turn_radius(Va, w, 0.0, 2.0 * kPi, phi) == Approx(R_down).epsilon(1e-3));
  // the hourglass's right turn from due west (-90 deg) to 14 deg sweeps through -45 deg ...
  CHECK(wind_turn_radius(Va, w, -kPi / 2, 104.0 * kPi / 180.0, phi) == Approx(R_down).epsilon(1e-3));
  // ... its left turn from due west to 166 deg (through south) does not: the largest ground
  // speed is at the start, 5 cos 45 + sqrt(17^2 - (5 sin 45)^2), with that crab angle
  const double Vg = 5.0 * std::cos(kPi / 4) + std::sqrt(Va * Va - 12.5);
  const double cos_crab = std::sqrt(1.0 - 12.5 / (Va * Va));
  CHECK(wind_turn_radius(Va, w, -kPi / 2, -104.0 * kPi / 180.0, phi) == Approx(Vg * Vg / (g * std::tan(phi) * cos_crab)).epsilon(1e-9));
  // the bank a circle of that radius asks for is the follower's feed-forward: never above phi
  const double R = wind_turn_radius(Va, w, 0.0, 2.0 * kPi, phi);
  for (int i = 0; i < 360; ++i) {
    const double chi = i * kPi / 180.0;
    const double w_cross = -w.x() * std::sin(chi) + w.y() * std::cos(chi);
    const double c = std::sqrt(1.0 - w_cross * w_cross / (Va * Va));
    const double v = w.x() * std::cos(chi) + w.y() * std::sin(chi) + Va * c;
    CHECK(std::atan(v * v / (g * R * c)) <= phi + 1e-9);
  }
  // bad input: 0 (the manager then keeps R_min)
  CHECK(wind_turn_radius(0.0, w, 0.0, 1.0, phi) == 0.0);
  CHECK(wind_turn_radius(Va, w, 0.0, 1.0, 0.0) == 0.0);
  CHECK(wind_turn_radius(Va, Vec3(std::nan(""), 0, 0), 0.0, 1.0, phi) == 0.0);
}
