// tern/coordination/path_estimate.hpp: how far and how long a fixed-wing aircraft has to fly to a
// point, for coordination plans. Plain C++ (Eigen), no host types.
//
// Frame and units: horizontal positions are (north, east) in m in one local NED frame common to
// every vehicle (the coordination plugin converts each vehicle's estimate into it); courses are
// rad from north, clockwise; speeds m/s; wind is the NED horizontal wind (the direction the air
// moves to), m/s.
//
// Sources: Beard & McLain, *Small Unmanned Aircraft* (uavbook):
//   * turn_then_line_length: the last two pieces of a Dubins path (sec. 11.2.3): a turn of radius
//     R from the current course, then the straight tangent line to the point (the "CS" path; no
//     final course is imposed). It is the path the vector-field follower flies to a straight-line
//     leg that starts at the aircraft (sec. 10.2), to within the follower's convergence.
//   * ground_speed / airspeed_for: the wind triangle (sec. 2.3): ground velocity = air velocity +
//     wind, with the ground track along q.
// Errors: none thrown; non-finite inputs give non-finite results (callers validate the estimate).
#pragma once

#include <Eigen/Core>

namespace tern::coord {

using Vec2 = Eigen::Vector2d;

/// Length (m) of the shorter of the two turn-then-straight paths (right turn, left turn, both of
/// radius R > 0) from position p with course chi (rad) to target: R * (arc turned) + tangent
/// length. A target inside one turn circle takes the other turn (the two circles touch at p, so
/// one of them always works); a target at p gives 0.
double turn_then_line_length(const Vec2& p, double chi, const Vec2& target, double R);

/// Ground speed (m/s) along the unit direction q for airspeed Va in wind w (uavbook sec. 2.3):
/// Vg = w.q + sqrt(Va^2 - |w|^2 + (w.q)^2). At least `floor` (m/s, > 0): a wind the aircraft
/// cannot fly against gives the floor, so that times stay finite.
double ground_speed(double Va, const Vec2& w, const Vec2& q, double floor = 1.0);

/// Airspeed (m/s) that gives ground speed Vg >= 0 along the unit direction q in wind w:
/// |Vg q - w| (the air velocity is the ground velocity less the wind).
double airspeed_for(double Vg, const Vec2& w, const Vec2& q);

/// Unit direction from p to target, or (cos chi, sin chi) when they coincide.
Vec2 direction_to(const Vec2& p, const Vec2& target, double chi);

}  // namespace tern::coord
