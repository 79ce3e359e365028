// tern/path/follower.hpp: vector-field path following, Beard & McLain, *Small Unmanned
// Aircraft*, ch. 10 (straight lines: section 10.2, Alg. 3; orbits: section 10.3, Alg. 4).
// Plain C++ and Eigen, no host types.
#pragma once

#include <Eigen/Core>

#include "tern/path/geometry.hpp"
#include "tern/math.hpp"

namespace tern::path {

/// A path segment as the path manager hands it to the follower (ROSplane's CurrentPath).
struct PathSegment {
  enum class Type { orbit = 0, line = 1 };
  Type type = Type::orbit;
  double Va_d = 0.0;        ///< desired airspeed, m/s
  Vec3 r = Vec3::Zero();    ///< line: a point on the line, m NED
  Vec3 q = Vec3::UnitX();   ///< line: unit direction (its d component sets the climb), NED
  Vec3 c = Vec3::Zero();    ///< orbit: centre (its d sets the altitude), m NED
  double rho = 0.0;         ///< orbit: radius, m (> 0)
  int lambda = 1;           ///< orbit: 1 clockwise, -1 counter-clockwise (seen from above)
  int waypoint_index = -1;  ///< waypoint being flown to (index in the waypoint list), -1: none
  /// A land item's glide path (landing.hpp): r is the touchdown point; the altitude command
  /// stops at r's altitude beyond it.
  bool landing = false;
  double flare_height = 0.0;     ///< landing: m above r
  double decision_height = 0.0;  ///< landing: m above r
  int attempt = 0;               ///< landing: approaches flown, this one included
};

/// Gains of the vector fields. Defaults: ROSplane's Anaconda values
/// (rosplane/params/anaconda_autopilot_params.yaml, path_follower).
struct FollowerGains {
  double chi_inf = 1.2;       ///< course of approach from far away, rad, (0, pi/2]  (book: chi^inf)
  double k_path = 0.0175;     ///< line field transition gain, 1/m, > 0
  double k_orbit = 0.5;       ///< orbit field transition gain, dimensionless, > 0
  double gravity = kGravity;  ///< m/s^2, for the roll feed-forward
};

/// What the aircraft state the follower needs.
struct FollowerInput {
  Vec3 p = Vec3::Zero();  ///< position NED, m
  double chi = 0.0;       ///< course over ground, rad
  double psi = 0.0;       ///< heading, rad (for the wind-corrected feed-forward)
  double Va = 0.0;        ///< airspeed, m/s
  double Vg = 0.0;        ///< ground speed, m/s (0: unknown, Va is used)
};

/// What the follower commands (ROSplane's ControllerCommands).
struct FollowerCommand {
  double Va_c = 0.0;     ///< commanded airspeed, m/s (= the segment's Va_d)
  double h_c = 0.0;      ///< commanded altitude (-d), m
  double chi_c = 0.0;    ///< commanded course, rad, within pi of the input chi (not wrapped)
  double phi_ff = 0.0;   ///< roll feed-forward, rad (orbits only; 0 on lines)
  bool landing = false;  ///< on a land item's glide path (h_td valid)
  double h_td = 0.0;     ///< landing: the touchdown point's altitude (-r_d), m
};

/// Line: chi_c = chi_q - chi_inf (2/pi) atan(k_path e_py) (eq. 10.8), with chi_q the course of
/// q unwrapped near chi, e_py the cross-track error (eq. 10.2) positive right of the line; the
/// altitude command follows the line (eq. 10.5): h_c = -r_d - |s_ne| q_d / |q_ne|; on a landing
/// glide path no lower than the touchdown point's -r_d.
/// Orbit: chi_c = varphi + lambda (pi/2 + atan(k_orbit (d - rho) / rho)) (eq. 10.13),
/// h_c = -c_d, and near the orbit (|d - rho| < rho / 2) the coordinated-turn roll feed-forward
/// phi_ff = lambda atan(Vg^2 / (g rho cos(chi - psi))) (section 10.3, with cos(chi - psi)
/// limited to >= 0.5 so a large crab angle cannot ask for 90 degrees of roll).
/// Never returns NaN for finite inputs; a line with no horizontal direction holds the course.
FollowerCommand follow(const PathSegment& path, const FollowerInput& in, const FollowerGains& gains);

/// Signed cross-track error of p from the line (r, q), m, positive right of the direction of
/// travel (eq. 10.2's e_py).
double cross_track_error(const Vec3& r, const Vec3& q, const Vec3& p);

}  // namespace tern::path
