// tern/path/geometry.hpp: path geometry of Beard & McLain, *Small Unmanned Aircraft*, ch. 11
// (half-plane switching, fillets, Dubins paths). Plain C++ and Eigen, no host types.
//
// Frames and units: positions are NED in metres (n, e, d), courses chi in radians measured
// from north towards east (the book's chi). Turn direction lambda: +1 clockwise seen from
// above (a right turn), -1 counter-clockwise (a left turn), as in ROSplane's CurrentPath.
//
// All switching tests use the horizontal (n, e) components only: a fixed wing that is 20 m
// below its planned altitude still switches where the plan says. The book states the same
// tests in 3-D; with level legs both are identical.
#pragma once

#include <array>
#include <cmath>
#include <string_view>

#include <Eigen/Core>
#include "tern/math.hpp"

namespace tern::path {

using Vec3 = Eigen::Vector3d;

/// Horizontal unit vector of course chi: (cos chi, sin chi, 0).
inline Vec3 course_vector(double chi) { return {std::cos(chi), std::sin(chi), 0.0}; }

/// Horizontal distance between a and b, m.
inline double horizontal_distance(const Vec3& a, const Vec3& b) { return (a - b).head<2>().norm(); }

/// True when p lies in the closed half-plane H(z, n) = {p : (p - z)^T n >= 0} (Beard & McLain,
/// section 11.1), using the (n, e) components of p, z and n only.
bool in_half_plane(const Vec3& p, const Vec3& z, const Vec3& n);

/// Normal of the switching half-plane at w_i between the legs q_in (w_{i-1} -> w_i) and q_out
/// (w_i -> w_{i+1}), both horizontal unit vectors: n_i = (q_in + q_out) / |q_in + q_out|
/// (Beard & McLain, Alg. 5). When the legs double back (|q_in + q_out| ~ 0) the normal is q_in:
/// the aircraft switches when it passes w_i.
Vec3 line_switch_normal(const Vec3& q_in, const Vec3& q_out);

/// A fillet (Beard & McLain, section 11.2.1, Alg. 6) rounding the corner at w between the legs
/// w_prev -> w and w -> w_next with an orbit of radius R.
struct Fillet {
  enum class Kind {
    fillet,     ///< a proper fillet: line to z1, orbit (c, R, lambda) to z2, line on
    straight,   ///< legs (nearly) aligned, turn < kStraightTurn: switch at w like a line
    too_sharp,  ///< the corner (up to a 180-degree doubling back) needs more room than the legs
                ///< give: offset > shorter leg. Fallback: fly over w, then turn (line switching)
  };
  Kind kind = Kind::straight;
  Vec3 q_in = Vec3::UnitX();   ///< horizontal unit direction of the incoming leg
  Vec3 q_out = Vec3::UnitX();  ///< horizontal unit direction of the outgoing leg
  double varrho = 0.0;         ///< the book's varrho = acos(-q_in^T q_out), rad (pi: straight)
  double offset = 0.0;         ///< R / tan(varrho / 2): distance from w to z1 and to z2, m
  Vec3 z1 = Vec3::Zero();      ///< tangent point on the incoming leg (d of w), m NED
  Vec3 z2 = Vec3::Zero();      ///< tangent point on the outgoing leg (d of w), m NED
  Vec3 c = Vec3::Zero();       ///< orbit centre, c = w - R / sin(varrho / 2) n (d of w), m NED
  int lambda = 1;              ///< orbit direction: sign(q_in,n q_out,e - q_in,e q_out,n)
};

/// Turns smaller than this (rad) are flown as straight lines (the fillet would be empty and its
/// centre ill-defined).
inline constexpr double kStraightTurn = 1e-3;

/// Computes the fillet at w. Legs must be horizontally longer than 0 (the path manager removes
/// repeated waypoints first); throws std::invalid_argument otherwise or when R <= 0 or any
/// input is not finite.
Fillet compute_fillet(const Vec3& w_prev, const Vec3& w, const Vec3& w_next, double R);

/// Radius of a turn flown at airspeed Va (m/s) in the steady horizontal wind `wind` (NED m/s,
/// the direction the air moves to; its d component is ignored) such that the ground track is a
/// circle and the bank angle never exceeds phi (rad, in (0, pi/2)): the maximum over the swept
/// courses chi of Vg(chi)^2 / (g tan(phi) cos(chi - psi)), the bank a circle of that radius
/// asks for (Beard & McLain, section 10.3: phi_ff = atan(Vg^2 / (g R cos(chi - psi)))), with
/// Vg(chi) and the crab angle chi - psi of the wind triangle (section 2.3). The turn starts at
/// course chi0 (rad) and sweeps `sweep` rad (> 0 clockwise, < 0 counter-clockwise; |sweep| >=
/// 2 pi: every course). The ground speed is highest downwind, so a turn through the downwind
/// course needs (Va + |w|)^2 / (g tan(phi)). Courses the wind makes unflyable (cross wind >= Va)
/// count with a crab angle of asin(0.99). Evaluated every 2 degrees or finer and at the downwind
/// course when the turn sweeps it. Returns 0 for Va <= 0 or non-finite input.
double wind_turn_radius(double Va, const Vec3& wind, double chi0, double sweep, double phi, double g = kGravity);

/// The four Dubins path types of Beard & McLain, section 11.2.2 (R: right turn, S: straight,
/// L: left turn).
enum class DubinsType { RSR = 0, RSL = 1, LSR = 2, LSL = 3 };
std::string_view dubins_type_name(DubinsType t);

/// A Dubins path from the configuration (ps, chi_s) to (pe, chi_e) with turn radius R
/// (Beard & McLain, Alg. 7): orbit (cs, lambda_s) from ps to z1, line from z1 along q1 to z2,
/// orbit (ce, lambda_e) from z2 to z3 = pe, where the course is q3.
struct DubinsPath {
  DubinsType type = DubinsType::RSR;
  double R = 0.0;                   ///< turn radius, m
  double length = 0.0;              ///< horizontal length of the path, m
  std::array<double, 4> lengths{};  ///< length of each type (RSR, RSL, LSR, LSL); +inf if impossible
  Vec3 ps = Vec3::Zero(), pe = Vec3::Zero();
  double chi_s = 0.0, chi_e = 0.0;
  Vec3 cs = Vec3::Zero();   ///< start circle centre (d of ps)
  int lambda_s = 1;         ///< start circle direction
  Vec3 ce = Vec3::Zero();   ///< end circle centre (d of pe)
  int lambda_e = 1;         ///< end circle direction
  Vec3 z1 = Vec3::Zero();   ///< leaves the start circle (d of ps)
  Vec3 q1 = Vec3::UnitX();  ///< horizontal unit direction of the straight segment
  Vec3 z2 = Vec3::Zero();   ///< joins the end circle (d of pe)
  Vec3 z3 = Vec3::Zero();   ///< = pe
  Vec3 q3 = Vec3::UnitX();  ///< course vector at pe
  double arc_s = 0.0;       ///< angle turned on the start circle (ps -> z1), rad, [0, 2 pi)
  double arc_e = 0.0;       ///< angle turned on the end circle (z2 -> pe), rad, [0, 2 pi)
  bool close = false;       ///< |ps - pe| < 2 R (horizontal): the book asks for >= 3 R; RSL and
                            ///< LSR may be impossible, RSR and LSL always exist
};

/// Angles within 1e-9 rad of a full turn count as no turn: roundoff must not add a circle.
/// Shortest of RSR, RSL, LSR, LSL from (ps, chi_s) to (pe, chi_e) with radius R (Beard & McLain,
/// Alg. 7; ties go to the earlier type in that order). Works for any distance, including
/// ps == pe (a full circle or an arc on one circle). Throws std::invalid_argument when R <= 0
/// or an input is not finite.
DubinsPath dubins_path(const Vec3& ps, double chi_s, const Vec3& pe, double chi_e, double R);

}  // namespace tern::path
